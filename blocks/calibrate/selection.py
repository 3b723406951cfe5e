"""From scores to a decision: refit the most promising candidates jointly with the free parameters, rank by
BIC, accept at most one, and say when the data cannot tell candidates apart.

Refit: in the candidate's own netlist (the current one with this one patch: what would be written as the
augmented netlist), the candidate's parameter freed beside the current free parameters, warm-started at the
fit with the candidate at its linearised estimate (clipped into its bounds; moved nearer its zero, at most
START_RETREATS times, while the refit from there ends worse than the candidate at its zero: _first_fit), same
residual rows; one that stops at its evaluation limit is continued once from where it stopped, and the report
marks one that stopped again (its dBIC is then an upper bound). A refit with runs failing at its end that do not
fail with the candidate at its zero fails the fit tests, and its reasons say so first.
    dBIC = chi^2_new - chi^2_current + ln(n)      (one parameter more; known noise)
More starts: a refit from one start can end in a local minimum (the chi^2 of a circuit with unstable equilibria
at some parameters has several: on the MCV's real data a p1 sensor gain refitted from its linearised estimate
ends at chi^2 603.8, and from 0.5 and 1.5 times its value, the rest where the first ended, at 590.3 and 589.0,
which makes it as good as the turbulent line loss it had trailed by 13 in BIC). So every refit that passes
the fit tests (below) and ends within RESTART_WITHIN in BIC of the best is refitted again from RESTART_FACTORS
starts: the first refit's end with the candidate's parameter moved to zero + f * (phi - zero). The lowest chi^2
of its starts counts, and the report lists every start's chi^2 where they differ.
Accepted only if all hold, tried in BIC order until one passes (refits within 0.01 of each other in BIC, and
screening scores within 1e-6 of each other, are tied and taken in the order of their place keys: equivalent
places, such as a loss on either side of one valve, agree to their last digits, and rounding, which moves
with the machine's libraries, must not choose between them):
    |phi - phi0| > 3 SE, phi inside the candidate's physically plausible range, dBIC < -10, a degree of
    freedom left beside the candidate's parameter (with none the refit is exact whatever the model), and the
    held-out error with the candidate (refits without each fold) is lower than without it.
Ambiguity: another refitted candidate that also passes the first three tests and whose dBIC is within 10
of the best, or one not refitted whose de-correlated sensitivity is nearly parallel to the best's or to
such a candidate's (|cos| > 0.99; a place in series with an ambiguous one need not have been refitted):
then the report says "ambiguous between A and B" and names the data that would separate them (the logged signal the two
fitted alternatives disagree on most, and for steady data the prediction at 1.5 times the largest input).
It also says what the choice changes: every parameter fitted in both alternatives (the declared free ones and
the effects accepted in earlier rounds) whose two values differ by more than its standard error in the best
fit. A stiffness or an earlier effect that is only as good as an ambiguous choice must not be read as measured.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from blocks.calibrate.candidates.sensor_offset import range_text
from blocks.calibrate.fit import FitResult, fit, points_of
from blocks.calibrate.heldout import HeldOut, heldout
from blocks.calibrate.model import FAILED_RESIDUAL, Model
from blocks.calibrate.screening import Score

Z_MIN = 3.0
DBIC_MAX = -10.0
AMBIGUOUS_DBIC = 10.0
PARALLEL = 0.99
REFIT_EVALUATIONS = 40  # per attempt; a refit that stops at this limit gets one more attempt
RESTART_WITHIN = 3 * AMBIGUOUS_DBIC  # refits this close to the best in BIC are tried from more starts (the
# real data's p1 gain gained 15; one farther behind would need over 20 to come within the ambiguity margin)
RESTART_FACTORS = (0.5, 1.5)  # the candidate's parameter, relative to its zero, at the further starts
LINEARISED = "its linearised estimate"  # the first start's label, unless it was moved
WORSE_THAN_ZERO = 1.0  # a refit ending this much worse in chi^2 than the candidate at its zero is stuck:
START_RETREAT = 10.0  # its start is moved this many times nearer the candidate's zero,
START_RETREATS = 6  # at most this often
TIE_DBIC = 0.01  # refits closer than this in BIC are tied (a likelihood ratio of 1.005: no evidence either way)
TIE_SCORE = 1e-6  # screening scores T this close, relative to T, are tied


def z_score(phi: float, zero: float, se: float) -> float:
    """How many standard errors an effect's parameter lies from its zero (0 when the SE is not usable)."""
    return abs(phi - zero) / se if se > 0 and np.isfinite(se) else 0.0


