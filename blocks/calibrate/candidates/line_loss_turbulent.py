"""Turbulent line loss in series at a port: dp = k*q*|q| (pipe friction, fittings, a flow meter)."""

from blocks.calibrate.candidates.base import Candidate, Place, register, safe, series_ports, start_pressure

V_NODE = 1e-6
"""Oil volume [m^3] of the node between the inserted loss and the port (1 ml: far below the nets')."""


def insert_loss(doc, place, coefficient: str) -> None:
    """Insert a line_loss block at place.target['port'] with ``coefficient`` (k or R) = the parameter."""
    port = place.target["port"]
    comp = doc.unique(f"cal_loss_{safe(port)}")
    node = doc.unique(f"cal_n_{safe(port)}")
    doc.add_component(comp, "line_loss", {coefficient: place.param})
    doc.move_port(port, node, f"{comp}.a", f"{comp}.b", volume=V_NODE, initial=place.target.get("initial"))


@register
class LineLossTurbulent(Candidate):
    name = "line_loss_turbulent"
    title = "turbulent line loss"
    description = ("a pressure drop k*q*|q| in series at a port (line_loss block, a 1 ml node between it and "
                   "the port); zero k is the declared connection")

    def places(self, ctx):
        out = []
        for net, port, logged in series_ports(ctx):
            k_plaus = 50e5 / ctx.q_ref ** 2
            out.append(Place(self.name, f"{self.name}@{port}", f"net {net}, in series at {port}",
                             f"cal_kt_{safe(port)}", "Pa*s^2/m^6", 0.0, 0.0, 1e20,
                             0.1 * ctx.p_ref / ctx.q_ref ** 2, (0.0, k_plaus), target={"net": net, "port": port, "initial": start_pressure(ctx, net)},
                             meaning=f"dp = k*q|q|; at the reference flow {ctx.q_ref * 60000:.4g} l/min: k*q_ref^2",
                             plot_against=ctx.first_input_of_unit("m^3/s")))
        return out

    def patch(self, doc, place):
        insert_loss(doc, place, "k")
