"""Steady flow force on a valve spool: the block's continuous flow-force gain (e.g. spool_relief_valve.c_ff).

Applies to components whose block declares a continuous flow-force parameter (FLOW_FORCE_PARAMS). A block
with only an integer on/off switch for its flow force cannot take a zero-parameter patch: it is listed as
"not applicable" with the reason, and nothing is added to it.
"""

from blocks.calibrate.candidates.base import Candidate, Place, add_to_param, register, safe

FLOW_FORCE_PARAMS = {"c_ff": (-0.5, 0.5), "flow_force": (-3.0, 3.0)}
"""Continuous flow-force gains (zero = no flow force) this candidate drives, with their plausible ranges:
spool_relief_valve.c_ff (the force ratio of 2*Cd*Cv*cos(theta)*A*dp over the spool area) and
mcv_vaa.flow_force (the scale of the thesis's eq. 3.13, 1 = the thesis's hand fit)."""


@register
class FlowForce(Candidate):
    name = "flow_force"
    title = "steady flow force"
    description = ("the steady flow force on a valve spool through the block's continuous gain (c_ff of "
                   "spool_relief_valve: p_F = c_ff*s*dp over the spool area; flow_force of mcv_vaa: the scale of "
                   "eq. 3.13); zero gain: none")

    def places(self, ctx):
        out = []
        for comp, flat in ctx.top_components().items():
            names = {p.name: p for p in flat.cls.params}
            gain = next((n for n in FLOW_FORCE_PARAMS if n in names and not names[n].integer), None)
            if gain is None:
                switch = next((p for p in flat.cls.params if "flow_force" in p.name and p.integer), None)
                if switch is not None:
                    ctx.notes.append(f"flow_force: not applicable to {comp} ({flat.cls.type_name}): the block has "
                                     f"only the 0/1 switch '{switch.name}'; a continuous flow-force gain (zero = "
                                     f"none) is needed in the block for calibration to scale it")
                continue
            p = names[gain]
            base = ctx.values.get(f"{comp}.{gain}", 0.0)
            lo, hi = FLOW_FORCE_PARAMS[gain]
            out.append(Place(self.name, f"{self.name}@{comp}", f"on the spool of {comp}", f"cal_cff_{safe(comp)}",
                             p.unit, 0.0, p.lower - base, p.upper - base, 1e-3, (lo - base, hi - base),
                             target={"component": comp, "param": gain}, one_sided=False,
                             meaning=f"added to {comp}.{gain} (declared {base:g})",
                             plot_against=ctx.first_input_of_unit("m^3/s")))
        return out

    def patch(self, doc, place):
        add_to_param(doc, place.target["component"], place.target["param"], place.param)