@dataclass
class Refit:
    score: Score
    model: Model
    fit: FitResult
    phi: float
    se: float
    dchi2: float
    dbic: float
    plausible: bool
    heldout: HeldOut | None = None
    accepted: bool = False
    reasons: list = field(default_factory=list)
    column: int = -1  # the candidate's parameter's entry in x
    base_chi2: float = float("nan")  # the same model's chi^2 with the candidate at its zero
    base_failed_rows: int = 0  # rows whose run fails there already
    starts: list = field(default_factory=list)  # (start, chi^2 at its end) of every start tried, the first first

    @property
    def z(self) -> float:
        return z_score(self.phi, self.score.place.zero, self.se)

    @property
    def run_failure(self) -> str:
        """'' unless runs fail at the refit's end that do not fail with the candidate at its zero."""
        return self.fit.run_failure(self.base_failed_rows)

    @property
    def passes_fit_tests(self) -> bool:
        return self.z > Z_MIN and self.plausible and self.dbic < DBIC_MAX and not self.run_failure and self.free

    @property
    def free(self) -> bool:
        """A degree of freedom is left beside the candidate's parameter: with none the refit is exact whatever the
        model (chi^2 = 0), which no test can judge."""
        return self.fit.n > self.fit.p

    @property
    def only_implausible(self) -> bool:
        """Passes every fit test but the plausible range: the data ask for it, the range refuses it."""
        return self.z > Z_MIN and not self.plausible and self.dbic < DBIC_MAX and not self.run_failure and self.free


@dataclass
class Decision:
    refits: list[Refit]
    accepted: Refit | None
    ambiguous: list[str]  # place keys ambiguous with the best
    separation: list[str]
    base_heldout: HeldOut | None
    depends: list[str] = field(default_factory=list)  # what the choice among the ambiguous alternatives changes


def tie_broken(items: list, value, name, tied=lambda a, b: abs(b - a) < TIE_DBIC) -> list:
    """``items`` by ``value(item)``, least first; items tied with the first of their run (``tied(value of
    first, value of other)``; by default within TIE_DBIC) in the order of ``name(item)``. Equivalent places
    (a loss on either side of one valve, the same flow through it: the same effect) score and fit alike to
    the last digits, and which comes first must not be decided by rounding, which moves with the machine's
    libraries: a report is the same on every machine."""
    ordered = sorted(items, key=value)
    out = []
    while ordered:
        first = value(ordered[0])
        run = [item for item in ordered if item is ordered[0] or tied(first, value(item))]
        out += sorted(run, key=name)
        ordered = [item for item in ordered if not any(item is r for r in run)]
    return out


def candidates_to_refit(scores: list[Score], top: int) -> list[Score]:
    """The ``top`` best-scoring screened candidates with a score worth a refit (T > 3.84, p < 5 %); scores
    within TIE_SCORE (relative) of each other in the order of their place keys."""
    worth = [s for s in scores if s.status == "screened" and s.T > 3.84]
    return tie_broken(worth, lambda s: -s.T, lambda s: s.place.key,
                      lambda a, b: abs(b - a) <= TIE_SCORE * abs(a))[:top]


