"""Compiled equilibrium solver: a damped Newton iteration on the circuit's right-hand side, f(t, x) = 0.

Like :mod:`blocks.solve.rosenbrock` it is compiled once (numba, cached on disk) and receives a circuit's
rhs and observer as ``cfunc``s, so a circuit compiles only its own rhs.

Method
------
With the Jacobian J = df/dx by forward differences (every column, dense: the circuits that need an
equilibrium are small; perturbation dx_j = sqrt(eps) * max(|x_j|, s_j) away from zero, s_j the state's
nominal magnitude), each iteration solves

    J dx = -f(t, x)

(own LU with partial pivoting) and takes the longest step x + a dx, a in {1, 1/2, ..., 1/1024}, that passes
Deuflhard's natural monotonicity test: the simplified Newton step at the trial point, J dxb = -f(t, x + a dx)
with the same factors, is shorter than the step itself, |dxb| <= (1 - a/4) |dx|, in the scaled max-norm
|v| = max_j |v_j| / s_j. Unlike a merit ||f||, this test does not depend on how the rows of f are scaled:
a circuit's rates range from a pressure in a millilitre (1e12 Pa/s per l/min) to a spool position, and a
merit dominated by the stiffest rows rejects good steps (measured on the calibration netlists: 9 failures
in 369 solves with the test, every one of the 369 with an Armijo test on ||f_i/s_i||). It has converged when
a full Newton step is below ``tol`` in every state, |dx| <= tol; that last step is taken.
t is held fixed: an equilibrium of a circuit whose inputs are constant from t on.

Returns (status, x, y, J, iterations):
    0  converged: x the equilibrium, y the logged signals there, J the Jacobian at x
    1  singular Jacobian (no usable pivot): no isolated equilibrium near the guess
    2  no convergence within ``max_iter`` iterations, or no step lowers the merit
    3  a non-finite value in f or x
Whether the equilibrium is stable (every eigenvalue of J with a negative real part), and whether it is the
one a run would reach, the caller decides: this module only finds a root.
"""
import numpy as np
from numba import njit

from blocks.solve.rosenbrock import _ros_f, _ros_lu_factor, _ros_lu_solve


@njit(cache=True)
def _scaled_max(v, scale):
    m = 0.0
    for i in range(v.shape[0]):
        m = max(m, abs(v[i]) / scale[i])
    return m


@njit(cache=True)
def _all_finite(v):
    for i in range(v.shape[0]):
        if not np.isfinite(v[i]):
            return False
    return True


@njit(cache=True)
def _dense_jacobian(rhs, t, x, f0, theta, scale, J, xp, fp):
    n = x.shape[0]
    root_eps = np.sqrt(np.finfo(np.float64).eps)
    for j in range(n):
        h = root_eps * max(abs(x[j]), scale[j])
        if x[j] < 0.0:
            h = -h
        for i in range(n):
            xp[i] = x[i]
        xp[j] = x[j] + h
        h = xp[j] - x[j]
        _ros_f(rhs, t, xp, theta, fp)
        for i in range(n):
            J[i, j] = (fp[i] - f0[i]) / h


@njit(cache=True)
def newton(rhs, observe, x_guess, theta, t, scale, tol, max_iter, n_obs):
    """Equilibrium of x' = rhs(t, x, theta) near x_guess; see the module docstring."""
    n = x_guess.shape[0]
    x = x_guess.copy()
    f = np.empty(n)
    J = np.zeros((n, n))
    A = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    dx = np.empty(n)
    dxb = np.empty(n)
    xn = np.empty(n)
    fn = np.empty(n)
    xp = np.empty(n)
    fp = np.empty(n)
    y = np.full(n_obs, np.nan)
    _ros_f(rhs, t, x, theta, f)
    if not (_all_finite(x) and _all_finite(f)):
        return 3, x, y, J, 0
    status = 2
    iterations = 0
    for it in range(max_iter):
        iterations = it + 1
        _dense_jacobian(rhs, t, x, f, theta, scale, J, xp, fp)
        if not _all_finite(J.ravel()):
            return 3, x, y, J, iterations
        for i in range(n):
            for j in range(n):
                A[i, j] = J[i, j]
            dx[i] = -f[i]
        if _ros_lu_factor(A, piv) >= 0:
            return 1, x, y, J, iterations
        _ros_lu_solve(A, piv, dx)
        if not _all_finite(dx):
            return 3, x, y, J, iterations
        full = _scaled_max(dx, scale)
        if full <= tol:  # converged: take the last (tiny) step
            for i in range(n):
                x[i] += dx[i]
            status = 0
            break
        a = 1.0
        accepted = False
        while a >= 1.0 / 1024.0:
            for i in range(n):
                xn[i] = x[i] + a * dx[i]
            _ros_f(rhs, t, xn, theta, fn)
            if _all_finite(fn):
                for i in range(n):
                    dxb[i] = -fn[i]
                _ros_lu_solve(A, piv, dxb)  # the simplified Newton step at xn (same factors)
                if _all_finite(dxb) and _scaled_max(dxb, scale) <= (1.0 - 0.25 * a) * full:
                    accepted = True
                    break
            a *= 0.5
        if not accepted:
            break
        for i in range(n):
            x[i] = xn[i]
            f[i] = fn[i]
    if status == 0:
        _ros_f(rhs, t, x, theta, f)
        _dense_jacobian(rhs, t, x, f, theta, scale, J, xp, fp)
        _ros_f(observe, t, x, theta, y)
    return status, x, y, J, iterations
