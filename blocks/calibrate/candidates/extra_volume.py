"""Extra oil volume (compliance) on a net: hoses, accumulators, trapped air (a volume block)."""

from blocks.calibrate.candidates.base import Candidate, Place, register, safe
from blocks.block import PortKind

V_ZERO = 1e-12
"""The volume block's lower bound [m^3]: the candidate's zero (1e-12 m^3 beside litres is nothing)."""


@register
class ExtraVolume(Candidate):
    name = "extra_volume"
    title = "extra volume"
    description = "an added oil volume on a net with a pressure state (volume block); zero: 1e-12 m^3"

    def places(self, ctx):
        out = []
        for net in ctx.doc.section("nets"):
            if ctx.net_kind(net) is not PortKind.HYDRAULIC or not ctx.has_state(net) or net.startswith("cal_"):
                continue
            v_net = ctx.values.get(f"{net}.volume", 1e-4)
            v_net = v_net if isinstance(v_net, float) and v_net > 0 else 1e-4
            out.append(Place(self.name, f"{self.name}@{net}", f"on net {net}", f"cal_V_{safe(net)}", "m^3",
                             V_ZERO, V_ZERO, 10.0, 0.01 * v_net, (V_ZERO, 10.0 * v_net + 1e-3),
                             target={"net": net}, meaning=f"added oil volume (the net has {v_net * 1e3:.3g} l)",
                             plot_against="t"))
        return out

    def patch(self, doc, place):
        net = place.target["net"]
        comp = doc.unique(f"cal_volume_{safe(net)}")
        doc.add_component(comp, "volume", {"V": place.param})
        doc.set_net_ports(net, doc.net_ports(net) + [f"{comp}.port"])