def by_bic(refits: list[Refit]) -> list[Refit]:
    """Refits best (lowest dBIC) first; refits within TIE_DBIC of each other in the order of their place keys."""
    return tie_broken(refits, lambda r: r.dbic, lambda r: r.score.place.key)


def refit(model: Model, x0: np.ndarray, column: int, base: FitResult, score: Score) -> Refit:
    """Fit ``model`` (the current model plus the candidate at entry ``column`` of x) from x0, where x0 has
    the candidate at its zero; the base chi^2 is the same model's at x0."""
    rows = base.rows
    r0 = model.residuals(x0, points_of(model, rows))[rows]
    base_chi2, base_failed = float(np.sum(r0 ** 2)), int(np.sum(r0 == FAILED_RESIDUAL))
    active = base.active.copy()
    active[column] = True
    start = x0.copy()
    lo, hi = model.bounds()
    start[column] = float(np.clip(score.phi, lo[column], hi[column]))
    f, retreats = _first_fit(model, start, column, score.place.zero, active, rows, base_chi2)
    rf = _refit_result(score, model, f, column, base_chi2, base_failed)
    rf.starts.append((LINEARISED if not retreats else
                      f"{LINEARISED} moved {START_RETREAT ** retreats:g} times nearer its zero (from farther out "
                      "the refit ended worse than the candidate at its zero)", rf.fit.chi2))
    return rf


def _first_fit(model: Model, start: np.ndarray, column: int, zero: float, active: np.ndarray, rows: np.ndarray,
               base_chi2: float) -> tuple[FitResult, int]:
    """The fit from ``start`` (the linearised estimate); if it ends worse than the candidate at its zero (by
    over WORSE_THAN_ZERO in chi^2: the fit is stuck, since from the zero it could only go down), again from
    the candidate's entry START_RETREAT times nearer its zero, up to START_RETREATS times, until a fit does
    not. The lowest chi^2 counts; returned with how often its start was moved. A linearised estimate far
    beyond the linear range can lie where the model does not run (a turbulent loss in a refill valve's line,
    linearised to k = 3e19 Pa*s^2/m^6, closes the line and the solver's step falls below its minimum: every
    residual holds the failure value, there is no slope to follow, and the fit stops where it started) or
    where the outputs no longer move with it."""
    best, moved = _fit_continued(model, start, active, rows), 0
    evaluations, x = best.nfev, start.copy()
    for retreats in range(1, START_RETREATS + 1):
        if best.chi2 - base_chi2 <= WORSE_THAN_ZERO:
            break
        x[column] = zero + (x[column] - zero) / START_RETREAT
        f = _fit_continued(model, x, active, rows)
        evaluations += f.nfev
        if f.chi2 < best.chi2:
            best, moved = f, retreats
    best.nfev = evaluations
    return best, moved


def _fit_continued(model: Model, start: np.ndarray, active: np.ndarray, rows: np.ndarray) -> FitResult:
    """A fit from ``start``; one that stops at its evaluation limit is continued once from where it stopped."""
    f = fit(model, start, active, rows, max_nfev=REFIT_EVALUATIONS)
    if not f.converged:  # cut short, its chi^2 drop is understated: once more from where it stopped
        first = f
        f = fit(model, first.x, active, rows, max_nfev=REFIT_EVALUATIONS)
        f.nfev += first.nfev
        f.failures = first.failures + f.failures
    return f


def _refit_result(score: Score, model: Model, f: FitResult, column: int, base_chi2: float,
                  base_failed_rows: int) -> Refit:
    phi, se = float(f.x[column]), float(f.se[column])
    dchi2 = f.chi2 - base_chi2
    lo_p, hi_p = score.place.plausible
    return Refit(score, model, f, phi, se, float(dchi2), float(dchi2 + np.log(f.n)), bool(lo_p <= phi <= hi_p),
                 column=column, base_chi2=base_chi2, base_failed_rows=base_failed_rows)


