"""Compiled stiff integrator: Rodas4P2, an L-stable, stiffly accurate Rosenbrock method.

Compiled once (numba, cached on disk) for every circuit: a circuit's generated module supplies its
right-hand side and its observer as numba ``cfunc``s of :data:`RHS_SIGNATURE`, which ``integrate``
receives as first-class function arguments and calls through their C pointers. So a new circuit compiles
only its own small rhs, not the integrator, and the integrator's cache is shared by all circuits.

Method
------
Rodas4P2: G. Steinebach, "Improvement of Rosenbrock-Wanner method RODASP", in
S. Reis, M. Arnold (eds.), Progress in Differential-Algebraic Equations II, Springer 2020.
It has the structure of Hairer & Wanner's RODAS/Rodas4 (Solving ODEs II, Sec. VI.4) with
new coefficients chosen so that the method and its dense output keep their order on the
Prothero-Robinson test problem x' = lam (x - g(t)) + g'(t), i.e. on stiff components driven
by time-dependent inputs, where Rodas4 drops to order ~1 (measured here with lam = -1e3,
t in [0, 10], rtol 1e-6, atol 1e-9: Rodas4 631 steps, Rodas4P2 31). Coefficient values as in
OrdinaryDiffEq.jl (lib/OrdinaryDiffEqRosenbrock/src/rosenbrock_tableaus.jl, Rodas4P2Tableau).

Order 4, embedded order 3, 6 stages, gamma = 1/4, L-stable and stiffly accurate, with an
order-3 continuous extension. With J = df/dx(t_n, x_n) and f_t = df/dt(t_n, x_n) (both by
finite differences), each stage solves the linear system

    (I/(h*gamma) - J) k_i = f(t_n + c_i h, x_n + sum_{j<i} a_ij k_j)
                            + (1/h) sum_{j<i} C_ij k_j + h d_i f_t ,   i = 1..6

(c_5 = c_6 = 1, d_5 = d_6 = 0) with one LU factorisation of (I/(h*gamma) - J) per step
(own partial-pivot LU), so the method is linearly implicit: no Newton iteration. Stiff
accuracy (a_6j = a_5j, a_65 = 1, b = a_6 + e_6) gives

    x_5 = x_n + a51 k1 + a52 k2 + a53 k3 + a54 k4
    x_6 = x_5 + k5                      (embedded order-3 solution)
    x_{n+1} = x_6 + k6                  (order-4 solution)

so the local error estimate is simply k6. Dense output on the step, s in [0, 1]:

    x(t_n + s h) = (1-s) x_n + s (x_{n+1} + (1-s)(D1 + s D2)),
    D1 = sum_j h2j k_j,  D2 = sum_j h3j k_j   (j = 1..5)

x_min/x_max are taken over the accepted step end points and the interior extrema of this
cubic, so (up to rounding) x_min <= every logged sample X[k] and x_max >= every X[k].

Error control
-------------
    err = sqrt( (1/n) sum_i ( k6_i / (atol_i + rtol*max(|x_n,i|, |x_{n+1},i|)) )^2 )

A step is accepted if err <= 1. New step h_new = h * clip(0.9 err^(-1/4), 0.2, 6), taking the
smaller of that and Gustafsson's predictive (PI) value after an accepted step, as in RODAS;
no growth right after a rejection. A trial step whose stages, new state or derivative at
the new state are not finite is rejected and h is divided by 4.

Stops: a step never crosses a time of ``t_stops`` (sorted; those outside (t_out[0], t_out[-1]) are
ignored): one that would is shortened to end on it (its last stages, c = 1, evaluated just before it, as
for the last step when t_out[-1] is a stop),
and the next starts from there with the step the controller had proposed before the shortening (or
less, as it says). These are the times an input jumps or kinks: a step is as long as the error it sees
allows, and a pulse shorter than a step falls between its stages unseen (a 5 ms flow pulse in a 5 s run
at rest gave 0 bar instead of 6.5). Fixed steps end on them too: a stop between two points of the grid
t0 + k*fixed_h adds a step to it, and the grid goes on after it (a flow step 0.5 s into a run at
1 ms, 0.5 a rounding off the grid, was 1.1e-3 of its end pressure off the closed form, now 1e-12).

Jacobian: forward differences, perturbation dx_j = sqrt(eps) * max(|x_j|, atol_j/rtol),
with the sign of x_j (moves away from zero, never across it). Columns are grouped with a
colouring of the sparsity pattern (columns of one group have disjoint row patterns), one
rhs call per group. Known weakness (measured, left as specified): when the Jacobian has
large entries that cancel (e.g. a 2x2 block with eigenvalues -1 and -1e6 that is not
diagonal), the forward-difference round-off perturbs the slow eigenvalue and the step size
control pays for it (rtol 1e-6, atol 1e-10, t in [0, 5]: 225 step attempts; 91 with
central differences at eps^(1/3), which cost one more rhs call per group).

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
With fixed_h > 0 nothing but finiteness is checked: x' = x^2 from x0 = 1 over [0, 2] with
fixed_h = 0.01 returns status 0 and x = 5e74 (the singularity at t = 1 is stepped over).
Raises ValueError for malformed arguments: atol/jac_groups/jac_pattern not sized n,
t_out not sorted, a negative group, or a colouring whose groups share a row.
Pass writable C-contiguous arrays of one dtype each: a read-only array (e.g. a broadcast
view) is a new numba signature and triggers a second compilation.
"""
import numpy as np
from numba import njit, types

