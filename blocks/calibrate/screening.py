"""Screening every candidate at every place by a score test, at the current fit, in one screening netlist.

The screening netlist is the current netlist with every netlist candidate patched in at once, each with its
own parameter at its zero value: it is the current model (checked: its residuals at the fitted parameters
are compared with the fit's and the largest difference is reported). Sensitivities are forward differences
of the normalised residuals, s = (r(phi0 + h) - r(phi0))/h, the step h adapted until the largest change is
between 0.01 and 3 noise sigmas (a channel candidate needs no simulation: the change is in post-processing).

Score test (Rao), with J the Jacobian of the current fit's free parameters (declared, latent inputs,
accepted candidates) and r its residuals:
    s_perp = s - J (J^+ s)                 the part of the sensitivity the free parameters cannot absorb
    T      = (s_perp . r)^2 / (s_perp . s_perp)   ~ chi^2_1 when the candidate is absent
    phi    = phi0 - (s_perp . r) / (s_perp . s_perp)   the linearised estimate
T is the drop of chi^2 that the candidate would bring to first order, after the declared parameters have
taken what they can. A candidate whose parameter is one-sided (a loss, a leak, a friction, a volume, a delay
is >= 0) scores 0 when the data pull it below zero. "not identifiable": the free parameters absorb over
99.9 % of its sensitivity (||s_perp||^2 < 1e-3 ||s||^2; the absorbing parameters are named); "no effect":
even the largest step moved no residual by 1e-3 sigma, or (checked where the candidate would score, T > 1)
the change is not proportional to the step, at the step h or at 10 h: with d(h) the change of the
residuals at the step h,

    || d(h) - 2 d(h/2) || > 0.5 || d(h) ||

A first-order effect, which the score assumes, gives a small left side (a parameter that enters linearly:
0). The larger step is tried when the first fails, since a real effect fails there too where its first step
is too small against the solver's noise, or half of it falls where the candidate is not yet in force (a
transport delay below its shortest, T_min = 1e-5 s, passes its input through); there it is scored with the
larger step's change. A jump fails at both, with a left side of about || d(h) || or more: an extra volume on a
steady rig, which moves no equilibrium, moved residuals by 321 sigma at one step and 0 at half of it (a
point whose equilibrium check then fell back to its settling run, read before the larger volume settled),
and scored T = 14; refitted to 0.61 l at 40 standard errors, it lowered chi^2 by 1e-5. So does the
solver's noise: a turbulent loss before an ideal flow source, 8e4 times its own change.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats as sps

from blocks.calibrate.candidates.base import Place
from blocks.calibrate.fit import FitResult, column_space, points_of
from blocks.calibrate.model import Model


@dataclass
class Score:
    place: Place
    status: str  # "screened", "no effect", "not identifiable"
    T: float = 0.0
    p_value: float = 1.0
    phi: float = 0.0  # linearised estimate
    absorbed: float = 0.0
    absorbed_by: list = field(default_factory=list)
    step: float = 0.0
    s_perp: np.ndarray | None = None  # unit vector (used rows)
    note: str = ""


def screen(smodel: Model, x: np.ndarray, base: FitResult, places: list[Place], column_of: dict) -> tuple[list[Score], float]:
    """Score every place; ``column_of[place.key]`` is the candidate's entry of x (at its zero).
    Returns the scores and the largest |residual| difference between the screening model and the fit."""
    rows = base.rows
    points = points_of(smodel, rows)
    r0_full = smodel.residuals(x, points)
    r0 = r0_full[rows]
    consistency = float(np.max(np.abs(r0 - base.r[rows]))) if r0.size else 0.0
    Q, coef_basis, names = _basis(base, smodel)
    declared = {g.name for g in smodel.layout.globals if g.kind in ("declared", "candidate", "correction")}
    scores = []
    for place in places:
        j = column_of[place.key]
        s, h, moved = _sensitivity(smodel, x, j, place, points, rows, r0)
        if moved < 1e-3:
            scores.append(Score(place, "no effect", step=h, note="no residual moved by 1e-3 sigma"))
            continue
        projection = (Q, coef_basis, names, declared)
        score = _scored(place, s, h, r0, projection)
        if score.status == "screened" and score.T > PROPORTIONAL_FROM:
            first_order = _first_order(smodel, x, j, place, points, rows, r0, s * h, h)
            if first_order is None:
                score = Score(place, "no effect", step=h, note="the outputs' change is not proportional to its "
                              "size, at its step or 10 times it (a jump, or the solver's noise): no first-order "
                              "effect to score")
            elif first_order[1] != h:
                score = _scored(place, *first_order, r0, projection)
        scores.append(score)
    return scores, consistency


def _scored(place: Place, s: np.ndarray, h: float, r0: np.ndarray, projection) -> Score:
    """The score test of a candidate of sensitivity ``s`` (at the step ``h``) against the residuals ``r0``;
    ``projection``: the basis of the free parameters' columns and what names them (:func:`screen`)."""
    Q, coef_basis, names, declared = projection
    proj = Q @ (Q.T @ s) if Q.size else np.zeros_like(s)
    s_perp = s - proj
    ss, sp = float(s @ s), float(s_perp @ s_perp)
    absorbed = 1.0 - sp / ss if ss > 0 else 1.0
    by = _absorbers(coef_basis, names, s, declared)
    if sp < 1e-3 * ss:
        return Score(place, "not identifiable", absorbed=absorbed, absorbed_by=by, step=h,
                     note="absorbed by " + ", ".join(by))
    g = float(s_perp @ r0)
    T = g * g / sp
    phi = place.zero - g / sp
    note = ""
    if place.one_sided:
        sign = 1.0 if place.upper > place.zero else -1.0
        if (phi - place.zero) * sign < 0:
            T, note = 0.0, "the data pull it to the wrong sign"
    p = float(sps.chi2.sf(T, 1)) * (0.5 if place.one_sided and T > 0 else 1.0)
    return Score(place, "screened", T, p, phi, absorbed, by, h, s_perp / np.sqrt(sp), note)


