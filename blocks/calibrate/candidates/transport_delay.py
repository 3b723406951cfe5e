"""Transport delay on a signal net, between its driver and its inputs (a pade_delay block)."""

from blocks.block import PortKind
from blocks.calibrate.candidates.base import Candidate, Place, register, safe


@register
class TransportDelay(Candidate):
    name = "transport_delay"
    title = "transport delay"
    description = ("a delay of T between a signal's driver and its inputs (2nd-order Pade approximation, "
                   "pade_delay block, pass-through below 10 us); zero T: none")

    def places(self, ctx):
        out = []
        comps = ctx.top_components()
        for net in ctx.doc.section("nets"):
            if ctx.net_kind(net) is not PortKind.SIGNAL or net.startswith("cal_"):
                continue
            ports = ctx.doc.net_ports(net)
            driver = None
            for port in ports:
                comp, _, pname = port.partition(".")
                if comp in comps and any(p.name == pname and p.direction == "out" for p in comps[comp].cls.ports):
                    driver = port
            if driver is None or len(ports) < 2:
                continue
            out.append(Place(self.name, f"{self.name}@{net}", f"signal {net}, after {driver}", f"cal_T_{safe(net)}",
                             "s", 0.0, 0.0, 1.0, 1e-3, (0.0, min(0.5, 0.1 * ctx.t_span)),
                             target={"net": net, "driver": driver}, meaning="delay time", plot_against="t"))
        return out

    def patch(self, doc, place):
        net, driver = place.target["net"], place.target["driver"]
        comp = doc.unique(f"cal_delay_{safe(net)}")
        node = doc.unique(f"cal_n_{safe(net)}")
        doc.add_component(comp, "pade_delay", {"T": place.param})
        readers = [p for p in doc.net_ports(net) if p != driver]
        doc.set_net_ports(net, [driver, f"{comp}.u"])
        doc.section("nets")[node] = [f"{comp}.y"] + readers