RHS_SIGNATURE = types.void(
    types.float64,
    types.CPointer(types.float64), types.intp,
    types.CPointer(types.float64), types.intp,
    types.CPointer(types.float64), types.intp,
)
"""C signature of a circuit's rhs and observe: f(t, x, n, theta, m, out, k) (pointers with lengths)."""


@njit(cache=True)
def _ros_f(fn, t, x, theta, out):
    """Call a compiled circuit function (a numba cfunc of RHS_SIGNATURE) on arrays."""
    fn(t, x.ctypes, x.shape[0], theta.ctypes, theta.shape[0], out.ctypes, out.shape[0])


# ---------------------------------------------------------------------------------------
# Rodas4P2 integrator (vphs blocks/solve/rosenbrock.py). Coefficients: G. Steinebach,
# "Improvement of Rosenbrock-Wanner method RODASP", in: Progress in Differential-Algebraic
# Equations II, Springer 2020; values as in OrdinaryDiffEq.jl (OrdinaryDiffEqRosenbrock,
# rosenbrock_tableaus.jl, Rodas4P2Tableau).
# ---------------------------------------------------------------------------------------
_ROS_GAMMA = 0.25

_ROS_A21 = 3.0
_ROS_A31 = 0.906377755268814
_ROS_A32 = -0.189707390391685
_ROS_A41 = 3.758617027739064
_ROS_A42 = 1.161741776019525
_ROS_A43 = -0.849258085312803
_ROS_A51 = 7.089566927282776
_ROS_A52 = 4.573591406461604
_ROS_A53 = -8.423496976860259
_ROS_A54 = -0.959280113459775

_ROS_C21 = -12.0
_ROS_C31 = -6.354581592719008
_ROS_C32 = 0.338972550544623
_ROS_C41 = -8.575016317114033
_ROS_C42 = -7.606483992117508
_ROS_C43 = 12.224997650124820
_ROS_C51 = -5.888975457523102
_ROS_C52 = -8.157396617841821
_ROS_C53 = 24.805546872612922
_ROS_C54 = 12.790401512796979
_ROS_C61 = -4.408651676063871
_ROS_C62 = -6.692003137674639
_ROS_C63 = 24.625568527593117
_ROS_C64 = 16.627521966636085
_ROS_C65 = -5.714285714285718

_ROS_C2 = 0.75
_ROS_C3 = 0.321448134013046
_ROS_C4 = 0.519745732277726

_ROS_D1 = 0.25
_ROS_D2 = -0.5
_ROS_D3 = -0.189532918363016
_ROS_D4 = 0.085612108792769