PROPORTIONAL_FROM = 1.0
"""The score T above which a candidate's change is checked for proportionality to its step (below it, the
candidate ranks nowhere and the check's simulations are spared)."""
RETRY_FACTOR = 10.0
"""The larger step a change not proportional at its first step is tried again at (module docstring)."""


def _first_order(model, x, j, place: Place, points, rows, r0, d: np.ndarray, h: float):
    """(sensitivity, step) at which the change of the residuals is first order: ``h`` itself (``d`` the change
    there), else RETRY_FACTOR * h (within the candidate's room); None if it is at neither (module docstring)."""
    if _proportional(model, x, j, place, points, rows, r0, d, h):
        return d / h, h
    room = place.upper - place.zero
    larger = min(RETRY_FACTOR * h, 0.5 * room) if np.isfinite(room) and room > 0 else RETRY_FACTOR * h
    if not larger > h:
        return None
    wider = _change(model, x, j, place, points, rows, r0, larger)
    return (wider / larger, larger) if _proportional(model, x, j, place, points, rows, r0, wider, larger) else None


def _change(model, x, j, place: Place, points, rows, r0, h: float) -> np.ndarray:
    """The change of the used rows' residuals with the candidate at its zero + ``h``."""
    xp = x.copy()
    xp[j] = place.zero + h
    return model.residuals(xp, points)[rows] - r0


def _proportional(model, x, j, place: Place, points, rows, r0, d: np.ndarray, h: float) -> bool:
    """Whether the change ``d`` of the residuals at the step ``h`` is first order: half the step changes them
    by about half as much (module docstring)."""
    half = _change(model, x, j, place, points, rows, r0, 0.5 * h)
    return float(np.linalg.norm(d - 2.0 * half)) <= 0.5 * float(np.linalg.norm(d))


def _sensitivity(model, x, j, place: Place, points, rows, r0):
    h = place.step if place.step > 0 else 1e-6
    room = place.upper - place.zero
    if np.isfinite(room) and room > 0:
        h = min(h, 0.5 * room)
    moved, used = 0.0, h
    d = np.zeros_like(r0)
    for _ in range(8):
        used = h  # the step d is the change at (the next one may differ if the tries run out)
        d = _change(model, x, j, place, points, rows, r0, used)
        moved = float(np.max(np.abs(d))) if d.size else 0.0
        if moved < 1e-2:
            if np.isfinite(room) and h * 30 > 0.5 * room:
                break
            h *= 30.0
        elif moved > 3.0:
            h /= 10.0
        else:
            break
    return d / used, used, moved


def _basis(base: FitResult, model: Model):
    """An orthonormal basis of the column space of the fit's Jacobian (columns scaled to unit norm,
    numerically dependent ones dropped) and the per-parameter least-squares map, for naming absorbers."""
    J = base.J
    if J.size == 0:
        return np.zeros((J.shape[0], 0)), None, []
    keep, Js, U, s, Vt = column_space(J)
    names_all = np.array(model.layout.names())[np.nonzero(base.active)[0]]
    return U, (Js, U, s, Vt), list(names_all[keep])


def _absorbers(coef_basis, names, s, declared: set[str]) -> list[str]:
    """The (at most two) free parameters whose columns carry most of the absorbed part of s: by name if
    ``declared`` (fitted parameters, effects, sensor corrections; a per-group copy ``<name>[<group>]`` too),
    else "the latent inputs" (a steady point's true input, a command level or knot)."""
    if coef_basis is None:
        return []
    Js, U, sv, Vt = coef_basis
    c = Vt.T @ ((U.T @ s) / sv)
    contrib = np.abs(c) * np.sqrt(np.sum(Js * Js, axis=0))
    order = np.argsort(contrib)[::-1]
    out = []
    for k in order[:2]:
        if contrib[k] > 0.05 * contrib[order[0]]:
            name = names[k]
            out.append(name if name in declared else "the latent inputs")
    return list(dict.fromkeys(out))
