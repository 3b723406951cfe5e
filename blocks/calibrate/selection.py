"""From scores to a decision: refit the most promising candidates jointly with the free parameters, rank by
BIC, accept at most one, and say when the data cannot tell candidates apart.

Refit: the candidate's parameter freed beside the current free parameters, warm-started at the fit with
the candidate at its linearised estimate (clipped into its bounds), same residual rows.
    dBIC = chi^2_new - chi^2_current + ln(n)      (one parameter more; known noise)
Accepted only if all hold, tried in BIC order until one passes:
    |phi - phi0| > 3 SE, phi inside the candidate's physically plausible range, dBIC < -10, and the
    held-out error with the candidate (refits without each fold) is lower than without it.
Ambiguity: another candidate that also passes the first three tests and whose dBIC is within 10 of the
best, or whose de-correlated sensitivity is nearly parallel to the best's (|cos| > 0.99): then the report
says "ambiguous between A and B" and names the data that would separate them (the logged signal the two
fitted alternatives disagree on most, and for steady data the prediction at 1.5 times the largest input).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from blocks.calibrate.fit import FitResult, fit
from blocks.calibrate.heldout import HeldOut, heldout
from blocks.calibrate.model import Model
from blocks.calibrate.screening import Score

Z_MIN = 3.0
DBIC_MAX = -10.0
AMBIGUOUS_DBIC = 10.0
PARALLEL = 0.99


@dataclass
class Refit:
    score: Score
    fit: FitResult
    phi: float
    se: float
    dchi2: float
    dbic: float
    plausible: bool
    heldout: HeldOut | None = None
    accepted: bool = False
    reasons: list = field(default_factory=list)

    @property
    def z(self) -> float:
        return abs(self.phi - self.score.place.zero) / self.se if self.se > 0 and np.isfinite(self.se) else 0.0

    @property
    def passes_fit_tests(self) -> bool:
        return self.z > Z_MIN and self.plausible and self.dbic < DBIC_MAX


@dataclass
class Decision:
    refits: list[Refit]
    accepted: Refit | None
    ambiguous: list[str]  # place keys ambiguous with the best
    separation: list[str]
    base_heldout: HeldOut | None


def candidates_to_refit(scores: list[Score], top: int, n: int) -> list[Score]:
    """The ``top`` best-scoring screened candidates with a score worth a refit (T > 3.84, p < 5 %)."""
    ranked = sorted((s for s in scores if s.status == "screened" and s.T > 3.84), key=lambda s: -s.T)
    return ranked[:top]


def refit(smodel: Model, x: np.ndarray, base: FitResult, score: Score, column: int, base_chi2: float) -> Refit:
    place = score.place
    active = base.active.copy()
    active[column] = True
    x0 = x.copy()
    lo, hi = smodel.bounds()
    x0[column] = float(np.clip(score.phi, lo[column], hi[column]))
    f = fit(smodel, x0, active, base.rows, max_nfev=40)
    phi, se = float(f.x[column]), float(f.se[column])
    dchi2 = f.chi2 - base_chi2
    dbic = dchi2 + np.log(f.n)
    lo_p, hi_p = place.plausible
    plausible = bool(lo_p <= phi <= hi_p)
    return Refit(score, f, phi, se, float(dchi2), float(dbic), plausible)


def decide(smodel: Model, x: np.ndarray, base: FitResult, scores: list[Score], column_of: dict, top: int,
           heldout_spec, base_model: Model, base_fit: FitResult) -> Decision:
    rows = base.rows
    base_chi2 = float(np.sum(smodel.residuals(x, None if smodel.data.kind != "steady" else
                                              np.unique(smodel.row_point[rows]))[rows] ** 2))
    chosen = candidates_to_refit(scores, top, int(rows.sum()))
    refits = [refit(smodel, x, base, s, column_of[s.place.key], base_chi2) for s in chosen]
    refits.sort(key=lambda r: r.dbic)
    base_ho = None
    accepted = None
    for rf in refits:
        if not rf.z > Z_MIN:
            rf.reasons.append(f"|phi| = {rf.z:.2g} SE (needs > {Z_MIN:g})")
        if not rf.plausible:
            rf.reasons.append(f"outside the plausible range [{rf.score.place.plausible[0]:.3g}, "
                              f"{rf.score.place.plausible[1]:.3g}] {rf.score.place.unit}")
        if not rf.dbic < DBIC_MAX:
            rf.reasons.append(f"dBIC = {rf.dbic:.3g} (needs < {DBIC_MAX:g})")
        if rf.reasons or accepted is not None:
            continue
        if base_ho is None:
            base_ho = heldout(base_model, base_fit, heldout_spec)
        rf.heldout = heldout(smodel, rf.fit, heldout_spec)
        if not rf.heldout.error < base_ho.error:
            rf.reasons.append(f"held-out error {rf.heldout.error:.3g} is not below {base_ho.error:.3g}")
            continue
        rf.accepted = True
        accepted = rf
    ambiguous, separation = [], []
    best = accepted or next((rf for rf in refits if rf.passes_fit_tests), None)
    if best is not None:
        for rf in refits:
            if rf is best:
                continue
            close = rf.passes_fit_tests and rf.dbic - best.dbic < AMBIGUOUS_DBIC
            if close:
                ambiguous.append(rf.score.place.key)
                separation += separate(smodel, best, rf)
        for s in scores:
            if s is best.score or s.status != "screened" or s.s_perp is None or best.score.s_perp is None:
                continue
            if s.place.key in ambiguous:
                continue
            cos = abs(float(s.s_perp @ best.score.s_perp))
            if cos > PARALLEL:
                ambiguous.append(s.place.key)
                separation.append(f"{best.score.place.key} and {s.place.key} move the measured channels alike "
                                  f"(|cos| = {cos:.4f} after removing what the free parameters absorb)")
    return Decision(refits, accepted, ambiguous, separation, base_ho)


def separate(smodel: Model, a: Refit, b: Refit) -> list[str]:
    """What would tell the fitted alternatives a and b apart: the logged signal they disagree on most
    (relative to its own spread), and for steady data their predictions at 1.5 times the largest input."""
    out = []
    sa = smodel.signals(a.fit.x)
    sb = smodel.signals(b.fit.x)
    measured = {c.signal for c in smodel.channels if c.signal}
    best, name = 0.0, None
    for k, o in enumerate(smodel.circuit.outputs):
        diff = np.nanmax(np.abs(sa[:, k] - sb[:, k])) if np.isfinite(sa[:, k]).any() else 0.0
        scale = np.nanmax(np.abs(sa[:, k])) or 1.0
        if diff / scale > best and o.name not in measured:
            best, name = diff / scale, o
    key_a, key_b = a.score.place.key, b.score.place.key
    if name is not None and best > 1e-3:
        k = smodel.circuit.outputs.index(name)
        from blocks.units import parse_unit

        factor = parse_unit(name.display_unit).factor
        d = np.nanmax(np.abs(sa[:, k] - sb[:, k])) / factor
        out.append(f"{key_a} vs {key_b}: measuring '{name.name}' would separate them (the two fits predict it "
                   f"up to {d:.3g} {name.display_unit} apart)")
    if smodel.data.kind == "steady" and smodel.layout.inputs:
        worst = int(np.argmax(np.abs(smodel.data.measured[smodel.layout.inputs[0]])))
        pa = _extrapolate(smodel, a.fit.x, worst)
        pb = _extrapolate(smodel, b.fit.x, worst)
        if pa is not None and pb is not None:
            parts = []
            for c in smodel.channels:
                if c.role == "output":
                    k = smodel.signal_index[c.signal]
                    parts.append(f"{c.name} by {abs(pa[k] - pb[k]) / smodel.data.sigma[c.name]:.2g} sigma")
            out.append(f"{key_a} vs {key_b}: at 1.5 times the largest {smodel.layout.inputs[0]} the two fits "
                       f"differ in " + ", ".join(parts))
    return out


def _extrapolate(smodel: Model, x: np.ndarray, point: int):
    xp = x.copy()
    for i in range(len(smodel.layout.inputs)):
        j = smodel.layout.latent_index(point, i)
        if i == 0:
            xp[j] *= 1.5
    base = smodel._net_overrides(xp)
    return smodel._steady_point(point, xp, base)
