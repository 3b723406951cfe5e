"""A recorded input trace as a latent piecewise-linear signal: errors-in-variables for a time series whose
command is known only by its recording.

The netlist imposes the recording itself (a ``profile`` block whose ``values`` read the data column,
``{csv:, column:}``). Taken as it is, the recording's noise drives the circuit as if it were the true command
and biases the fit. With ``latent: trace`` on the input, the true command is instead a linear spline
through knots (t_j, z_j), j = 1..m:

    u(t) = z_j + (z_{j+1} - z_j) * (t - t_j) / (t_{j+1} - t_j)      for t_j <= t <= t_{j+1}

held at z_1 before t_1 and at z_m after t_m, and the measured column is a noisy reading of it,
u_meas(t_k) = u(t_k) + e_k, e_k ~ N(0, sigma^2). The knot values z_j and the interior knot times t_j are
fitted with the parameters (:mod:`blocks.calibrate.model`: the input's rows r_k = (u(t_k) - u_meas(t_k)) /
sigma count in chi^2 as the outputs' rows do, and the outputs inform the knots too). A knot time moves
between the samples: a step that falls between two samples, or a ramp's corner that the noise hides by a
few samples, is placed by what the outputs saw. Each interior knot time is bounded halfway to its
neighbours' start times, so the knots keep their order.

How many knots, and where they start, is chosen once from the measured column alone (:func:`choose_knots`):
1. split: starting from knots at the first and last sample, add a knot at the sample where it lowers
   chi^2 = sum(((u_meas - u) / sigma)^2) the most (:func:`split_gains`: the projection of the residuals on
   the knot's hat function, its neighbours held), refit the knot values by least squares, and repeat while
   the best knot lowers chi^2 by over ``margin`` (10 + ln n: the acceptance bar of an effect's dBIC);
2. prune: remove the knot whose removal raises chi^2 least, while that is under ``margin`` (a split
   places a knot near a corner; a better placed one may make it unneeded);
3. refine: move each knot, within 10 samples, to the sample where the spline fits best; prune again.
A command of steps, ramps and stops gets a knot at each corner (two for a step: its foot and its top);
a smooth command gets knots as dense as its curvature above the noise asks for. Each knot adds two fitted
parameters, two simulations per Jacobian: a trace that needs more than ``max_knots`` is refused.
"""

from __future__ import annotations

import numpy as np

MAX_KNOTS = 60
"""The most knots a latent trace may take (each adds its value and time to the fitted parameters)."""


def spline_basis(t: np.ndarray, knot_times: np.ndarray) -> np.ndarray:
    """B with B @ z = the linear spline through (knot_times, z) at the times t (held constant outside)."""
    eye = np.eye(len(knot_times))
    return np.column_stack([np.interp(t, knot_times, eye[j]) for j in range(len(knot_times))])


def knot_values(t: np.ndarray, u: np.ndarray, knots: np.ndarray) -> np.ndarray:
    """The least-squares knot values of the spline with knots at the samples ``knots`` (indices into t)."""
    z, *_ = np.linalg.lstsq(spline_basis(t, t[knots]), u, rcond=None)
    return z


def choose_knots(t: np.ndarray, u: np.ndarray, sigma: float, margin: float | None = None,
                 max_knots: int = MAX_KNOTS) -> np.ndarray:
    """Indices of the samples that carry the knots of the latent trace (see the module docstring); raises
    ValueError if more than ``max_knots`` are needed for the spline to follow ``u`` within its noise."""
    t, u = np.asarray(t, dtype=float), np.asarray(u, dtype=float)
    if len(t) < 2:
        raise ValueError("a latent trace needs at least two samples")
    margin = 10.0 + np.log(len(t)) if margin is None else margin
    knots = [0, len(t) - 1]
    while True:
        r = (u - spline_basis(t, t[knots]) @ knot_values(t, u, np.array(knots))) / sigma
        best_gain, best_split = 0.0, None
        for a, b in zip(knots[:-1], knots[1:]):
            if b - a < 2:
                continue
            gain = split_gains(t[a:b + 1] - t[a], r[a:b + 1])
            s = int(np.argmax(gain))
            if gain[s] > best_gain:
                best_gain, best_split = float(gain[s]), (a + 1 + s, b)
        if best_split is None or best_gain <= margin:
            return np.array(prune(t, u, sigma, refine(t, u, prune(t, u, sigma, knots, margin)), margin))
        if len(knots) == max_knots:
            raise ValueError(f"the recording needs more than {max_knots} knots to be followed within its noise "
                             f"(sigma {sigma:g})")
        split, b = best_split
        knots.insert(knots.index(b), split)


