"""Viscous friction on a moving body: tau = -b*w (rot_damper) or f = -b*v (trans_damper).

Plausible: a friction at the reference speed of at most what a Coulomb friction may be (coulomb_friction's
range): b*w_ref <= 1e4 N*m on a shaft, b*v_ref <= 1e6 N on a translating body (w_ref, v_ref: the largest
measured speed or velocity, else 10 rad/s and 0.1 m/s; blocks.calibrate.candidates.base.Context)."""

from blocks.block import PortKind
from blocks.calibrate.candidates.base import Candidate, Place, mechanical_nets, register, safe


@register
class ViscousFriction(Candidate):
    name = "viscous_friction"
    title = "viscous friction"
    description = "a friction torque (force) b*w opposing the motion of a body; zero b: none"

    def places(self, ctx):
        out = []
        for net, kind in mechanical_nets(ctx):
            rot = kind is PortKind.ROTATIONAL
            out.append(Place(self.name, f"{self.name}@{net}", f"on {net}", f"cal_b_{safe(net)}",
                             "N*m*s/rad" if rot else "N*s/m", 0.0, 0.0, 1e9, 1e-3 if rot else 1.0,
                             (0.0, 1e4 / max(ctx.w_ref, 1e-3)) if rot else (0.0, 1e6 / max(ctx.v_ref, 1e-6)),
                             target={"net": net, "rot": rot},
                             meaning="friction proportional to the speed",
                             plot_against=ctx.first_input_of_unit("rad/s" if rot else "m/s")))
        return out

    def patch(self, doc, place):
        net = place.target["net"]
        comp = doc.unique(f"cal_viscous_{safe(net)}")
        doc.add_component(comp, "rot_damper" if place.target["rot"] else "trans_damper", {"b": place.param})
        doc.set_net_ports(net, doc.net_ports(net) + [f"{comp}.port"])