def restarted(rf: Refit) -> Refit:
    """``rf`` tried again from RESTART_FACTORS starts (its end, the candidate's parameter moved to
    zero + f * (phi - zero), clipped into its bounds): the refit with the lowest chi^2, every start listed."""
    zero = rf.score.place.zero
    lo, hi = rf.model.bounds()
    best, evaluations, starts, tried = rf, rf.fit.nfev, list(rf.starts), {rf.phi}
    for factor in RESTART_FACTORS:
        start = rf.fit.x.copy()
        start[rf.column] = float(np.clip(zero + factor * (rf.phi - zero), lo[rf.column], hi[rf.column]))
        if start[rf.column] in tried:  # clipped back onto a start already tried (phi at a bound)
            continue
        tried.add(start[rf.column])
        f = _fit_continued(rf.model, start, rf.fit.active, rf.fit.rows)
        evaluations += f.nfev
        starts.append((f"{factor:g} x its first value", f.chi2))
        if f.chi2 < best.fit.chi2:
            best = _refit_result(rf.score, rf.model, f, rf.column, rf.base_chi2, rf.base_failed_rows)
    best.starts = starts
    best.fit.nfev = evaluations  # over every start; ``converged`` is the lowest one's
    return best


def several_minima(rf: Refit, tol: float = 1.0) -> bool:
    """Whether the starts of ``rf`` ended more than ``tol`` apart in chi^2."""
    chi2 = [c for _, c in rf.starts]
    return len(chi2) > 1 and max(chi2) - min(chi2) > tol


def decide(scores: list[Score], top: int, heldout_spec, base_model: Model, base_fit: FitResult,
           candidate_model, with_heldout: bool = True) -> Decision:
    """``candidate_model(score)`` gives (model, x0, column) for one candidate (see :func:`refit`)."""
    chosen = candidates_to_refit(scores, top)
    refits = []
    for s in chosen:
        model, x0, column = candidate_model(s)
        refits.append(refit(model, x0, column, _aligned(base_fit, base_model, model), s))
    refits = by_bic(refits)
    passing = [rf.dbic for rf in refits if rf.passes_fit_tests]
    if passing:  # the window is measured from the best refit that passes (a failing one may lead by far)
        lead = min(passing)
        refits = by_bic([restarted(rf) if rf.passes_fit_tests and rf.dbic - lead < RESTART_WITHIN else rf
                         for rf in refits])
    base_ho = None
    accepted = None
    for rf in refits:
        if rf.run_failure:  # first: the other reasons then judge a misfit that is not one
            rf.reasons.append(rf.run_failure)
        if not rf.z > Z_MIN:
            rf.reasons.append(f"|phi| = {rf.z:.2g} SE (needs > {Z_MIN:g})")
        if not rf.plausible:
            rf.reasons.append(f"outside the plausible range {range_text(getattr(rf.model, 'exp', None), rf.score.place)}")
        if not rf.dbic < DBIC_MAX:
            rf.reasons.append(f"dBIC = {rf.dbic:.3g} (needs < {DBIC_MAX:g})")
        if not rf.free:
            rf.reasons.append(f"no degree of freedom left beside it ({rf.fit.n} readings, {rf.fit.p} unknowns)")
        if accepted is not None and not rf.reasons:
            rf.reasons.append(f"{rf.dbic - accepted.dbic:.3g} behind the accepted {accepted.score.place.key} in BIC")
        if rf.reasons:
            continue
        if with_heldout:
            if base_ho is None:
                base_ho = heldout(base_model, base_fit, heldout_spec)
            rf.heldout = heldout(rf.model, rf.fit, heldout_spec)
            if not rf.heldout.score < base_ho.score:
                rf.reasons.append(f"held-out {rf.heldout.measure} {rf.heldout.score:.4g} is not below "
                                  f"{base_ho.score:.4g}")
                continue
        rf.accepted = True
        accepted = rf
    best = accepted or next((rf for rf in refits if rf.passes_fit_tests), None)
    ambiguous, separation = ambiguity(best, refits, scores) if best is not None else ([], [])
    depends = [line for rf in refits if rf is not best and rf.score.place.key in ambiguous
               for line in [choice_moves(best, rf)] if line]
    return Decision(refits, accepted, ambiguous, separation, base_ho, depends)


