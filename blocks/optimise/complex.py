"""The Complex method (Box 1965) as thesis section 4.5 states it, with the Complex-RF refinements.

Notation as in the thesis: k designs y_1..y_k in n variables within the bounds l <= y <= u; f their costs.

1. Population: y_i = l + R_i * (u - l), R_i uniform in [0, 1]^n (Box 1965); k = max(2n, 3) unless set.
2. Each iteration (optional forgetting first, see 6.): j = the worst design (largest cost), b = the best.
   Centroid of the others (eq. 4.3):      y_c = sum_{i != j} y_i / (k - 1)
   Reflection through it (eq. 4.4):       y_new = y_c + alpha * (y_c - y_j),  alpha = 1.3
   y_new replaces y_j and is evaluated.
3. While the new design is still the worst -- f(y_new) >= max_{i != j} f_i (a tie counts as worst) --
   it is moved toward the centroid and the best design (eqs. 4.5, 4.6):
       y_new <- 0.5 * (y_new + eps * y_c + (1 - eps) * y_b)
       eps = (n0 / (n0 + n_rep - 1)) ** ((n0 + n_rep - 1) / n0),   n0 = 4 ("normally 4 or 5")
   with n_rep = 1, 2, ... the number of times in a row the design has been the worst.
   Eq. 4.5 is garbled in the extracted text ("0.5 * |y_j + eps*y_c + (1 + eps)*y_k|"); the form above is
   Krus and Andersson (2003): the weights must sum to 2 for a point that does not depend on where the
   origin is, and at n_rep = 1 (eps = 1) it must be Box's (1965) move half-way to the centroid. As n_rep
   grows eps -> 0 and the design is drawn toward the best one. y_c stays the centroid of step 2 and y_b
   the best design of the complex (it cannot change while the moved design stays the worst).
   At most ``max_retractions`` moves per iteration (30, as J. Andersson's complexrf.m); then the design
   stays in the complex as its worst and the next iteration reflects it again.
4. Bounds: every candidate is clipped into [l, u] after it is computed (the complex never leaves them).
5. Randomisation (Complex-RF, optional, r_fak = 0 by default): each candidate of 2. and 3. gets
       y <- y + r_fak * (u - l) * s * (R - 0.5),  s = max_m (max_i y_im - min_i y_im) / (u_m - l_m)
   before clipping, R uniform in [0, 1]^n and s the complex's normalised spread (the form of Krus and
   Andersson 2003 as written in J. Andersson's complexrf.m and Hopsan's Complex-RF); it keeps the
   complex from collapsing into a subspace.
6. Forgetting (Complex-RF, optional, gamma = 0 by default): at the start of every iteration all costs the
   complex remembers are raised by K_f times their spread,
       f_i <- f_i + (max f - min f) * K_f,   K_f = 1 - (alpha / 2) ** (gamma / k)
   so that old designs age and a freshly evaluated one is preferred (noisy or drifting costs). The
   aged costs choose the worst and best; the true costs are what is reported and checked for convergence.
7. Stops: the budget of evaluations is spent; the spread in parameters s <= tol_x (normalised by the
   bounds); or the spread in cost (f_max - f_min) / |f_min| <= tol_f (f_max - f_min <= tol_f if
   f_min = 0), over the true costs of the complex. Checked before each iteration.

Parallel evaluation (Complex-RFP "task prediction", Braun and Krus): the reflection and the retractions
that would follow it form a sequence that depends only on the complex at the start of the iteration,
as long as each one stays the worst. With ``candidates = c`` the first c of that sequence are evaluated
at once (the batch goes to the workers); the first that is not the worst is accepted, exactly where the
one-at-a-time method would accept it, and the later ones are discarded. The random numbers of an
iteration come from one stream consumed in sequence order, so the accepted designs -- the whole path of
the complex -- are the same for every c, given the seed. The path's evaluations are the ones the
one-at-a-time method (c = 1) makes; only they count against ``max_evaluations``, so that the budget stops
every c at the same point of the path (a batch never asks for more than the budget has left, and the
discarded ones, at most c - 1 a batch, come on top). c thus changes only how many simulations run and
how long a wall-clock iteration takes, never the result. The initial population is evaluated as one batch.

``evaluate(points, info)`` gets a list of points (1-d arrays) and a list of dicts describing them
({"step": "initial" | "reflection" | "retraction", "iteration", "n_rep"}) and returns their costs;
it may evaluate them in parallel. Costs must be finite (a failed simulation is given a penalty cost).
``on_path(used)``, if given, is called after every batch with the number of its first points that are on
the path; the rest were evaluated ahead and are not needed (the caller leaves them out of its result: a
discarded point may cost less than any on the path, and reporting it would make the result depend on c).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

ALPHA = 1.3  # reflection distance (Box 1965; thesis eq. 4.4)


@dataclass
class ComplexSettings:
    points: int | None = None  # k; default max(2n, 3)
    alpha: float = ALPHA
    n0: float = 4.0
    rfak: float = 0.0
    gamma: float = 0.0
    tol_x: float = 1e-4
    tol_f: float = 1e-5
    max_evaluations: int = 500
    max_retractions: int = 30
    candidates: int = 1


@dataclass
class OptimiseResult:
    """What every method returns (coordinates as the method saw them)."""

    x: np.ndarray
    f: float
    evaluations: int  # on the method's path (for the Complex method: without the discarded candidates)
    iterations: int
    reason: str
    extra: dict = field(default_factory=dict)


# ---- the steps, as the thesis writes them (also what the tests check by hand) ----------------------------
def centroid(Y: np.ndarray, j: int) -> np.ndarray:
    """Eq. 4.3: the mean of every design but the j-th."""
    return (Y.sum(axis=0) - Y[j]) / (len(Y) - 1)


def reflect(y_c: np.ndarray, y_j: np.ndarray, alpha: float = ALPHA) -> np.ndarray:
    """Eq. 4.4: y_new = alpha * (y_c - y_j) + y_c."""
    return alpha * (y_c - y_j) + y_c


def epsilon(n0: float, n_rep: int) -> float:
    """Eq. 4.6: eps = (n0 / (n0 + n_rep - 1)) ** ((n0 + n_rep - 1) / n0); 1 at n_rep = 1."""
    m = n0 + n_rep - 1
    return (n0 / m) ** (m / n0)


def retract(y_new: np.ndarray, y_c: np.ndarray, y_best: np.ndarray, eps: float) -> np.ndarray:
    """Eq. 4.5 (reconstructed): y_new <- 0.5 * (y_new + eps * y_c + (1 - eps) * y_best)."""
    return 0.5 * (y_new + eps * y_c + (1.0 - eps) * y_best)


def spread(Y: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> float:
    """The complex's largest extent along any variable, as a fraction of that variable's range."""
    return float(np.max((Y.max(axis=0) - Y.min(axis=0)) / (upper - lower)))


def forgetting_factor(alpha: float, gamma: float, k: int) -> float:
    """K_f = 1 - (alpha/2) ** (gamma/k) (Krus and Andersson 2003); 0 when gamma = 0."""
    return 1.0 - (alpha / 2.0) ** (gamma / k)


def cost_spread(f: np.ndarray) -> float:
    low, high = float(np.min(f)), float(np.max(f))
    return (high - low) / abs(low) if low != 0.0 else high - low


# ---- the method -------------------------------------------------------------------------------------------
def check_settings(s: ComplexSettings, n: int) -> int:
    """The number of points k; ValueError for settings the method cannot run with."""
    k = s.points if s.points is not None else max(2 * n, 3)
    if n < 1:
        raise ValueError("the Complex method needs at least one free parameter")
    if k < n + 1 or k < 2:
        raise ValueError(f"points = {k}: the complex needs at least n + 1 = {n + 1} points")
    if s.max_evaluations < k:
        raise ValueError(f"max_evaluations = {s.max_evaluations} is fewer than the {k} points of the population")
    if not s.alpha > 0 or not s.n0 > 0 or s.rfak < 0 or s.gamma < 0 or s.candidates < 1 or s.max_retractions < 0:
        raise ValueError("alpha and n0 must be positive; rfak, gamma and max_retractions >= 0; candidates >= 1")
    return k


def complex_minimise(evaluate: Callable, lower, upper, settings: ComplexSettings | None = None, seed: int = 0,
                     initial: np.ndarray | None = None, on_path: Callable[[int], None] | None = None) -> OptimiseResult:
    """Minimise with the Complex(-RF) method; see the module docstring. ``initial`` (k x n) replaces the
    random population (for tests and restarts); ``on_path(used)`` hears after each batch how many of its
    points are on the path."""
    on_path = on_path or (lambda used: None)
    s = settings or ComplexSettings()
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    if np.any(~(upper > lower)):
        raise ValueError("every upper bound must be above its lower bound")
    n = len(lower)
    k = check_settings(s, n)
    if initial is not None:
        Y = np.clip(np.array(initial, float), lower, upper)
        k = len(Y)
    else:
        R = np.random.default_rng([seed, 0]).random((k, n))
        Y = lower + R * (upper - lower)
    f_true = np.asarray(evaluate(list(Y), [{"step": "initial", "iteration": 0, "n_rep": 0}] * k), float)
    on_path(k)
    evaluations = k  # on the path
    f_aged = f_true.copy()
    kf = forgetting_factor(s.alpha, s.gamma, k)
    iteration, reason = 0, "budget"
    discarded = 0
    while True:
        if evaluations >= s.max_evaluations:
            reason = "budget"
            break
        if spread(Y, lower, upper) <= s.tol_x:
            reason = "parameters converged"
            break
        if cost_spread(f_true) <= s.tol_f:
            reason = "cost converged"
            break
        iteration += 1
        if kf > 0.0:
            f_aged = f_aged + (f_aged.max() - f_aged.min()) * kf
        j, b = int(np.argmax(f_aged)), int(np.argmin(f_aged))
        y_c = centroid(Y, j)
        others_worst = float(np.max(np.delete(f_aged, j)))
        sequence = _candidates(Y, j, b, y_c, lower, upper, s, np.random.default_rng([seed, 1, iteration]))
        accepted = False
        tried = 0  # candidates of this iteration walked through (the one-at-a-time path)
        while not accepted and tried <= s.max_retractions and evaluations < s.max_evaluations:
            size = min(s.candidates, s.max_retractions + 1 - tried, s.max_evaluations - evaluations)
            batch = [next(sequence) for _ in range(size)]
            costs = evaluate([y for y, _ in batch],
                             [{"step": "reflection" if rep == 0 else "retraction", "iteration": iteration, "n_rep": rep}
                              for _, rep in batch])
            used = 0
            for (y, _), cost in zip(batch, costs):
                used += 1
                Y[j], f_true[j], f_aged[j] = y, cost, cost
                if cost < others_worst:
                    accepted = True
                    break
            tried += used
            evaluations += used
            discarded += size - used  # evaluated ahead, not needed
            on_path(used)
    best = int(np.argmin(f_true))
    return OptimiseResult(Y[best].copy(), float(f_true[best]), evaluations, iteration, reason,
                          {"points": k, "complex": Y.copy(), "costs": f_true.copy(), "discarded": discarded})


def _candidates(Y, j, b, y_c, lower, upper, s: ComplexSettings, rng):
    """The reflection (n_rep = 0), then the retractions n_rep = 1, 2, ..., each computed as if every earlier
    one had stayed the worst; yields (point, n_rep). Random draws are taken in this order only."""
    Y = Y.copy()
    y = reflect(y_c, Y[j], s.alpha)
    rep = 0
    while True:
        if s.rfak > 0.0:
            y = y + s.rfak * (upper - lower) * spread(Y, lower, upper) * (rng.random(len(y)) - 0.5)
        y = np.clip(y, lower, upper)
        yield y, rep
        Y[j] = y
        rep += 1
        y = retract(y, y_c, Y[b], epsilon(s.n0, rep))