def prune(t: np.ndarray, u: np.ndarray, sigma: float, knots: list[int], margin: float) -> list[int]:
    """Knots taken out, the cheapest first, while taking one out raises the chi^2 of the refitted spline by
    less than ``margin`` (the splits place a knot where the spline with its ends held gains most, which may
    leave a few a better placed knot makes unneeded). The first and last sample keep theirs."""
    current = _chi2(t, u, knots) / sigma ** 2
    while len(knots) > 2:
        costs = [(_chi2(t, u, knots[:i] + knots[i + 1:]) / sigma ** 2 - current, i) for i in range(1, len(knots) - 1)]
        cost, i = min(costs)
        if cost >= margin:
            break
        current += cost
        del knots[i]
    return knots


def refine(t: np.ndarray, u: np.ndarray, knots: list[int], window: int = 10, passes: int = 5) -> list[int]:
    """Each interior knot moved, within ``window`` samples and between its neighbours, to the sample where
    the refitted spline fits best (a knot placed by a split sits near a corner, not always on it); repeated
    until no knot moves."""
    knots = list(knots)
    for _ in range(passes):
        moved = False
        for i in range(1, len(knots) - 1):
            low, high = max(knots[i - 1] + 1, knots[i] - window), min(knots[i + 1] - 1, knots[i] + window)
            trials = [(_chi2(t, u, knots[:i] + [k] + knots[i + 1:]), k) for k in range(low, high + 1)]
            best = min(trials)[1]
            if best != knots[i]:
                knots[i], moved = best, True
        if not moved:
            break
    return knots


def _chi2(t: np.ndarray, u: np.ndarray, knots: list[int]) -> float:
    """The sum of squared residuals (unscaled) of the least-squares spline with knots at the samples given."""
    r = u - spline_basis(t, t[knots]) @ knot_values(t, u, np.array(knots))
    return float(r @ r)


def split_gains(tt: np.ndarray, rr: np.ndarray) -> np.ndarray:
    """The drop of chi^2 = rr.rr from a knot added at each interior sample of a segment, its ends held: the
    squared projection (rr.h)^2 / (h.h) of the residuals on the hat function h that rises from 0 at the first
    sample to 1 at the new knot and falls to 0 at the last. tt: the segment's times from its start."""
    left_rt, left_r = np.cumsum(tt * rr), np.cumsum(rr)  # sums over samples 0..s
    left_tt, left_t = np.cumsum(tt * tt), np.cumsum(tt)
    total_rt, total_r, total_tt, total_t = left_rt[-1], left_r[-1], left_tt[-1], left_t[-1]
    n = len(tt)
    count = np.arange(1, n + 1)
    s = np.arange(1, n - 1)  # the interior samples
    ts, tb = tt[s], tt[-1]
    rise = left_rt[s] / ts  # sum over 0..s of (t/ts) r
    fall = (tb * (total_r - left_r[s]) - (total_rt - left_rt[s])) / (tb - ts)  # over s+1..end of (tb-t)/(tb-ts) r
    rise_hh = left_tt[s] / ts ** 2
    right_n = n - count[s]
    fall_hh = (tb * tb * right_n - 2.0 * tb * (total_t - left_t[s]) + (total_tt - left_tt[s])) / (tb - ts) ** 2
    return (rise + fall) ** 2 / (rise_hh + fall_hh)
