"""Compiled stiff integrator: Rodas4, an L-stable, stiffly accurate Rosenbrock method.

This file is a *template*. The engine generates, for each circuit, a module that
defines ``rhs(t, x, theta, dx)`` and ``observe(t, x, theta, y)`` as ``@njit(cache=True)``
functions and then pastes in verbatim everything below the ``# --- template ---`` line
(see ``blocks/solve/template.py``). The integrator refers to ``rhs``/``observe`` as module
globals, so numba can cache the whole module on disk. Everything above the marker only
exists so that this file imports on its own. All template names start with ``_ros``
(apart from ``integrate``); generated code must not define names with that prefix.

Method
------
Rodas4 (Hairer & Wanner, *Solving Ordinary Differential Equations II*, 2nd ed.,
Sec. VI.4, the code RODAS, coefficient set METH=1 of ``rodas.f``; numerical values as
reproduced in OrdinaryDiffEq.jl ``src/tableaus/rosenbrock_tableaus.jl``, ``Rodas4Tableau``).
Order 4, embedded order 3, 6 stages, gamma = 1/4, L-stable and stiffly accurate, with an
order-3 continuous extension. With J = df/dx(t_n, x_n) (finite differences) and
f_t = df/dt(t_n, x_n) (finite difference), each stage solves the linear system

    (I/(h*gamma) - J) k_i = f(t_n + c_i h, x_n + sum_{j<i} a_ij k_j)
                            + (1/h) sum_{j<i} C_ij k_j + h d_i f_t ,   i = 1..6

with one LU factorisation of (I/(h*gamma) - J) per step (own partial-pivot LU), so
the method is linearly implicit: no Newton iteration. Stiff accuracy gives
(a_6j = a_5j, a_65 = 1, b = a_6 + e_6):

    x_5 = x_n + a51 k1 + a52 k2 + a53 k3 + a54 k4
    x_6 = x_5 + k5                      (embedded order-3 solution)
    x_{n+1} = x_6 + k6                  (order-4 solution)

so the local error estimate is simply k6. The dense output on the step, s in [0, 1]:

    x(t_n + s h) = (1-s) x_n + s (x_{n+1} + (1-s)(D1 + s D2)),
    D1 = sum_j h2j k_j,  D2 = sum_j h3j k_j   (j = 1..5)

Error control
-------------
    err = sqrt( (1/n) sum_i ( k6_i / (atol_i + rtol*max(|x_n,i|, |x_{n+1},i|)) )^2 )

A step is accepted if err <= 1. New step h_new = h * clip(0.9 err^(-1/4), 0.2, 6), taking the
smaller of that and Gustafsson's predictive (PI) value after an accepted step, as in RODAS;
no growth right after a rejection. A trial step whose stages, new state or derivative at
the new state are not finite is rejected and h is divided by 4.

Jacobian: forward differences, perturbation dx_j = sqrt(eps) * max(|x_j|, atol_j/rtol),
with the sign of x_j (moves away from zero, never across it). Columns are grouped with a
colouring of the sparsity pattern (columns of one group have disjoint row patterns), one
rhs call per group.

Status codes returned by ``integrate``
--------------------------------------
    0  ok
    1  step size underflow (h < 1e-14 * max(1, |t|))
    2  max_steps exceeded (steps attempted: accepted + rejected)
    3  non-finite value in the state or its derivative (also: a step-size underflow whose
       last rejection was caused by non-finite values, and a singular iteration matrix)
On failure: t_reached/x_end are the last accepted time/state, rows of X/Y for output
times after it are NaN, bad_index is the first state found non-finite (status 3) or the
state with the largest contribution to the last error estimate (status 1/2); else -1.
stats = [n_accepted, n_rejected, n_rhs, n_jac, n_lu].
"""
import numpy as np
from numba import njit


@njit(cache=True)
def rhs(t, x, theta, dx):  # placeholder, the generated module defines the real one
    for i in range(x.shape[0]):
        dx[i] = 0.0


@njit(cache=True)
def observe(t, x, theta, y):  # placeholder, the generated module defines the real one
    for i in range(y.shape[0]):
        y[i] = 0.0


# --- template ---
# ---------------------------------------------------------------------------------------
# Rodas4 integrator (vphs blocks/solve/rosenbrock.py). Coefficients: Hairer & Wanner,
# RODAS (rodas.f, METH=1), values as in OrdinaryDiffEq.jl Rodas4Tableau.
# ---------------------------------------------------------------------------------------
_ROS_GAMMA = 0.25