def ambiguity(best: Refit, refits: list[Refit], scores: list[Score]) -> tuple[list[str], list[str]]:
    """The places the data cannot tell from ``best`` and what would separate them: refitted alternatives
    that pass the fit tests within 10 in BIC of it; places not refitted whose de-correlated sensitivity is
    nearly parallel (|cos| > 0.99) to the best's, or to such an alternative's (to first order as good as
    the one it parallels: the same loss at the other end of one line). A refitted place is judged by its
    refit only."""
    ambiguous, separation = [], []
    alike = [best]
    for rf in refits:
        if rf is not best and rf.passes_fit_tests and rf.dbic - best.dbic < AMBIGUOUS_DBIC:
            ambiguous.append(rf.score.place.key)
            separation += separate(best, rf)
            alike.append(rf)
    refitted = {id(rf.score) for rf in refits}  # a refitted place is judged by its refit, above
    for s in scores:
        if id(s) in refitted or s.status != "screened" or s.s_perp is None or s.place.key in ambiguous:
            continue
        for ref in alike:
            if ref.score.s_perp is None or ref.score is s:
                continue
            cos = abs(float(s.s_perp @ ref.score.s_perp))
            if cos > PARALLEL:
                ambiguous.append(s.place.key)
                key, other = best.score.place.key, ref.score.place.key
                separation.append(
                    f"{key} and {s.place.key} move the measured channels alike (|cos| = {cos:.4f} after removing "
                    f"what the free parameters absorb)" if ref is best else
                    f"{s.place.key} moves the measured channels like {other} (|cos| = {cos:.4f} after removing "
                    f"what the free parameters absorb), which is ambiguous with {key}")
                break
    return ambiguous, separation


def choice_moves(a: Refit, b: Refit) -> str | None:
    """The parameters fitted in both a and b whose values differ by more than one standard error of a's fit
    (a: the best), in their display units; None when nothing shared moves that much."""
    from blocks.units import display_factor

    moved = []
    for k, g in enumerate(a.model.layout.globals):
        if not a.fit.active[k]:
            continue
        try:
            j = b.model.layout.index(g.name)
        except KeyError:
            continue
        se, diff = float(a.fit.se[k]), abs(float(a.fit.x[k] - b.fit.x[j]))
        if b.fit.active[j] and np.isfinite(se) and se > 0 and diff > se:
            f = display_factor(g.unit)
            unit = "" if g.unit in ("1", "") else f" {g.unit}"
            moved.append(f"{g.name} = {a.fit.x[k] / f:.4g} against {b.fit.x[j] / f:.4g}{unit} ({diff / se:.2g} SE)")
    if not moved:
        return None
    return f"{a.score.place.key} vs {b.score.place.key}: the choice moves " + "; ".join(moved)


def _aligned(base: FitResult, base_model: Model, model: Model) -> FitResult:
    """The base fit's active mask and rows in ``model``'s parameter vector (shared names, same latents)."""
    names = model.layout.names()
    old = {n: k for k, n in enumerate(base_model.layout.names())}
    active = np.array([n in old and bool(base.active[old[n]]) for n in names], dtype=bool)
    from dataclasses import replace

    return replace(base, active=active)


