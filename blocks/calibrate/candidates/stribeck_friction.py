"""Stribeck friction on a rotating body: a breakaway excess dTs*exp(-(w/w_s)^2)*sign(w) near standstill."""

from blocks.block import PortKind
from blocks.calibrate.candidates.base import Candidate, Place, mechanical_nets, register, safe

W_W = 0.01
"""Speed width [rad/s] of the tanh smoothing of sign(w) in the inserted stribeck_friction."""


def stribeck_speed(ctx) -> float:
    """w_s: 5 % of the largest measured speed (1 rad/s without a measured speed)."""
    return max(0.05 * ctx.w_ref, 1e-3) if ctx.w_ref > 0 else 1.0


@register
class StribeckFriction(Candidate):
    name = "stribeck_friction"
    title = "Stribeck friction"
    description = ("a breakaway torque excess dTs*exp(-(w/w_s)^2)*sign(w) that decays over the Stribeck speed "
                   "w_s = 5 % of the largest measured speed (stribeck_friction block, rotational only); zero dTs: none")

    def places(self, ctx):
        out = []
        ws = stribeck_speed(ctx)
        for net, kind in mechanical_nets(ctx, kinds=(PortKind.ROTATIONAL,)):
            out.append(Place(self.name, f"{self.name}@{net}", f"on {net}", f"cal_dTs_{safe(net)}", "N*m",
                             0.0, 0.0, 1e9, 0.1, (0.0, 1e4), target={"net": net, "w_s": ws},
                             meaning=f"breakaway excess torque, Stribeck speed w_s = {ws:.3g} rad/s",
                             plot_against=ctx.first_input_of_unit("rad/s")))
        return out

    def patch(self, doc, place):
        net = place.target["net"]
        comp = doc.unique(f"cal_stribeck_{safe(net)}")
        doc.add_component(comp, "stribeck_friction", {"Tc": 0.0, "dTs": place.param, "w_s": place.target["w_s"],
                                                      "b": 0.0, "w_w": W_W})
        doc.set_net_ports(net, doc.net_ports(net) + [f"{comp}.port"])