_ROS_A21 = 1.544
_ROS_A31 = 0.9466785280815826
_ROS_A32 = 0.2557011698983284
_ROS_A41 = 3.314825187068521
_ROS_A42 = 2.896124015972201
_ROS_A43 = 0.9986419139977817
_ROS_A51 = 1.221224509226641
_ROS_A52 = 6.019134481288629
_ROS_A53 = 12.53708332932087
_ROS_A54 = -0.6878860361058950

_ROS_C21 = -5.6688
_ROS_C31 = -2.430093356833875
_ROS_C32 = -0.2063599157091915
_ROS_C41 = -0.1073529058151375
_ROS_C42 = -9.594562251023355
_ROS_C43 = -20.47028614809616
_ROS_C51 = 7.496443313967647
_ROS_C52 = -10.24680431464352
_ROS_C53 = -33.99990352819905
_ROS_C54 = 11.70890893206160
_ROS_C61 = 8.083246795921522
_ROS_C62 = -7.981132988064893
_ROS_C63 = -31.52159432874371
_ROS_C64 = 16.31930543123136
_ROS_C65 = -6.058818238834054

_ROS_C2 = 0.386
_ROS_C3 = 0.21
_ROS_C4 = 0.63

_ROS_D1 = 0.25
_ROS_D2 = -0.1043
_ROS_D3 = 0.1035
_ROS_D4 = -0.03620000000000023

_ROS_H21 = 10.12623508344586
_ROS_H22 = -7.487995877610167
_ROS_H23 = -34.80091861555747
_ROS_H24 = -7.992771707568823
_ROS_H25 = 1.025137723295662
_ROS_H31 = -0.6762803392801253
_ROS_H32 = 6.087714651680015
_ROS_H33 = 16.43084320892478
_ROS_H34 = 24.76722511418386
_ROS_H35 = -6.594389125716872

_ROS_SAFE = 0.9
_ROS_FACMIN = 0.2
_ROS_FACMAX = 6.0
_ROS_SQRT_EPS = 1.4901161193847656e-08
_ROS_EPS = 2.220446049250313e-16


@njit(cache=True)
def _ros_first_nonfinite(v):
    for i in range(v.shape[0]):
        if not np.isfinite(v[i]):
            return i
    return -1


@njit(cache=True)
def _ros_lu_factor(A, piv):
    """In-place LU with partial pivoting (LAPACK-style row interchanges).
    Returns -1 on success, else the column where no usable pivot was found."""
    n = A.shape[0]
    for k in range(n):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, n):
            v = abs(A[i, k])
            if v > amax:
                amax = v
                p = i
        piv[k] = p
        if not (amax > 0.0) or not np.isfinite(amax):
            return k
        if p != k:
            for j in range(n):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
        inv = 1.0 / A[k, k]
        for i in range(k + 1, n):
            lik = A[i, k] * inv
            A[i, k] = lik
            if lik != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= lik * A[k, j]
    return -1


