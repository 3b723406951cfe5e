"""Cost terms over logged signals (thesis section 4.4, eqs. 4.1, 4.2, 4.7-4.9).

A term reads one logged signal s(t) of a simulation result (SI), optionally minus a reference r(t) (another
logged signal, or a constant), expressed in the term's ``unit`` (``scale`` = SI value of one unit, so an
error in m becomes one in mm before it is squared), over the window t_from <= t <= t_to (the whole run by
default):

- ``ise``     integral of the squared error        J = int (e/scale)^2 dt       [unit^2*s]
- ``max_abs`` largest absolute error               J = max |e/scale|            [unit]
- ``hp_ise``  integral of the square of the signal through a 2nd-order high-pass
                  H(s) = s^2 / (s^2 + 2*zeta*wn*s + wn^2),  J = int (h/scale)^2 dt   [unit^2*s]

with e = s - r. The job's cost is a weighted sum of terms, per load case, combined over the cases
(sum, mean or worst). The thesis's costs are, in these terms (positions in mm, velocities in mm/s,
pressure in Pa):
    C_pos = 50 * int e_pos^2 dt + int e_vel^2 dt   (eq. 4.1) = ise(x - x_ref, mm, weight 50) + ise(v - v_ref, mm/s)
    C_vib = 3e-8 * int p_high^2 dt                 (eq. 4.2) = hp_ise(pA, Pa, weight 3e-8)
    C1 = C_pos, C2 = C_vib, C3 = C_pos + C_vib     (eqs. 4.7-4.9)
The thesis names neither the units of eq. 4.1 nor the high-pass's corner frequency; mm and mm/s give
costs of the size of its Table 4.2 (a few mm of error over 3 s is ~1e3), and the corner is a job setting.

Integrals are trapezoidal over the logged samples. The high-pass is applied to the logged samples
offline: H(s) discretised exactly for an input linear between samples (first-order hold) at the output
step, started in steady state at the first sample (so a constant initial pressure is no step and gives
no output); it needs the logged signal at a uniform step (a ragged grid is interpolated onto one). Its
gain is low by about (wn*dt)^2/12 against the continuous filter -- measured 8.3e-4 at wn = 100 rad/s and
a 1 ms output step, so int h^2 dt is 0.17 % low; it scales with dt^2 (tests/optimise/test_costs.py checks
it against the highpass2 block simulated in the circuit).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

KINDS = ("ise", "max_abs", "hp_ise")


@dataclass(frozen=True)
class Term:
    name: str
    kind: str
    signal: str
    weight: float = 1.0
    reference: str | None = None  # a logged signal
    offset: float = 0.0  # a constant reference (SI), when ``reference`` is None
    scale: float = 1.0  # SI value of one ``unit``
    unit: str = ""  # for reports: the unit the error is expressed in
    wn: float = 0.0  # hp_ise: corner angular frequency [rad/s]
    zeta: float = 0.7071067811865476
    t_from: float | None = None
    t_to: float | None = None

    @property
    def value_unit(self) -> str:
        u = self.unit or "1"
        return u if self.kind == "max_abs" else f"({u})^2*s"


def trapezoid(y: np.ndarray, t: np.ndarray) -> float:
    return float(0.5 * np.sum((y[1:] + y[:-1]) * np.diff(t))) if len(t) > 1 else 0.0


def window(term: Term, t: np.ndarray) -> np.ndarray:
    lo = -np.inf if term.t_from is None else term.t_from
    hi = np.inf if term.t_to is None else term.t_to
    return (t >= lo) & (t <= hi)


def term_signal(term: Term, t: np.ndarray, signals) -> np.ndarray:
    """What the term integrates or maximises, in its unit: the error, or the high-passed signal."""
    s = np.asarray(signals[term.signal], float)
    if term.kind == "hp_ise":
        return highpass(t, s, term.wn, term.zeta) / term.scale
    r = np.asarray(signals[term.reference], float) if term.reference is not None else term.offset
    return (s - r) / term.scale


def evaluate_term(term: Term, t: np.ndarray, signals) -> float:
    """The term's value from time ``t`` and a mapping of logged signals (SI)."""
    with np.errstate(over="ignore", invalid="ignore"):  # a non-finite value fails the evaluation, no warning
        y = term_signal(term, t, signals)
        keep = window(term, t)
        if term.kind == "max_abs":
            return float(np.max(np.abs(y[keep]))) if np.any(keep) else 0.0
        return trapezoid(y[keep] ** 2, t[keep])


def highpass(t: np.ndarray, u: np.ndarray, wn: float, zeta: float) -> np.ndarray:
    """u through s^2/(s^2 + 2 zeta wn s + wn^2), first-order hold, steady state at u[0]."""
    from scipy.signal import lfilter

    if len(t) < 2:
        return np.zeros_like(u)
    steps = np.diff(t)
    dt = float(np.median(steps))
    uniform = np.allclose(steps, dt, rtol=1e-6, atol=0.0)
    tu, uu = t, u
    if not uniform:
        n = max(2, int(round((t[-1] - t[0]) / dt)) + 1)
        tu = np.linspace(t[0], t[-1], n)
        uu = np.interp(tu, t, u)
        dt = float(tu[1] - tu[0])
    b, a, zi_unit = _discrete_highpass(round(wn, 12), round(zeta, 12), round(dt, 15))
    y, _ = lfilter(b, a, uu, zi=zi_unit * uu[0])
    return y if uniform else np.interp(t, tu, y)


@lru_cache(maxsize=64)
def _discrete_highpass(wn: float, zeta: float, dt: float):
    from scipy.signal import cont2discrete, lfilter_zi

    num, den = [1.0, 0.0, 0.0], [1.0, 2.0 * zeta * wn, wn * wn]
    bd, ad, _ = cont2discrete((num, den), dt, method="foh")
    b = np.atleast_1d(np.squeeze(bd))
    a = np.atleast_1d(np.squeeze(ad))
    return b, a, lfilter_zi(b, a)


def combine(values: list[float], how: str) -> float:
    """Load cases' costs into one: sum, mean or worst (the largest)."""
    if how == "sum":
        return float(np.sum(values))
    if how == "mean":
        return float(np.mean(values))
    if how == "worst":
        return float(np.max(values))
    raise ValueError(f"unknown combination '{how}'")
