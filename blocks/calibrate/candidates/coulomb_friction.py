"""Coulomb friction on a moving body: tau = -Tc*tanh(w/w_w) (rot_friction) or f = -Fc*tanh(v/v_w)."""

from blocks.block import PortKind
from blocks.calibrate.candidates.base import Candidate, Place, mechanical_nets, register, safe

W_W = 0.1
"""Speed width [rad/s] of the tanh smoothing of sign(w) in the inserted rot_friction."""
V_W = 1e-3
"""Velocity width [m/s] of the tanh smoothing of sign(v) in the inserted trans_friction."""


@register
class CoulombFriction(Candidate):
    name = "coulomb_friction"
    title = "Coulomb friction"
    description = "a friction torque (force) Tc*sign(w) opposing the motion of a body; zero Tc: none"

    def places(self, ctx):
        out = []
        for net, kind in mechanical_nets(ctx):
            rot = kind is PortKind.ROTATIONAL
            out.append(Place(self.name, f"{self.name}@{net}", f"on {net}", f"cal_Tc_{safe(net)}",
                             "N*m" if rot else "N", 0.0, 0.0, 1e9, 0.1 if rot else 10.0,
                             (0.0, 1e4 if rot else 1e6), target={"net": net, "rot": rot},
                             meaning="friction opposing the motion, smoothed over "
                             + (f"w_w = {W_W:g} rad/s" if rot else f"v_w = {V_W * 1e3:g} mm/s"),
                             plot_against=ctx.first_input_of_unit("rad/s" if rot else "m/s")))
        return out

    def patch(self, doc, place):
        net = place.target["net"]
        comp = doc.unique(f"cal_coulomb_{safe(net)}")
        if place.target["rot"]:
            doc.add_component(comp, "rot_friction", {"Tc": place.param, "b": 0.0, "w_w": W_W})
        else:
            doc.add_component(comp, "trans_friction", {"Fc": place.param, "b": 0.0, "v_w": V_W})
        doc.set_net_ports(net, doc.net_ports(net) + [f"{comp}.port"])
