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

States that act on nothing. A state whose column of J is exactly zero off the diagonal (judged at the
guess) moves no other state: a friction state whose force coefficient is zero, a filter that only feeds a
logged signal. (Exactly zero: a threshold relative to the fastest rate would also catch real couplings, since
a line's flow state behind a tiny inertance makes rates of 1e12/s.) The others do not depend on it, so they
are solved with it held where the guess has it (its row replaced by dx_j = 0); then each such state is
solved on its own row, f_j(x_j) = 0 with the rest held, by a scalar Newton iteration (steps accepted while
|f_j| falls). With rho_j = max_k |J_jk| s_k / s_j (k != j; 1/s) how fast its rate follows the others: one
whose own slope d_j = df_j/dx_j is below 1e-10 rho_j (the Dahl state of a spool at rest, which rests
anywhere; an integrator) is "neutral": it stays where it is if its rate is what the others' tolerance
leaves, |f_j| / s_j <= tol * rho_j, and otherwise there is no equilibrium (an integrator of a constant).
Stability: the eigenvalues of the rest, and the slopes d_j of the states that act on nothing and are not
neutral (a neutral one is left out: it rests anywhere, and nothing depends on it). Last, at the result
each such state must still act on nothing and a Newton step of the rest must be below tol, else status 2;
a solve that ends in status 1 or 2 with such states held is made again with every state in Newton's
system (a coupling can be zero at the guess only: a product a*b at a = b = 0).
t is held fixed: an equilibrium of a circuit whose inputs are constant from t on.

Returns (status, x, y, J, iterations, sinks, growth_sinks):
    0  converged: x the equilibrium, y the logged signals there, J the Jacobian at x
    1  singular Jacobian (no usable pivot): no isolated equilibrium near the guess
    2  no convergence within ``max_iter`` iterations, or no step lowers the merit
    3  a non-finite value in f or x
    4  converged in the other states, but a state that acts on nothing has no rest point
sinks marks the states that act on nothing; growth_sinks is the largest d_j among them that counts for
stability (-inf if none does).
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
def _sink_states(J, sink):
    """Mark the states whose column of J is exactly zero off the diagonal (they act on no other state)."""
    n = J.shape[0]
    for j in range(n):
        sink[j] = True
        for i in range(n):
            if i != j and J[i, j] != 0.0:
                sink[j] = False
                break


@njit(cache=True)
def _row_rate(J, scale, j):
    """rho_j = max_k |J_jk| s_k / s_j over k != j: how fast state j's rate follows the others (1/s)."""
    rho = 0.0
    for k in range(J.shape[0]):
        if k != j:
            rho = max(rho, abs(J[j, k]) * scale[k] / scale[j])
    return rho


@njit(cache=True)
def _own_rate_slope(rhs, t, x, theta, scale, j, fj, xp, fp):
    """d f_j / d x_j by a forward difference (the step of _dense_jacobian)."""
    h = np.sqrt(np.finfo(np.float64).eps) * max(abs(x[j]), scale[j])
    if x[j] < 0.0:
        h = -h
    for i in range(x.shape[0]):
        xp[i] = x[i]
    xp[j] = x[j] + h
    _ros_f(rhs, t, xp, theta, fp)
    return (fp[j] - fj) / (xp[j] - x[j])


@njit(cache=True)
def _solve_sink(rhs, t, x, theta, scale, j, f, rho, tol, max_iter, xp, fp):
    """The scalar Newton iteration on f_j(x_j) = 0, the other states held, rho the row's rate rho_j
    (module docstring).
    Returns (status, d_j at the end): 0 solved (or neutral and at rest), 2 not within max_iter steps,
    4 no rest point (neutral but moving, or no step lowers |f_j|)."""
    d = 0.0
    for _ in range(max_iter):
        d = _own_rate_slope(rhs, t, x, theta, scale, j, f[j], xp, fp)
        if not abs(d) > 1e-10 * rho:  # neutral: rests wherever it is, if it is at rest here
            return (0 if abs(f[j]) / scale[j] <= tol * rho else 4), d
        step = -f[j] / d
        if abs(step) / scale[j] <= tol:
            x[j] += step
            _ros_f(rhs, t, x, theta, f)
            return 0, d
        a = 1.0
        while a >= 1.0 / 1024.0:
            for i in range(x.shape[0]):
                xp[i] = x[i]
            xp[j] = x[j] + a * step
            _ros_f(rhs, t, xp, theta, fp)
            if np.isfinite(fp[j]) and abs(fp[j]) < abs(f[j]):
                break
            a *= 0.5
        if a < 1.0 / 1024.0:
            return 4, d
        x[j] = xp[j]
        for i in range(x.shape[0]):
            f[i] = fp[i]
    return 2, d


@njit(cache=True)
def _newton_step(J, f, sink, A, piv, dx):
    """dx = -J^-1 f with the rows and columns of the states that act on nothing replaced by dx_j = 0; A and
    piv keep the factors. False if J (so reduced) is singular."""
    n = J.shape[0]
    for i in range(n):
        for j in range(n):
            A[i, j] = 0.0 if sink[i] or sink[j] else J[i, j]
        A[i, i] = 1.0 if sink[i] else A[i, i]
        dx[i] = 0.0 if sink[i] else -f[i]
    if _ros_lu_factor(A, piv) >= 0:
        return False
    _ros_lu_solve(A, piv, dx)
    return True


@njit(cache=True)
def newton(rhs, observe, x_guess, theta, t, scale, tol, max_iter, n_obs):
    """Equilibrium of x' = rhs(t, x, theta) near x_guess; see the module docstring."""
    out = _newton(rhs, observe, x_guess, theta, t, scale, tol, max_iter, n_obs, True)
    if (out[0] == 1 or out[0] == 2) and np.any(out[5]):
        # a coupling that is zero only at the guess made a state look like one that acts on nothing
        return _newton(rhs, observe, x_guess, theta, t, scale, tol, max_iter, n_obs, False)
    return out


@njit(cache=True)
def _newton(rhs, observe, x_guess, theta, t, scale, tol, max_iter, n_obs, use_sinks):
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
    sink = np.zeros(n, dtype=np.bool_)
    growth_sinks = -np.inf
    _ros_f(rhs, t, x, theta, f)
    if not (_all_finite(x) and _all_finite(f)):
        return 3, x, y, J, 0, sink, growth_sinks
    status = 2
    iterations = 0
    for it in range(max_iter):
        iterations = it + 1
        _dense_jacobian(rhs, t, x, f, theta, scale, J, xp, fp)
        if not _all_finite(J.ravel()):
            return 3, x, y, J, iterations, sink, growth_sinks
        if it == 0 and use_sinks:
            _sink_states(J, sink)
        if not _newton_step(J, f, sink, A, piv, dx):
            return 1, x, y, J, iterations, sink, growth_sinks
        if not _all_finite(dx):
            return 3, x, y, J, iterations, sink, growth_sinks
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
                    dxb[i] = 0.0 if sink[i] else -fn[i]
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
        if np.any(sink):  # their rows' rates rho_j need the Jacobian before they are solved
            _dense_jacobian(rhs, t, x, f, theta, scale, J, xp, fp)
        for j in range(n):
            if sink[j]:
                rho = _row_rate(J, scale, j)
                solved, d = _solve_sink(rhs, t, x, theta, scale, j, f, rho, tol, max_iter, xp, fp)
                if solved != 0:
                    status = solved
                    break
                if abs(d) > 1e-10 * rho:
                    growth_sinks = max(growth_sinks, d)
        _dense_jacobian(rhs, t, x, f, theta, scale, J, xp, fp)
        if status == 0 and np.any(sink):
            for j in range(n):  # each must still act on nothing where it came to rest ...
                for i in range(n):
                    if sink[j] and i != j and J[i, j] != 0.0:
                        status = 2
            # ... and the states solved on their own rows must not have moved the rest
            if status == 0 and not (_newton_step(J, f, sink, A, piv, dx) and _scaled_max(dx, scale) <= tol):
                status = 2
        if status == 0:
            _ros_f(observe, t, x, theta, y)
    return status, x, y, J, iterations, sink, growth_sinks
