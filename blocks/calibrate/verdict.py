"""The verdict of a calibration: the effects found, removed, exchanged or superseded, the ambiguities and
what would separate them, refits refused only for their range, parameters the data do not fix, a noise
overstated, and whether a discrepancy remains unexplained (the lack-of-fit tests of the final fit,
:meth:`blocks.calibrate.stats.LackOfFit.significant`), with what to check first when the misfit is gross or a
run starts off the data."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from blocks.calibrate.candidates.sensor_offset import shown as shown_offset, shown_text
from blocks.calibrate.run_start import initial_values, start_misfits

if TYPE_CHECKING:
    from blocks.calibrate.run import Calibration, Round, Stage

GROSS_MISFIT = 100.0  # final chi^2/nu beyond which the verdict asks to check the experiment before the effects


def final_effects(cal: Calibration) -> list:
    """[(place, round)] of the final model's accepted effects, in round order (an exchanged-in effect in the
    place of the one it replaced)."""
    made = next((ex for ex in cal.exchanges if ex.made), None)
    effects = []
    for rnd in cal.rounds:
        if rnd.decision.accepted is not None:
            place = rnd.decision.accepted.score.place
            effects.append((made.place if made is not None and place.key == made.out_key else place, rnd.index))
    return effects




def verdict(cal: Calibration) -> tuple[list[str], bool]:
    """The report's verdict lines and whether a discrepancy remains unexplained. An effect removed by the
    elimination check is "removed"; one the final fit no longer holds over 3 SE from zero that the check
    could not take out (the last one, or a model that cannot be built without it) is "superseded", not
    "found"; it stays in the augmented netlist, where its fitted value is what the final fit says."""
    lines = list(getattr(cal, "restarts", []))
    for key, title, where, param, value, se, unit in cal.accepted:
        said = shown_text(cal.exp, key, value, se, unit)  # a sensor offset in its channel's unit, as the data are
        if abs(value) > 3.0 * se:
            lines.append(f"found: {title} {where}: {param} = {said}")
        else:
            lines.append(f"superseded: {title} {where}: {param} = {said} in the final fit, no longer over 3 SE "
                         f"from zero (a later effect explains what it did)")
    for ex in cal.exchanges:
        if ex.made:
            lines.append(f"exchanged: {ex.out_key} (accepted in round {ex.round}) for {ex.in_key}, which fits better "
                         f"beside the effects found after it (BIC lower by {-ex.dbic:.3g})"
                         + ("; by less than 10: ambiguous between the two" if ex.ambiguous else ""))
    param_of = {place.key: place.param for place, _ in final_effects(cal)}
    removed = [(test.key, param_of.get(test.key, test.key)) for test in cal.removals if test.removed]
    for test in cal.removals:
        if test.removed:
            lines.append(f"removed: {test.key} (accepted in round {test.round}): beside the other effects it is "
                         f"{test.z:.2g} SE from zero and taking it out changes BIC by {test.dbic:+.3g} (an effect "
                         f"is kept only over 3 SE and over +10)")
    for rnd in cal.rounds:
        if rnd.stopped:
            lines.append(f"round {rnd.index}: the trace stopped: {rnd.stopped}")
        lines += refused_as_implausible(rnd, cal.exp)
        if rnd.decision.ambiguous:
            best = rnd.decision.accepted or next((r for r in rnd.decision.refits if r.passes_fit_tests), None)
            name = best.score.place.key if best else "?"
            lines.append(f"round {rnd.index}: ambiguous between {name} and {', '.join(rnd.decision.ambiguous)}")
            lines += [f"  to separate them: {s}" for s in rnd.decision.separation]
            lines += [f"  what the choice changes: {s}" + "".join(
                f" ({param}, of {key}, was removed after this round)" for key, param in removed if param in s)
                      for s in rnd.decision.depends]
    unexplained = False
    if getattr(cal, "held_levels", None):
        lines.append(f"not fitted: {', '.join(cal.held_levels)}, command level(s) in force only after the last "
                     f"sample of their run: they act on no sample, so they keep the netlist's values")
    if cal.final is not None:
        failure = cal.final.fit.run_failure()
        if failure:  # such rows hold a penalty, not a residual: say so before any statistic they enter
            lines.append(f"the final fit's runs fail: {failure}")
        loose = unidentified(cal.final) if cal.final.fit.failed_rows < cal.final.fit.n else []
        if loose:
            lines.append(f"not identifiable from these data: {', '.join(loose)} (the data do not fix "
                         f"{'it' if len(loose) == 1 else 'them'}: an infinite standard error; the value reported is "
                         f"wherever the fit left it, and a fit 'to the noise' says nothing about it)")
    if cal.final is not None and not cal.final.fit.converged:
        lines.append(f"the final fit stopped at its limit of {cal.final.fit.nfev} evaluations before converging: "
                     f"its values may not be the best fit")
    if cal.final is not None:
        for c in cal.final.lof.overstated_noise():
            lines.append(f"{c.name}: chi^2/nu = {c.reduced:.3g}, far below 1: its residuals (RMS "
                         f"{c.rmse / c.sigma:.2g} of its noise) are much smaller than the noise given; check its "
                         f"noise and the noise's unit: with the noise overstated every test here is lenient, and an "
                         f"effect can go unseen")
        reasons = cal.final.lof.significant()
        if reasons:
            unexplained = True
            lines.append("unexplained discrepancy remains: " + "; ".join(reasons))
            if cal.final.fit.inflation > GROSS_MISFIT:  # over the rows that ran
                lines.append(f"  the model misses the data by chi^2/nu = {cal.final.fit.inflation:.3g}, far more than "
                             f"an effect of the library leaves unexplained: check the experiment first (units, "
                             f"overrides, the groups' values, which columns are imposed); an effect found on such "
                             f"a fit explains a sliver of the misfit and is not to be read as measured")
            lines += [f"  {m.line(initial_values(cal.final))}" for m in start_misfits(cal.final)]
            exact = cal.exp.exact_columns
            if exact:
                lines.append("  the netlist imposes " + ", ".join(f"the column {c} ({p})" for c, p in exact)
                             + " exactly as read from the data: its measurement noise is not accounted for, passes "
                               "into the outputs and can be what remains (listed under inputs: with latent: trace, it "
                               "is fitted with its noise)")
        elif not cal.accepted:
            lines.append("no effect found: the declared model fits to the noise")
        else:
            lines.append("the augmented model fits to the noise")
    return lines, unexplained




def refused_as_implausible(rnd: Round, exp) -> list[str]:
    """A verdict line for each refit of the round that the data ask for (over 3 SE, BIC over 10 lower) and
    that fits better than what the round accepted, refused because its value lies outside the candidate's
    plausible range (the held-out test is not run on a refit already refused): a limit of the library, not
    of the data, which the engineer must see. Values in the unit the report shows them in (``exp``'s
    channels: a sensor offset in its channel's unit, :func:`~blocks.calibrate.candidates.sensor_offset.shown`)."""
    accepted = rnd.decision.accepted
    out = []
    for rf in rnd.decision.refits:
        if rf.only_implausible and (accepted is None or rf.dbic < accepted.dbic):
            place, lo_hi = rf.score.place, rf.score.place.plausible
            factor, unit = shown_offset(exp, place.key, 1.0, place.unit)
            unit = "" if unit in ("", "1", "SI") else f" {unit}"
            limit = next((b for b in (place.lower, place.upper) if np.isfinite(b)
                          and abs(rf.phi - b) <= 1e-6 * max(abs(b), abs(rf.se))), None)
            out.append(f"round {rnd.index}: {place.key} = {shown_text(exp, place.key, rf.phi, rf.se, place.unit)}"
                       + (f" (at the limit of its search, {limit * factor:g}{unit})" if limit is not None else "")
                       + f" (dBIC {rf.dbic:.4g}"
                       + (f", better than the accepted {accepted.score.place.key}" if accepted else "")
                       + f") passed the fit tests and was refused as outside its plausible range "
                       f"[{lo_hi[0] * factor:.3g}, {lo_hi[1] * factor:.3g}]{unit} (its held-out error was then not "
                       f"tested): if such a value is possible in this machine, the library's range is what refused it")
    return out




def unidentified(stage: Stage) -> list[str]:
    """The fitted parameters (declared, effects and sensor corrections; latent inputs have their own readings)
    that the data do not fix: an infinite or undefined standard error (blocks.calibrate.fit.covariance)."""
    return [f.name for k, f in enumerate(stage.model.layout.globals)
            if f.kind in ("declared", "candidate", "correction") and stage.fit.active[k]
            and not np.isfinite(stage.fit.se[k])]