# dense output; note: an older OrdinaryDiffEq.jl tableau file has h24, h32, h34, h35 with
# the opposite sign, which makes the interpolant only first-order accurate (measured).
_ROS_H21 = -5.323528268423303
_ROS_H22 = -10.042123754867493
_ROS_H23 = 17.175254928256965
_ROS_H24 = -5.079931171878093
_ROS_H25 = -0.016185991706112
_ROS_H31 = 6.984505741529879
_ROS_H32 = 6.914061169603662
_ROS_H33 = -0.849178943070653
_ROS_H34 = 18.104410789349338
_ROS_H35 = -3.516963011559032

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
def _ros_jacobian(rhs, t, x, f0, theta, atol, rtol, col_ptr, row_idx, grp_ptr, grp_cols, J, xp, fp):
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
        _ros_f(rhs, t, xp, theta, fp)
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
def _ros_dfdt(rhs, t, x, f0, theta, fx, fp):
    """Forward difference df/dt into fx (exactly 0 for autonomous rhs). One rhs call."""
    delt = np.sqrt(_ROS_EPS * max(1e-5, abs(t)))
    tp = t + delt
    delt = tp - t
    _ros_f(rhs, tp, x, theta, fp)
    for i in range(x.shape[0]):
        fx[i] = (fp[i] - f0[i]) / delt
    return 1