@njit(cache=True)
def _ros_lu_solve(A, piv, b):
    """Solve with the factors from _ros_lu_factor, overwriting b."""
    n = A.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(n):
        s = b[i]
        for j in range(i):
            s -= A[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= A[i, j] * b[j]
        b[i] = s / A[i, i]


@njit(cache=True)
def _ros_err_norm(err, x, xnew, atol, rtol):
    """RMS of err_i / (atol_i + rtol*max(|x_i|, |xnew_i|)); also the index of the largest term."""
    n = err.shape[0]
    s = 0.0
    worst = -1.0
    idx = 0
    for i in range(n):
        sc = atol[i] + rtol * max(abs(x[i]), abs(xnew[i]))
        if sc < 1e-300:
            sc = 1e-300
        r = err[i] / sc
        r2 = r * r
        s += r2
        if r2 > worst:
            worst = r2
            idx = i
    if n == 0:
        return 0.0, -1
    return np.sqrt(s / n), idx


@njit(cache=True)
def _ros_jacobian(t, x, f0, theta, atol, rtol, col_ptr, row_idx, grp_ptr, grp_cols, J, xp, fp):
    """Grouped forward-difference Jacobian into J (entries outside the pattern are 0).
    Returns the number of rhs calls."""
    n = x.shape[0]
    n_groups = grp_ptr.shape[0] - 1
    rfl = max(rtol, 1e-12)
    for i in range(n):
        for j in range(n):
            J[i, j] = 0.0
    for i in range(n):
        xp[i] = x[i]
    calls = 0
    for g in range(n_groups):
        if grp_ptr[g + 1] == grp_ptr[g]:
            continue
        for jj in range(grp_ptr[g], grp_ptr[g + 1]):
            j = grp_cols[jj]
            scale = max(abs(x[j]), atol[j] / rfl)
            if not (scale > 0.0) or not np.isfinite(scale):
                scale = 1.0
            d = _ROS_SQRT_EPS * scale
            if x[j] < 0.0:
                d = -d
            xp[j] = x[j] + d
        rhs(t, xp, theta, fp)
        calls += 1
        for jj in range(grp_ptr[g], grp_ptr[g + 1]):
            j = grp_cols[jj]
            d = xp[j] - x[j]
            for r in range(col_ptr[j], col_ptr[j + 1]):
                i = row_idx[r]
                J[i, j] = (fp[i] - f0[i]) / d
            xp[j] = x[j]
    return calls


@njit(cache=True)
def _ros_dfdt(t, x, f0, theta, fx, fp):
    """Forward difference df/dt into fx (exactly 0 for autonomous rhs). One rhs call."""
    delt = np.sqrt(_ROS_EPS * max(1e-5, abs(t)))
    tp = t + delt
    delt = tp - t
    rhs(tp, x, theta, fp)
    for i in range(x.shape[0]):
        fx[i] = (fp[i] - f0[i]) / delt
    return 1


@njit(cache=True)
def _ros_stages(t, h, x, f0, fx, M, piv, theta, ks, ytmp, ftmp, xnew):
    """One Rodas4 step with the factorised iteration matrix M. Writes the stage vectors
    into ks[0..5] (ks[5] is the error estimate) and the new state into xnew.
    Returns the number of rhs calls (5)."""
    n = x.shape[0]
    ih = 1.0 / h
    k1 = ks[0]
    k2 = ks[1]
    k3 = ks[2]
    k4 = ks[3]
    k5 = ks[4]
    k6 = ks[5]
    # stage 1
    for i in range(n):
        k1[i] = f0[i] + h * _ROS_D1 * fx[i]
    _ros_lu_solve(M, piv, k1)
    # stage 2
    for i in range(n):
        ytmp[i] = x[i] + _ROS_A21 * k1[i]
    rhs(t + _ROS_C2 * h, ytmp, theta, ftmp)
    for i in range(n):
        k2[i] = ftmp[i] + ih * (_ROS_C21 * k1[i]) + h * _ROS_D2 * fx[i]
    _ros_lu_solve(M, piv, k2)
    # stage 3
    for i in range(n):
        ytmp[i] = x[i] + _ROS_A31 * k1[i] + _ROS_A32 * k2[i]
    rhs(t + _ROS_C3 * h, ytmp, theta, ftmp)
    for i in range(n):
        k3[i] = ftmp[i] + ih * (_ROS_C31 * k1[i] + _ROS_C32 * k2[i]) + h * _ROS_D3 * fx[i]
    _ros_lu_solve(M, piv, k3)
    # stage 4
    for i in range(n):
        ytmp[i] = x[i] + _ROS_A41 * k1[i] + _ROS_A42 * k2[i] + _ROS_A43 * k3[i]
    rhs(t + _ROS_C4 * h, ytmp, theta, ftmp)
    for i in range(n):
        k4[i] = (ftmp[i] + ih * (_ROS_C41 * k1[i] + _ROS_C42 * k2[i] + _ROS_C43 * k3[i])
                 + h * _ROS_D4 * fx[i])
    _ros_lu_solve(M, piv, k4)
    # stage 5 (c5 = 1, d5 = 0)
    for i in range(n):
        ytmp[i] = x[i] + _ROS_A51 * k1[i] + _ROS_A52 * k2[i] + _ROS_A53 * k3[i] + _ROS_A54 * k4[i]
    rhs(t + h, ytmp, theta, ftmp)
    for i in range(n):
        k5[i] = ftmp[i] + ih * (_ROS_C51 * k1[i] + _ROS_C52 * k2[i] + _ROS_C53 * k3[i]
                                + _ROS_C54 * k4[i])
    _ros_lu_solve(M, piv, k5)
    # stage 6 (c6 = 1, d6 = 0): evaluated at the embedded solution x5 + k5
    for i in range(n):
        ytmp[i] = ytmp[i] + k5[i]
    rhs(t + h, ytmp, theta, ftmp)
    for i in range(n):
        k6[i] = ftmp[i] + ih * (_ROS_C61 * k1[i] + _ROS_C62 * k2[i] + _ROS_C63 * k3[i]
                                + _ROS_C64 * k4[i] + _ROS_C65 * k5[i])
    _ros_lu_solve(M, piv, k6)
    for i in range(n):
        xnew[i] = ytmp[i] + k6[i]
    return 5


@njit(cache=True)
def _ros_dense_coeffs(ks, d1, d2):
    n = d1.shape[0]
    for i in range(n):
        d1[i] = (_ROS_H21 * ks[0, i] + _ROS_H22 * ks[1, i] + _ROS_H23 * ks[2, i]
                 + _ROS_H24 * ks[3, i] + _ROS_H25 * ks[4, i])
        d2[i] = (_ROS_H31 * ks[0, i] + _ROS_H32 * ks[1, i] + _ROS_H33 * ks[2, i]
                 + _ROS_H34 * ks[3, i] + _ROS_H35 * ks[4, i])


@njit(cache=True)
def _ros_dense_eval(s, x, xnew, d1, d2, out):
    s1 = 1.0 - s
    for i in range(x.shape[0]):
        out[i] = s1 * x[i] + s * (xnew[i] + s1 * (d1[i] + s * d2[i]))


@njit(cache=True)
def _ros_update_extrema(x, xnew, d1, d2, x_min, x_max):
    """Track min/max over the step: both ends and the interior extrema of the cubic
    continuous extension p(s) = (1-s) y0 + s (y1 + (1-s)(a + s b))."""
    for i in range(x.shape[0]):
        y0 = x[i]
        y1 = xnew[i]
        a = d1[i]
        b = d2[i]
        lo = min(y0, y1)
        hi = max(y0, y1)
        # p'(s) = qa s^2 + qb s + qc
        qa = -3.0 * b
        qb = 2.0 * (b - a)
        qc = y1 - y0 + a
        r1 = -1.0
        r2 = -1.0
        if qa != 0.0:
            disc = qb * qb - 4.0 * qa * qc
            if disc >= 0.0:
                sq = np.sqrt(disc)
                q = -0.5 * (qb + sq) if qb >= 0.0 else -0.5 * (qb - sq)
                if q != 0.0:
                    r1 = q / qa
                    r2 = qc / q
                else:
                    r1 = 0.0
        elif qb != 0.0:
            r1 = -qc / qb
        if 0.0 < r1 < 1.0:
            s1 = 1.0 - r1
            v = s1 * y0 + r1 * (y1 + s1 * (a + r1 * b))
            lo = min(lo, v)
            hi = max(hi, v)
        if 0.0 < r2 < 1.0:
            s1 = 1.0 - r2
            v = s1 * y0 + r2 * (y1 + s1 * (a + r2 * b))
            lo = min(lo, v)
            hi = max(hi, v)
        if lo < x_min[i]:
            x_min[i] = lo
        if hi > x_max[i]:
            x_max[i] = hi


@njit(cache=True)
def _ros_initial_step(t0, x, f0, theta, atol, rtol, span, hmax, xt, ft):
    """Hairer's starting-step heuristic (HNW I, Sec. II.4), embedded order 3.
    Returns (h, number of rhs calls)."""
    n = x.shape[0]
    if n == 0:
        return min(span, hmax), 0
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = atol[i] + rtol * abs(x[i])
        if sc < 1e-300:
            sc = 1e-300
        d0 += (x[i] / sc) ** 2
        d1 += (f0[i] / sc) ** 2
    d0 = np.sqrt(d0 / n)
    d1 = np.sqrt(d1 / n)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, span, hmax)
    for i in range(n):
        xt[i] = x[i] + h0 * f0[i]
    rhs(t0 + h0, xt, theta, ft)
    d2 = 0.0
    for i in range(n):
        sc = atol[i] + rtol * abs(x[i])
        if sc < 1e-300:
            sc = 1e-300
        d2 += ((ft[i] - f0[i]) / sc) ** 2
    d2 = np.sqrt(d2 / n) / h0
    if not np.isfinite(d2):
        h = h0
    else:
        dm = max(d1, d2)
        if dm <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / dm) ** 0.25
        h = min(100.0 * h0, h1)
    return min(h, span, hmax), 1


