"""A steady motion: the circuit at rest but for positions that keep moving (a cylinder's stroke at a
constant speed), the operating point of ``vphs linearise --equilibrium`` when there is no rest point.

The compiled equilibrium (:mod:`blocks.solve.equilibrium`) asks every rate to vanish, but those of states
that act on nothing. A position that acts on the circuit cannot rest while its body moves: a cylinder's
stroke sets its chambers' volumes, so dp/dt = beta/V(x) * sum(q) depends on x. Here the travelling
positions P are the states j whose rate is a rigid body's speed times a constant, f_j = c*w_k (row j of
the Jacobian has one nonzero entry, in a speed's column: a cylinder's stroke, a sensor's angle; not a
spool's position, whose speed is the spool's own state), or depends on no state (the integral of a
command: a servo's position reference), which move at the guess (f_j != 0) and which act on another state
(one that acts on nothing the compiled equilibrium lets integrate already). They are held at the guess's
values and the others solved for rest:

    f_i(t, x) = 0  for every i not in P,   x_j (j in P) held

by MINPACK's hybrid Newton method (scipy.optimize.root) on the states divided by their nominal
magnitudes s_i and the rates by the same s_i. The solution counts when each such rate is what an offset of
REST * s_i from rest makes, |f_i| <= REST * s_i * max(1, |df_i/dx_i|) (the criterion of
:func:`blocks.linearise.at_rest`), and the held positions still move there, |f_j| > REST * s_j (else it is
a rest point that the compiled Newton method could not isolate, such as oil shut in two chambers, where
the pressures' level is arbitrary: no steady motion is claimed).

The rest stays at rest as the positions move when they act on it only through what vanishes at rest (a
chamber's volume multiplies the net flow into it, zero in steady motion) or when their actions cancel as
they move together (a servo's reference and its load's position, whose difference is the error); a spring
or an end stop on a position, or an error still settling, makes the point a snapshot of a motion that
changes, which ``vphs linearise`` says (``A[rest, P] @ f_P``, how the others' rates change as the
positions move, is then over 1e-3 of its terms).
"""

from __future__ import annotations

import numpy as np
import scipy.optimize

from blocks.linearise import REST


def travelling(rhs, x: np.ndarray, nominal: np.ndarray, speeds: np.ndarray) -> list[int]:
    """The states that integrate a rigid body's speed (``speeds`` marks those states), or an input, move at
    ``x``, and act on another state (module docstring)."""
    f0 = rhs(x)
    depends = np.zeros((x.size, x.size), dtype=bool)  # depends[i, k]: state k moves rate i
    for k in range(x.size):
        h = 1e-6 * max(abs(x[k]), nominal[k])
        xp, xm = x.copy(), x.copy()
        xp[k] += h
        xm[k] -= h
        depends[:, k] = rhs(xp) != rhs(xm)
    found = []
    for j in range(x.size):
        on = np.flatnonzero(depends[j])
        integrates = on.size == 0 or (on.size == 1 and on[0] != j and speeds[on[0]])
        acts = np.delete(depends[:, j], j).any()
        if f0[j] != 0.0 and integrates and acts:
            found.append(j)
    return found


def steady_motion(rhs, x_guess: np.ndarray, nominal: np.ndarray,
                  speeds: np.ndarray) -> tuple[np.ndarray, list[int]] | None:
    """(x, moving): the others at rest with the travelling positions ``moving`` held at the guess's values,
    or None when there are no such positions or no such rest is found. ``rhs(x)`` gives f(t, x); ``speeds``
    marks the rigid bodies' speed states."""
    x_guess = np.asarray(x_guess, dtype=float)
    moving = travelling(rhs, x_guess, nominal, speeds)
    if not moving:
        return None
    rest = np.array([i for i in range(x_guess.size) if i not in moving], dtype=int)
    scale = nominal[rest]

    def state(z: np.ndarray) -> np.ndarray:
        x = x_guess.copy()
        x[rest] = z * scale
        return x

    def residual(z: np.ndarray) -> np.ndarray:
        return rhs(state(z))[rest] / scale

    with np.errstate(all="ignore"):
        solution = scipy.optimize.root(residual, x_guess[rest] / scale, method="hybr",
                                       options={"xtol": 1e-13, "maxfev": 200 * (rest.size + 1)})
    x = state(solution.x)
    f = rhs(x)
    if not np.all(np.isfinite(f)):
        return None
    if np.any(np.abs(f[moving]) <= REST * nominal[moving]):
        return None  # a rest point after all, which Newton could not isolate (oil shut in): not a motion
    for i in rest:
        h = 1e-6 * max(abs(x[i]), nominal[i])
        xp, xm = x.copy(), x.copy()
        xp[i] += h
        xm[i] -= h
        slope = (rhs(xp)[i] - rhs(xm)[i]) / (2.0 * h)
        if abs(f[i]) > REST * nominal[i] * max(1.0, abs(slope)):
            return None
    return x, moving