@njit(cache=True)
def _ros_stages(rhs, t, h, t_end, x, f0, fx, M, piv, theta, ks, ytmp, ftmp, xnew):
    """One Rodas4 step with the factorised iteration matrix M. Writes the stage vectors
    into ks[0..5] (ks[5] is the error estimate) and the new state into xnew. Stages 5 and 6
    (c = 1) evaluate the rhs at t_end: t + h, or just before it for a step ending on a stop
    (the inputs' values on the step, not those they jump to there).
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
    _ros_f(rhs, t + _ROS_C2 * h, ytmp, theta, ftmp)
    for i in range(n):
        k2[i] = ftmp[i] + ih * (_ROS_C21 * k1[i]) + h * _ROS_D2 * fx[i]
    _ros_lu_solve(M, piv, k2)
    # stage 3
    for i in range(n):
        ytmp[i] = x[i] + _ROS_A31 * k1[i] + _ROS_A32 * k2[i]
    _ros_f(rhs, t + _ROS_C3 * h, ytmp, theta, ftmp)
    for i in range(n):
        k3[i] = ftmp[i] + ih * (_ROS_C31 * k1[i] + _ROS_C32 * k2[i]) + h * _ROS_D3 * fx[i]
    _ros_lu_solve(M, piv, k3)
    # stage 4
    for i in range(n):
        ytmp[i] = x[i] + _ROS_A41 * k1[i] + _ROS_A42 * k2[i] + _ROS_A43 * k3[i]
    _ros_f(rhs, t + _ROS_C4 * h, ytmp, theta, ftmp)
    for i in range(n):
        k4[i] = (ftmp[i] + ih * (_ROS_C41 * k1[i] + _ROS_C42 * k2[i] + _ROS_C43 * k3[i])
                 + h * _ROS_D4 * fx[i])
    _ros_lu_solve(M, piv, k4)
    # stage 5 (c5 = 1, d5 = 0)
    for i in range(n):
        ytmp[i] = x[i] + _ROS_A51 * k1[i] + _ROS_A52 * k2[i] + _ROS_A53 * k3[i] + _ROS_A54 * k4[i]
    _ros_f(rhs, t_end, ytmp, theta, ftmp)
    for i in range(n):
        k5[i] = ftmp[i] + ih * (_ROS_C51 * k1[i] + _ROS_C52 * k2[i] + _ROS_C53 * k3[i]
                                + _ROS_C54 * k4[i])
    _ros_lu_solve(M, piv, k5)
    # stage 6 (c6 = 1, d6 = 0): evaluated at the embedded solution x5 + k5
    for i in range(n):
        ytmp[i] = ytmp[i] + k5[i]
    _ros_f(rhs, t_end, ytmp, theta, ftmp)
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
def _ros_initial_step(rhs, t0, x, f0, theta, atol, rtol, span, hmax, xt, ft):
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
    _ros_f(rhs, t0 + h0, xt, theta, ft)
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
def _ros_sparsity(jac_pattern, jac_groups, n_groups):
    """Pattern as compressed columns (col_ptr, row_idx) and the groups as lists of
    columns (grp_ptr, grp_cols)."""
    n = jac_pattern.shape[0]
    for j in range(n):
        if jac_groups[j] < 0:
            raise ValueError("integrate: jac_groups must be >= 0")
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
    # the colouring must be valid: columns of one group may not share a row
    owner = np.full(n, -1, dtype=np.int64)
    for g in range(ng):
        for jj in range(grp_ptr[g], grp_ptr[g + 1]):
            j = grp_cols[jj]
            for r in range(col_ptr[j], col_ptr[j + 1]):
                i = row_idx[r]
                if owner[i] == g:
                    raise ValueError("integrate: jac_groups is not a valid colouring of "
                                     "jac_pattern (two columns of one group share a row)")
                owner[i] = g
    return col_ptr, row_idx, grp_ptr, grp_cols


@njit(cache=True)
def integrate(rhs, observe, x0, theta, t_out, t_stops, rtol, atol, h0, h_max, max_steps, fixed_h,
              jac_pattern, jac_groups, n_groups, n_obs):
    """Integrate x' = rhs(t, x, theta) from t_out[0] to t_out[-1] with Rodas4P2.

    Returns (status, t_reached, x_end, X, Y, x_min, x_max, stats, bad_index); see the
    module docstring of blocks/solve/rosenbrock.py."""
    n = x0.shape[0]
    K = t_out.shape[0]
    if atol.shape[0] != n or jac_groups.shape[0] != n:
        raise ValueError("integrate: atol and jac_groups must have one entry per state")
    if jac_pattern.shape[0] != n or jac_pattern.shape[1] != n:
        raise ValueError("integrate: jac_pattern must be n x n")
    for k in range(1, K):
        if not (t_out[k] >= t_out[k - 1]):
            raise ValueError("integrate: t_out must be sorted (non-decreasing)")
    X = np.full((K, n), np.nan)
    Y = np.full((K, n_obs), np.nan)
    stats = np.zeros(5, dtype=np.int64)
    x = np.empty(n)
    for i in range(n):
        x[i] = x0[i]
    x_min = x.copy()
    x_max = x.copy()

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

    status = 0
    bad = -1
    proceed = K > 0
    t = np.nan
    t0 = np.nan
    tf = np.nan
    next_out = 0
    n_rhs = 0
    n_jac = 0
    n_lu = 0
    n_acc = 0
    n_rej = 0

    if proceed:
        t0 = t_out[0]
        tf = t_out[K - 1]
        t = t0
        for i in range(n):
            X[0, i] = x[i]
        _ros_f(observe, t0, x, theta, Y[0])
        next_out = 1
        nf = _ros_first_nonfinite(x)
        if nf >= 0:
            status = 3
            bad = nf
            proceed = False
    if proceed:
        while next_out < K and t_out[next_out] <= t0:
            for i in range(n):
                X[next_out, i] = x[i]
            _ros_f(observe, t_out[next_out], x, theta, Y[next_out])
            next_out += 1
        if next_out >= K:
            proceed = False
    if proceed:
        _ros_f(rhs, t, x, theta, f0)
        n_rhs += 1
        nf = _ros_first_nonfinite(f0)
        if nf >= 0:
            status = 3
            bad = nf
            proceed = False

    if proceed:
        col_ptr, row_idx, grp_ptr, grp_cols = _ros_sparsity(jac_pattern, jac_groups, n_groups)
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
            h, c = _ros_initial_step(rhs, t, x, f0, theta, atol, rtol, span, hmax, ytmp, ftmp)
            n_rhs += c

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
        n_stops = t_stops.shape[0]
        next_stop = 0
        while next_stop < n_stops and t_stops[next_stop] <= t0 + 2.0 * hmin_tf:
            next_stop += 1
        stop_at_tf = False  # the end is a stop too (a sliced run's slice ending on one)
        for i in range(n_stops):
            if abs(t_stops[i] - tf) <= 2.0 * hmin_tf:
                stop_at_tf = True
        h_free = 0.0  # the controller's step before it was shortened to end on a stop (0: not shortened)

        while True:
            if n_steps >= max_steps:
                status = 2
                bad = nonfinite_idx if last_fail_nonfinite else err_idx
                break
            last = False
            if fixed:
                h_free = 0.0
                if i_fixed + 1 >= n_fixed:
                    t_new = tf
                    last = True
                else:
                    t_new = t0 + (i_fixed + 1) * fixed_h
                    if t_new >= tf:
                        t_new = tf
                        last = True
                if next_stop < n_stops and t_stops[next_stop] < tf - 2.0 * hmin_tf \
                        and t_stops[next_stop] <= t_new + 2.0 * hmin_tf:
                    h_free = fixed_h  # ends on the stop: its c = 1 stages just before it
                    if t_stops[next_stop] < t_new - 2.0 * hmin_tf:
                        t_new = t_stops[next_stop]  # a stop between grid points: the grid goes on after it
                        last = False
                h = t_new - t
            else:
                if h > hmax:
                    h = hmax
                h_free = 0.0
                if t + h >= tf - 2.0 * hmin_tf:
                    t_new = tf
                    last = True
                else:
                    t_new = t + h
                if next_stop < n_stops and t_stops[next_stop] < tf - 2.0 * hmin_tf \
                        and t_new >= t_stops[next_stop] - 2.0 * hmin_tf:
                    h_free = h
                    t_new = t_stops[next_stop]
                    last = False
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
                n_rhs += _ros_jacobian(rhs, t, x, f0, theta, atol, rtol, col_ptr, row_idx,
                                       grp_ptr, grp_cols, J, ytmp, ftmp)
                n_rhs += _ros_dfdt(rhs, t, x, f0, theta, fx, ftmp)
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
                t_end = np.nextafter(t_new, -np.inf) if h_free > 0.0 or (last and stop_at_tf) else t + h
                n_rhs += _ros_stages(rhs, t, h, t_end, x, f0, fx, M, piv, theta, ks, ytmp, ftmp, xnew)
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
                _ros_f(rhs, t_new, xnew, theta, fnew)
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
                    _ros_f(observe, t_out[next_out], X[next_out], theta, Y[next_out])
                    next_out += 1
                _ros_update_extrema(x, xnew, dd1, dd2, x_min, x_max)
                for i in range(n):
                    x[i] = xnew[i]
                    f0[i] = fnew[i]
                t = t_new
                n_acc += 1
                if last:
                    break
                while next_stop < n_stops and t_stops[next_stop] <= t + 2.0 * hmin_tf:
                    next_stop += 1
                need_jac = True
                if fixed:
                    if t >= t0 + (i_fixed + 1) * fixed_h - 2.0 * hmin_tf:
                        i_fixed += 1
                else:
                    errc = max(err, 1e-10)
                    fac = _ROS_SAFE * errc ** -0.25
                    if hacc > 0.0:
                        # Gustafsson's predictive controller, as in RODAS
                        facgus = _ROS_SAFE * (h / hacc) * (erracc / (errc * errc)) ** 0.25
                        fac = min(fac, facgus)
                    fac = min(_ROS_FACMAX, max(_ROS_FACMIN, fac))
                    if rejected_last:
                        fac = min(fac, 1.0)
                    hacc = h
                    erracc = max(1e-2, err)
                    h = h * fac
                    if h_free > 0.0 and fac >= 1.0 and h < h_free:
                        h = h_free  # a step shortened to end on a stop does not shrink the next
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
    return status, t, x, X, Y, x_min, x_max, stats, bad