@njit(cache=True)
def _ros_run(x, theta, t_out, rtol, atol, h0, h_max, max_steps, fixed_h,
             jac_pattern, jac_groups, n_groups, X, Y, x_min, x_max, stats):
    """Main loop. x holds x0 on entry and the last accepted state on exit.
    Returns (status, t_reached, bad_index)."""
    n = x.shape[0]
    K = t_out.shape[0]
    t0 = t_out[0]
    tf = t_out[K - 1]
    t = t0

    for i in range(n):
        X[0, i] = x[i]
    observe(t0, x, theta, Y[0])
    nf = _ros_first_nonfinite(x)
    if nf >= 0:
        return 3, t, nf
    next_out = 1
    while next_out < K and t_out[next_out] <= t0:
        for i in range(n):
            X[next_out, i] = x[i]
        observe(t_out[next_out], x, theta, Y[next_out])
        next_out += 1
    if next_out >= K:
        return 0, t, -1

    # sparsity pattern as compressed columns, and the column groups
    col_ptr = np.zeros(n + 1, dtype=np.int64)
    for j in range(n):
        c = 0
        for i in range(n):
            if jac_pattern[i, j]:
                c += 1
        col_ptr[j + 1] = col_ptr[j] + c
    row_idx = np.empty(col_ptr[n], dtype=np.int64)
    for j in range(n):
        p = col_ptr[j]
        for i in range(n):
            if jac_pattern[i, j]:
                row_idx[p] = i
                p += 1
    ng = n_groups
    for j in range(n):
        if jac_groups[j] + 1 > ng:
            ng = jac_groups[j] + 1
    grp_ptr = np.zeros(ng + 1, dtype=np.int64)
    for j in range(n):
        grp_ptr[jac_groups[j] + 1] += 1
    for g in range(ng):
        grp_ptr[g + 1] += grp_ptr[g]
    grp_cols = np.empty(n, dtype=np.int64)
    fill = grp_ptr[:ng].copy()
    for j in range(n):
        g = jac_groups[j]
        grp_cols[fill[g]] = j
        fill[g] += 1

    # work space
    f0 = np.empty(n)
    fnew = np.empty(n)
    fx = np.empty(n)
    J = np.empty((n, n))
    M = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    ks = np.empty((6, n))
    ytmp = np.empty(n)
    ftmp = np.empty(n)
    xnew = np.empty(n)
    dd1 = np.empty(n)
    dd2 = np.empty(n)

    n_rhs = 0
    n_jac = 0
    n_lu = 0
    n_acc = 0
    n_rej = 0

    rhs(t, x, theta, f0)
    n_rhs += 1
    nf = _ros_first_nonfinite(f0)
    if nf >= 0:
        stats[2] = n_rhs
        return 3, t, nf

    span = tf - t0
    hmax = h_max if h_max > 0.0 else np.inf
    fixed = fixed_h > 0.0
    n_fixed = 1
    h = 0.0
    if fixed:
        n_fixed = int(np.ceil(span / fixed_h - 1e-9))
        if n_fixed < 1:
            n_fixed = 1
    elif h0 > 0.0:
        h = min(h0, span, hmax)
    else:
        h, c = _ros_initial_step(t, x, f0, theta, atol, rtol, span, hmax, ytmp, ftmp)
        n_rhs += c

    status = 0
    bad = -1
    n_steps = 0
    i_fixed = 0
    need_jac = True
    rejected_last = False
    last_fail_nonfinite = False
    nonfinite_idx = -1
    err_idx = 0
    err = 0.0
    hacc = 0.0
    erracc = 1.0
    hmin_tf = 1e-14 * max(1.0, abs(tf))

    while True:
        if n_steps >= max_steps:
            status = 2
            bad = nonfinite_idx if last_fail_nonfinite else err_idx
            break
        last = False
        if fixed:
            if i_fixed + 1 >= n_fixed:
                t_new = tf
                last = True
            else:
                t_new = t0 + (i_fixed + 1) * fixed_h
                if t_new >= tf:
                    t_new = tf
                    last = True
            h = t_new - t
        else:
            if h > hmax:
                h = hmax
            if t + h >= tf - 2.0 * hmin_tf:
                t_new = tf
                last = True
            else:
                t_new = t + h
            h = t_new - t
            if not last and h < 1e-14 * max(1.0, abs(t)):
                if last_fail_nonfinite:
                    status = 3
                    bad = nonfinite_idx
                else:
                    status = 1
                    bad = err_idx
                break

        if need_jac:
            n_rhs += _ros_jacobian(t, x, f0, theta, atol, rtol, col_ptr, row_idx,
                                   grp_ptr, grp_cols, J, ytmp, ftmp)
            n_rhs += _ros_dfdt(t, x, f0, theta, fx, ftmp)
            n_jac += 1
            need_jac = False

        fac1 = 1.0 / (h * _ROS_GAMMA)
        for i in range(n):
            for j in range(n):
                M[i, j] = -J[i, j]
            M[i, i] += fac1
        fail_col = _ros_lu_factor(M, piv)
        n_lu += 1
        n_steps += 1

        ok = fail_col < 0
        if ok:
            n_rhs += _ros_stages(t, h, x, f0, fx, M, piv, theta, ks, ytmp, ftmp, xnew)
            nf = _ros_first_nonfinite(xnew)
            if nf >= 0:
                ok = False
                nonfinite_idx = nf
            else:
                err, err_idx = _ros_err_norm(ks[5], x, xnew, atol, rtol)
                if not np.isfinite(err):
                    ok = False
                    nonfinite_idx = _ros_first_nonfinite(ks[5])
        else:
            nonfinite_idx = fail_col

        accept = ok and (fixed or err <= 1.0)
        if accept:
            rhs(t_new, xnew, theta, fnew)
            n_rhs += 1
            nf = _ros_first_nonfinite(fnew)
            if nf >= 0:
                ok = False
                accept = False
                nonfinite_idx = nf

        if accept:
            _ros_dense_coeffs(ks, dd1, dd2)
            while next_out < K and t_out[next_out] <= t_new:
                s = (t_out[next_out] - t) / h
                _ros_dense_eval(s, x, xnew, dd1, dd2, X[next_out])
                observe(t_out[next_out], X[next_out], theta, Y[next_out])
                next_out += 1
            _ros_update_extrema(x, xnew, dd1, dd2, x_min, x_max)
            for i in range(n):
                x[i] = xnew[i]
                f0[i] = fnew[i]
            t = t_new
            n_acc += 1
            if last:
                break
            need_jac = True
            if fixed:
                i_fixed += 1
            else:
                errc = max(err, 1e-10)
                fac = _ROS_SAFE * errc ** -0.25
                if hacc > 0.0:
                    facgus = _ROS_SAFE * (h / hacc) * (erracc / (errc * errc)) ** 0.25
                    fac = min(fac, facgus)
                fac = min(_ROS_FACMAX, max(_ROS_FACMIN, fac))
                if rejected_last:
                    fac = min(fac, 1.0)
                hacc = h
                erracc = max(1e-2, err)
                h = h * fac
            rejected_last = False
            last_fail_nonfinite = False
        else:
            n_rej += 1
            if fixed:
                # no error control in fixed mode: only a non-finite step gets here
                status = 3
                bad = nonfinite_idx
                break
            if not ok:
                h = 0.25 * h
                last_fail_nonfinite = True
            else:
                fac = max(_ROS_FACMIN, _ROS_SAFE * err ** -0.25)
                if n_acc == 0:
                    fac = min(fac, 0.1)
                h = h * fac
                last_fail_nonfinite = False
            rejected_last = True

    stats[0] = n_acc
    stats[1] = n_rej
    stats[2] = n_rhs
    stats[3] = n_jac
    stats[4] = n_lu
    return status, t, bad


@njit(cache=True)
def integrate(x0, theta, t_out, rtol, atol, h0, h_max, max_steps, fixed_h,
              jac_pattern, jac_groups, n_groups, n_obs):
    """Integrate x' = rhs(t, x, theta) from t_out[0] to t_out[-1] with Rodas4.

    Returns (status, t_reached, x_end, X, Y, x_min, x_max, stats, bad_index); see the
    module docstring of blocks/solve/rosenbrock.py."""
    n = x0.shape[0]
    K = t_out.shape[0]
    X = np.full((K, n), np.nan)
    Y = np.full((K, n_obs), np.nan)
    stats = np.zeros(5, dtype=np.int64)
    x = np.empty(n)
    for i in range(n):
        x[i] = x0[i]
    x_min = x.copy()
    x_max = x.copy()
    if K == 0:
        return 0, np.nan, x, X, Y, x_min, x_max, stats, -1
    status, t_reached, bad = _ros_run(x, theta, t_out, rtol, atol, h0, h_max, max_steps,
                                      fixed_h, jac_pattern, jac_groups, n_groups,
                                      X, Y, x_min, x_max, stats)
    return status, t_reached, x, X, Y, x_min, x_max, stats, bad
