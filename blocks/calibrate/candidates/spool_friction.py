"""Spool friction with hysteresis: the block's Dahl friction parameter (spool_relief_valve.p_fric).

With Dahl's model the friction force stays where it was when the spool stops, so points approached from
below and from above differ by 2*p_fric in pressure: a hysteresis. A tanh-smoothed Coulomb friction could
not do that (it vanishes at rest). Blocks without a spool force balance that takes a friction term (the
crane's mcv_vaa: 2nd-order spool response to a static equilibrium) cannot take this patch: "not applicable".
"""

from blocks.calibrate.candidates.base import Candidate, Place, add_to_param, register, safe

FRICTION_PARAMS = ("p_fric",)


@register
class SpoolFriction(Candidate):
    name = "spool_friction"
    title = "spool friction (hysteresis)"
    description = ("Coulomb friction of a valve spool with Dahl's pre-sliding model (p_fric of "
                   "spool_relief_valve), which holds the spool short of its equilibrium: hysteresis; zero: none")

    def places(self, ctx):
        out = []
        for comp, flat in ctx.top_components().items():
            names = {p.name for p in flat.cls.params}
            param = next((n for n in FRICTION_PARAMS if n in names), None)
            if param is None:
                if flat.cls.type_name == "mcv_vaa":
                    ctx.notes.append(f"spool_friction: not applicable to {comp} (mcv_vaa): its spool follows a "
                                     f"static equilibrium through a 2nd-order response, with no friction force "
                                     f"in the balance to scale")
                continue
            base = ctx.values.get(f"{comp}.{param}", 0.0)
            out.append(Place(self.name, f"{self.name}@{comp}", f"on the spool of {comp}", f"cal_pfric_{safe(comp)}",
                             "Pa", 0.0, 0.0, 1e9 - base, 1e3, (0.0, 50e5), target={"component": comp, "param": param},
                             meaning=f"Coulomb friction over the spool area, added to {comp}.{param}",
                             plot_against=ctx.first_input_of_unit("m^3/s")))
        return out

    def patch(self, doc, place):
        add_to_param(doc, place.target["component"], place.target["param"], place.param)