def separate(a: Refit, b: Refit) -> list[str]:
    """What would tell the fitted alternatives a and b apart: the logged signal (not compared) they disagree
    on most, relative to its own size, and for steady data their predictions at 1.5 times the largest input."""
    from blocks.units import parse_unit

    out = []
    sa = a.model.signals(a.fit.x)
    sb = b.model.signals(b.fit.x)
    names_b = {o.name: k for k, o in enumerate(b.model.circuit.outputs)}
    measured = {c.signal for c in a.model.channels if c.signal}
    best, which = 0.0, None
    for k, o in enumerate(a.model.circuit.outputs):
        if o.name in measured or o.name not in names_b:
            continue
        ya, yb = sa[:, k], sb[:, names_b[o.name]]
        if not (np.isfinite(ya).any() and np.isfinite(yb).any()):
            continue
        diff = float(np.nanmax(np.abs(ya - yb)))
        scale = float(np.nanmax(np.abs(ya))) or 1.0
        if diff / scale > best:
            best, which = diff / scale, (o, diff)
    key_a, key_b = a.score.place.key, b.score.place.key
    if which is not None and best > 1e-3:
        o, diff = which
        unit = "" if o.display_unit in ("", "1") else f" {o.display_unit}"
        apart = f"the two fits predict it up to {diff / parse_unit(o.display_unit or '1').factor:.3g}{unit} apart"
        imposed = next((c.name for c in a.model.channels if c.role == "input" and c.name == o.name), None)
        if imposed is not None:  # the data have it, but as an imposed input: say so rather than "measure it"
            out.append(f"{key_a} vs {key_b}: comparing the logged signal '{o.name}' with the data's column "
                       f"'{imposed}' (imposed as an input in this experiment) would separate them ({apart})")
        else:
            out.append(f"{key_a} vs {key_b}: measuring '{o.name}' would separate them ({apart})")
    model = a.model
    if model.data.kind == "steady" and model.layout.inputs:
        worst = int(np.argmax(np.abs(model.data.measured[model.layout.inputs[0]])))
        pa = _extrapolate(a.model, a.fit.x, worst)
        pb = _extrapolate(b.model, b.fit.x, worst)
        if pa is not None and pb is not None:
            parts = []
            for c in model.channels:
                if c.role == "output":
                    ka, kb = a.model.signal_index[c.signal], b.model.signal_index[c.signal]
                    parts.append(f"{c.name} by {abs(pa[ka] - pb[kb]) / model.data.sigma[c.name]:.2g} sigma")
            out.append(f"{key_a} vs {key_b}: at 1.5 times the largest {model.layout.inputs[0]} the two fits "
                       f"differ in " + ", ".join(parts))
    return out


def _extrapolate(model: Model, x: np.ndarray, point: int):
    xp = x.copy()
    j = model.layout.latent_index(point, 0)
    xp[j] *= 1.5
    return model._steady_point(point, xp, model._net_overrides(xp))


RESTART_DROP = 25.0
"""A refit whose chi^2 is this much below the fit's beyond what its candidate accounts for (z^2, with z from
the SE not inflated by the misfit: a 5-sigma drop for one parameter) went to a better minimum of the other
parameters."""


def better_start(refits: list[Refit], base_chi2: float) -> Refit | None:
    """The refit of a round (``refits``, of a fit with ``base_chi2``) that shows that fit stopped short of its
    best: its candidate is not significant (under 3 SE from zero) and yet its chi^2 is over RESTART_DROP below
    the fit's beyond the z^2 the candidate accounts for, so the other parameters found a better minimum on the way (an
    oscillating circuit's fit started 20 % off its mass can stop in a local minimum). z is taken from the SE
    before the misfit inflates it (a model far from the data inflates every SE, and its candidates' drops
    are their own). The lowest such refit, or None."""
    found = []
    for rf in refits:
        if rf.run_failure or not (rf.se > 0 and np.isfinite(rf.se)) or not rf.z < Z_MIN:
            continue
        z_raw = rf.z * np.sqrt(rf.fit.inflation)
        if base_chi2 - rf.fit.chi2 - z_raw ** 2 > RESTART_DROP:
            found.append(rf)
    return min(found, key=lambda rf: rf.fit.chi2, default=None)
