"""Table interpolation shared by the signal blocks (numba-compiled, callable from Python too).

Breakpoint vectors must be strictly increasing; :func:`check_breakpoints` says so at build time, the
compiled kernels assume it and do not check again in the hot path.
"""

import math

import numpy as np
from numba import njit


@njit(cache=True)
def find_interval(x, xs):
    """Index i of the segment [xs[i], xs[i+1]] that holds x, clamped to 0..n-2 (n = len(xs) >= 2).

    Binary search, O(log n): long profiles read from CSV files cost no more than short ones.
    """
    n = xs.shape[0]
    if x <= xs[0]:
        return 0
    if x >= xs[n - 1]:
        return n - 2
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xs[mid] <= x:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def interp1(x, xs, ys, extrapolate):
    """Linear interpolation of (xs, ys) at x; outside [xs[0], xs[-1]] the end value is held, or the end
    segment is extended when ``extrapolate`` is true. A one-point table is a constant."""
    n = xs.shape[0]
    if n == 1:
        return ys[0]
    if not extrapolate:
        if x <= xs[0]:
            return ys[0]
        if x >= xs[n - 1]:
            return ys[n - 1]
    i = find_interval(x, xs)
    s = (x - xs[i]) / (xs[i + 1] - xs[i])
    return ys[i] + s * (ys[i + 1] - ys[i])


@njit(cache=True)
def _clamped_bracket(x, xs):
    """(i, i1, s): x lies at fraction s in [0, 1] between xs[i] and xs[i1], x clamped to the table."""
    n = xs.shape[0]
    if n == 1 or x <= xs[0]:
        return 0, 0, 0.0
    if x >= xs[n - 1]:
        return n - 1, n - 1, 0.0
    i = find_interval(x, xs)
    return i, i + 1, (x - xs[i]) / (xs[i + 1] - xs[i])


@njit(cache=True)
def interp2(u1, u2, xs, ys, zs):
    """Bilinear interpolation of z(x, y), z stored row-major: z(xs[i], ys[j]) = zs[i*len(ys) + j].
    Inputs outside the table are clamped to its edges."""
    ny = ys.shape[0]
    i, i1, sx = _clamped_bracket(u1, xs)
    j, j1, sy = _clamped_bracket(u2, ys)
    z00 = zs[i * ny + j]
    z01 = zs[i * ny + j1]
    z10 = zs[i1 * ny + j]
    z11 = zs[i1 * ny + j1]
    return (1.0 - sx) * ((1.0 - sy) * z00 + sy * z01) + sx * ((1.0 - sy) * z10 + sy * z11)


# ---- build-time checks (plain Python; called through the blocks' ``check_values``) ----
def check_breakpoints(name: str, xs) -> str | None:
    """None if ``xs`` is a non-empty, finite, strictly increasing vector, else what is wrong."""
    xs = np.asarray(xs, dtype=float)
    if xs.ndim != 1 or xs.size == 0:
        return f"{name} must be a non-empty vector"
    if not all(math.isfinite(v) for v in xs):
        return f"{name} must be finite"
    if xs.size > 1 and not np.all(np.diff(xs) > 0.0):
        k = int(np.argmin(np.diff(xs) > 0.0))
        return f"{name} must be strictly increasing ({name}[{k}] = {xs[k]:g}, {name}[{k + 1}] = {xs[k + 1]:g})"
    return None


def check_length(name: str, values, expected: int, why: str) -> str | None:
    """None if ``values`` has ``expected`` entries, else what is wrong."""
    n = len(values)
    return None if n == expected else f"{name} has {n} entries, {why} needs {expected}"
