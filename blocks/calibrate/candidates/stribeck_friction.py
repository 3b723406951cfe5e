"""Stribeck friction on a moving body: a breakaway excess dTs*exp(-(w/w_s)^2)*sign(w) near standstill
(stribeck_friction on a shaft; trans_stribeck_friction, dFs*exp(-(v/v_s)^2)*sign(v), on a translating body
such as a cylinder's rod, where seal friction is the usual stick-slip)."""

from blocks.block import PortKind
from blocks.calibrate.candidates.base import Candidate, Place, mechanical_nets, register, safe

W_W = 0.01
"""Speed width [rad/s] of the tanh smoothing of sign(w) in the inserted stribeck_friction."""
V_W = 1e-4
"""Velocity width [m/s] of the tanh smoothing of sign(v) in the inserted trans_stribeck_friction."""


def stribeck_speed(ctx) -> float:
    """w_s: 5 % of the largest measured speed (1 rad/s without a measured speed)."""
    return max(0.05 * ctx.w_ref, 1e-3) if ctx.w_ref > 0 else 1.0


def stribeck_velocity(ctx) -> float:
    """v_s: 5 % of the largest measured velocity (of 0.1 m/s without one: 5 mm/s)."""
    return max(0.05 * ctx.v_ref, 1e-5)


@register
class StribeckFriction(Candidate):
    name = "stribeck_friction"
    title = "Stribeck friction"
    description = ("a breakaway torque (force) excess dTs*exp(-(w/w_s)^2)*sign(w) that decays over the Stribeck "
                   "speed w_s = 5 % of the largest measured speed (or velocity; stribeck_friction, "
                   "trans_stribeck_friction); zero dTs: none")

    def places(self, ctx):
        out = []
        for net, kind in mechanical_nets(ctx):
            if kind is PortKind.ROTATIONAL:
                ws = stribeck_speed(ctx)
                out.append(Place(self.name, f"{self.name}@{net}", f"on {net}", f"cal_dTs_{safe(net)}", "N*m",
                                 0.0, 0.0, 1e9, 0.1, (0.0, 1e4), target={"net": net, "w_s": ws, "rot": True},
                                 meaning=f"breakaway excess torque, Stribeck speed w_s = {ws:.3g} rad/s",
                                 plot_against=ctx.first_input_of_unit("rad/s")))
            else:
                vs = stribeck_velocity(ctx)
                out.append(Place(self.name, f"{self.name}@{net}", f"on {net}", f"cal_dFs_{safe(net)}", "N",
                                 0.0, 0.0, 1e9, 10.0, (0.0, 1e6), target={"net": net, "v_s": vs, "rot": False},
                                 meaning=f"breakaway excess force, Stribeck velocity v_s = {vs * 1e3:.3g} mm/s",
                                 plot_against=ctx.first_input_of_unit("m/s")))
        return out

    def patch(self, doc, place):
        net = place.target["net"]
        comp = doc.unique(f"cal_stribeck_{safe(net)}")
        if place.target["rot"]:
            doc.add_component(comp, "stribeck_friction", {"Tc": 0.0, "dTs": place.param, "w_s": place.target["w_s"],
                                                          "b": 0.0, "w_w": W_W})
        else:
            doc.add_component(comp, "trans_stribeck_friction", {"Fc": 0.0, "dFs": place.param,
                                                                "v_s": place.target["v_s"], "b": 0.0, "v_w": V_W})
        doc.set_net_ports(net, doc.net_ports(net) + [f"{comp}.port"])
