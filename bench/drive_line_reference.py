"""Hand-written reference model of the drive-line benchmark circuit.

Everything is in SI units (Pa, m, m^3, s, rad, N*m, kg*m^2).

Circuit
-------
Supply pS = 207 bar, tank pT = 0.  Oil: rho = 850 kg/m^3, bulk modulus
beta = 8e8 Pa.

4/3 servo valve.  The spool position x (dimensionless, -1 ... 1) follows the
command u through a 2nd-order lag omega_n^2 / (s^2 + 2 zeta omega_n s +
omega_n^2) with omega_n = 52.6 rad/s, zeta = 0.9.  States x and v = dx/dt:

    dx/dt = v
    dv/dt = omega_n^2 (u - x) - 2 zeta omega_n v

Metering edges (A0 = 125 mm^2, deadband 0.02, Cd = 0.7):

    A_PA = A_BT = A0 * max(0,  x - 0.02) / 0.98     (open for x > 0)
    A_PB = A_AT = A0 * max(0, -x - 0.02) / 0.98     (open for x < 0)

(this is A0 * max(0, |x| - 0.02)/0.98 on the edges that are open for the sign
of x, zero on the other two).  Regularised turbulent orifice, flow counted
positive in the direction of the edge name (from its first to its second
port), dp = p_first - p_second, dpt = 1 bar:

    q(A, dp) = Cd * A * sqrt(2/rho) * dp / (dp^2 + dpt^2)^(1/4)

    q_PA = q(A_PA, pS - pA)      flow P -> A
    q_BT = q(A_BT, pB - pT)      flow B -> T
    q_PB = q(A_PB, pS - pB)      flow P -> B
    q_AT = q(A_AT, pA - pT)      flow A -> T

(the orifice is odd in dp, so reverse flow, e.g. A -> P when pA > pS, comes
out with a negative sign automatically.)

Motor: two 30 cm^3/rev motors in parallel, D = 2 * 30e-6 / (2 pi) m^3/rad.
Flow through the motor from line A to line B (positive when the motor turns
forward, omega > 0, or when pA > pB pushes oil through the leakage path,
k_leak = 1e-12 m^3/(s Pa)):

    q_m = D * omega + k_leak * (pA - pB)            flow A -> B

Line volumes (V each; both V = 1e-3 m^3 and V = 2e-5 m^3 are run).  Mass
balance of each line, inflow positive:

    dpA/dt = beta/V * ( q_PA - q_AT - q_m )     in: P->A;      out: A->T, A->motor->B
    dpB/dt = beta/V * ( q_m + q_PB - q_BT )     in: motor, P->B; out: B->T

NOTE on signs: the task brief wrote dpB/dt = beta/V (q_m - q_BT - q_PB).
q_PB (flow P -> B) enters line B, so it must carry a PLUS sign; with a minus
sign line B would be drained when it is connected to the 207 bar supply.  The
model uses the physically correct +q_PB.

Load: hydraulic torque tau_h = D (pA - pB) drives omega positive.  Inertia

    J = 2*0.0034 + 0.085 + 7500 * 0.075^2 / 39^2   kg m^2

viscous b = 0.01 N m s/rad, and Coulomb friction 10 % of the magnitude of
the hydraulic torque, smoothed with tanh(omega/0.1) and opposing motion:

    tau_c = 0.1 * |D (pA - pB)| * tanh(omega / 0.1)
    J domega/dt = D (pA - pB) - b omega - tau_c
    dtheta/dt  = omega

Bridge position x_b = theta * r with r = 0.075/39 m/rad (theta positive ->
bridge moves forward).

Controller.  Reference speed v_ref: ramp 0 -> 0.4 m/s over 0 ... 0.5 s, hold
0.4 m/s to 2.5 s, ramp to 0 at 3 s (0 afterwards).  Reference position
x_ref = integral of v_ref (closed form, piecewise quadratic, x_ref(3) = 1.0 m):

    t <= 0.5        : v = 0.8 t,               x = 0.4 t^2
    0.5 < t <= 2.5  : v = 0.4,                 x = 0.1 + 0.4 (t - 0.5)
    2.5 < t <= 3    : v = 0.4 - 0.8 (t - 2.5), x = 0.9 + 0.4 tau - 0.4 tau^2, tau = t-2.5
    t > 3           : v = 0,                   x = 1.0

    u = clip(0.4 * v_ref + 4.0 * (x_ref - x_b), -1, 1)

State vector y = [x_spool, v_spool, pA, pB, omega, theta] (6 states).
Initial state: at rest, pA = pB = 20 bar.  Simulated 0 ... 3 s, output on a
1 ms grid (3001 points).

Solver settings (common to every hand-written variant, also used by the
benchmark for bdsim where the solver accepts them):

    rtol = 1e-6
    atol = ATOL = 1e-6 * typical state scale
         = [1e-6 (spool, scale 1), 1e-4 (1/s, scale 100),
            20 Pa (pA, scale 207 bar), 20 Pa (pB),
            2e-4 rad/s (scale ~200 rad/s), 5e-4 rad (scale ~520 rad = 1 m)]

The Radau reference uses rtol = 1e-10 and atol = ATOL * 1e-4.

`rhs` and `jac` are numba @njit(cache=True) functions; `jac` is the
analytic Jacobian, which the variants can use via `use_jac=True` (the
default for the reference solution).
"""

from __future__ import annotations

import math
import time

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp

# ---------------------------------------------------------------------------
# parameter vector layout
# ---------------------------------------------------------------------------
I_PS, I_PT, I_RHO, I_BETA, I_V = 0, 1, 2, 3, 4
I_A0, I_CD, I_DPT, I_XDB = 5, 6, 7, 8
I_WN, I_ZETA = 9, 10
I_D, I_LEAK, I_J, I_B, I_FC, I_WC, I_R = 11, 12, 13, 14, 15, 16, 17
I_KFF, I_KP, I_VMAX, I_T1, I_T2, I_T3 = 18, 19, 20, 21, 22, 23
N_PARAMS = 24

T_END = 3.0
T_EVAL = np.linspace(0.0, T_END, 3001)  # 1 ms grid
P0 = 20e5
Y0 = np.array([0.0, 0.0, P0, P0, 0.0, 0.0])
STATE_NAMES = ("x_spool", "v_spool", "pA", "pB", "omega", "theta")

RTOL = 1e-6
ATOL = np.array([1e-6, 1e-4, 20.0, 20.0, 2e-4, 5e-4])
REF_RTOL = 1e-10
REF_ATOL = ATOL * 1e-4

R_BRIDGE = 0.075 / 39.0  # bridge travel per motor radian [m/rad]


def make_params(V: float) -> np.ndarray:
    """Parameter array for line volume V [m^3] (see module docstring)."""
    p = np.zeros(N_PARAMS)
    p[I_PS] = 207e5
    p[I_PT] = 0.0
    p[I_RHO] = 850.0
    p[I_BETA] = 8e8
    p[I_V] = V
    p[I_A0] = 125e-6
    p[I_CD] = 0.7
    p[I_DPT] = 1e5
    p[I_XDB] = 0.02
    p[I_WN] = 52.6
    p[I_ZETA] = 0.9
    p[I_D] = 2 * 30e-6 / (2 * math.pi)
    p[I_LEAK] = 1e-12
    p[I_J] = 2 * 0.0034 + 0.085 + 7500 * 0.075**2 / 39**2
    p[I_B] = 0.01
    p[I_FC] = 0.1
    p[I_WC] = 0.1
    p[I_R] = R_BRIDGE
    p[I_KFF] = 0.4
    p[I_KP] = 4.0
    p[I_VMAX] = 0.4
    p[I_T1] = 0.5
    p[I_T2] = 2.5
    p[I_T3] = 3.0
    return p


# ---------------------------------------------------------------------------
# reference trajectory (closed form)
# ---------------------------------------------------------------------------
@njit(cache=True)
def ref_traj(t, vmax, t1, t2, t3):
    """(v_ref, x_ref) for the trapezoidal speed profile."""
    a1 = vmax / t1
    a3 = vmax / (t3 - t2)
    x1 = 0.5 * vmax * t1
    x2 = x1 + vmax * (t2 - t1)
    if t <= 0.0:
        return 0.0, 0.0
    elif t <= t1:
        return a1 * t, 0.5 * a1 * t * t
    elif t <= t2:
        return vmax, x1 + vmax * (t - t1)
    elif t <= t3:
        tau = t - t2
        return vmax - a3 * tau, x2 + vmax * tau - 0.5 * a3 * tau * tau
    else:
        return 0.0, x2 + 0.5 * vmax * (t3 - t2)


def reference_profile(t, V: float = 1e-3):
    """Vectorised (v_ref, x_ref) for plotting / checks."""
    p = make_params(V)
    t = np.atleast_1d(t)
    out = np.array([ref_traj(float(ti), p[I_VMAX], p[I_T1], p[I_T2], p[I_T3]) for ti in t])
    return out[:, 0], out[:, 1]


# ---------------------------------------------------------------------------
# right-hand side and Jacobian
# ---------------------------------------------------------------------------
@njit(cache=True)
def _orifice(k, dp, dpt2):
    """q = k dp / (dp^2+dpt^2)^(1/4) and dq/ddp."""
    s = dp * dp + dpt2
    r = s ** -0.25
    q = k * dp * r
    dq = k * (0.5 * dp * dp + dpt2) * r / s
    return q, dq


@njit(cache=True)
def rhs(t, y, p):
    xs = y[0]
    vs = y[1]
    pA = y[2]
    pB = y[3]
    w = y[4]
    th = y[5]

    pS = p[I_PS]
    pT = p[I_PT]
    dpt2 = p[I_DPT] * p[I_DPT]
    kA = p[I_CD] * p[I_A0] * math.sqrt(2.0 / p[I_RHO]) / (1.0 - p[I_XDB])
    xdb = p[I_XDB]
    D = p[I_D]

    # controller
    vref, xref = ref_traj(t, p[I_VMAX], p[I_T1], p[I_T2], p[I_T3])
    u = p[I_KFF] * vref + p[I_KP] * (xref - th * p[I_R])
    if u > 1.0:
        u = 1.0
    elif u < -1.0:
        u = -1.0

    # valve
    op = xs - xdb
    on = -xs - xdb
    kpos = kA * op if op > 0.0 else 0.0
    kneg = kA * on if on > 0.0 else 0.0
    d = pS - pA
    q_PA = kpos * d / (d * d + dpt2) ** 0.25
    d = pB - pT
    q_BT = kpos * d / (d * d + dpt2) ** 0.25
    d = pS - pB
    q_PB = kneg * d / (d * d + dpt2) ** 0.25
    d = pA - pT
    q_AT = kneg * d / (d * d + dpt2) ** 0.25

    # motor
    dpl = pA - pB
    q_m = D * w + p[I_LEAK] * dpl
    tau_h = D * dpl
    tau_c = p[I_FC] * abs(tau_h) * math.tanh(w / p[I_WC])

    c = p[I_BETA] / p[I_V]
    wn = p[I_WN]
    dy = np.empty(6)
    dy[0] = vs
    dy[1] = wn * wn * (u - xs) - 2.0 * p[I_ZETA] * wn * vs
    dy[2] = c * (q_PA - q_AT - q_m)
    dy[3] = c * (q_m + q_PB - q_BT)
    dy[4] = (tau_h - p[I_B] * w - tau_c) / p[I_J]
    dy[5] = w
    return dy


@njit(cache=True)
def jac(t, y, p):
    xs = y[0]
    pA = y[2]
    pB = y[3]
    w = y[4]
    th = y[5]

    pS = p[I_PS]
    pT = p[I_PT]
    dpt2 = p[I_DPT] * p[I_DPT]
    kA = p[I_CD] * p[I_A0] * math.sqrt(2.0 / p[I_RHO]) / (1.0 - p[I_XDB])
    xdb = p[I_XDB]
    D = p[I_D]
    c = p[I_BETA] / p[I_V]
    wn = p[I_WN]
    leak = p[I_LEAK]

    vref, xref = ref_traj(t, p[I_VMAX], p[I_T1], p[I_T2], p[I_T3])
    u = p[I_KFF] * vref + p[I_KP] * (xref - th * p[I_R])
    du_dth = -p[I_KP] * p[I_R] if (u > -1.0 and u < 1.0) else 0.0

    op = xs - xdb
    on = -xs - xdb
    kpos = kA * op if op > 0.0 else 0.0
    kneg = kA * on if on > 0.0 else 0.0
    dkpos = kA if op > 0.0 else 0.0   # d kpos / dx
    dkneg = -kA if on > 0.0 else 0.0  # d kneg / dx

    q1, g_PA = _orifice(1.0, pS - pA, dpt2)   # unit-k flow and slope
    q2, g_BT = _orifice(1.0, pB - pT, dpt2)
    q3, g_PB = _orifice(1.0, pS - pB, dpt2)
    q4, g_AT = _orifice(1.0, pA - pT, dpt2)

    J = np.zeros((6, 6))
    J[0, 1] = 1.0
    J[1, 0] = -wn * wn
    J[1, 1] = -2.0 * p[I_ZETA] * wn
    J[1, 5] = wn * wn * du_dth

    # dpA/dt = c (kpos q1 - kneg q4 - D w - leak (pA-pB))
    J[2, 0] = c * (dkpos * q1 - dkneg * q4)
    J[2, 2] = c * (-kpos * g_PA - kneg * g_AT - leak)
    J[2, 3] = c * leak
    J[2, 4] = -c * D
    # dpB/dt = c (D w + leak (pA-pB) + kneg q3 - kpos q2)
    J[3, 0] = c * (dkneg * q3 - dkpos * q2)
    J[3, 2] = c * leak
    J[3, 3] = c * (-leak - kneg * g_PB - kpos * g_BT)
    J[3, 4] = c * D

    dpl = pA - pB
    th_w = math.tanh(w / p[I_WC])
    sgn = 1.0 if dpl > 0.0 else (-1.0 if dpl < 0.0 else 0.0)
    dtc_ddp = p[I_FC] * D * sgn * th_w
    invJ = 1.0 / p[I_J]
    J[4, 2] = (D - dtc_ddp) * invJ
    J[4, 3] = (-D + dtc_ddp) * invJ
    J[4, 4] = (-p[I_B] - p[I_FC] * abs(D * dpl) * (1.0 - th_w * th_w) / p[I_WC]) * invJ
    J[5, 4] = 1.0
    return J


def warmup() -> None:
    """Compile (or load from cache) the numba functions."""
    p = make_params(1e-3)
    rhs(0.1, Y0, p)
    jac(0.1, Y0, p)


# ---------------------------------------------------------------------------
# solvers
# ---------------------------------------------------------------------------
def solve_handwritten(V: float, method: str = "LSODA", use_jac: bool = False,
                      rtol: float = RTOL, atol=None):
    """solve_ivp with the numba rhs; returns (t, y) with y shape (6, 3001)."""
    if method not in ("LSODA", "BDF", "Radau"):
        raise ValueError(f"unsupported method {method!r}")
    p = make_params(V)
    sol = solve_ivp(rhs, (0.0, T_END), Y0.copy(), method=method, t_eval=T_EVAL,
                    rtol=rtol, atol=ATOL if atol is None else atol,
                    jac=jac if use_jac else None, args=(p,))
    if not sol.success:
        raise RuntimeError(f"{method} failed: {sol.message}")
    return sol.t, sol.y


def reference(V: float):
    """Accurate solution: Radau, rtol 1e-10, atol = ATOL*1e-4, analytic Jacobian."""
    return solve_handwritten(V, "Radau", use_jac=True, rtol=REF_RTOL, atol=REF_ATOL)


def bridge_position(y) -> np.ndarray:
    return y[5] * R_BRIDGE


if __name__ == "__main__":
    warmup()
    for V in (1e-3, 2e-5):
        t0 = time.perf_counter()
        t, y = reference(V)
        dt = time.perf_counter() - t0
        vref, xref = reference_profile(t, V)
        xb = bridge_position(y)
        print(f"V={V:g}: ref {dt:.2f}s  xb(3)={xb[-1]:.5f} m  "
              f"max|xref-xb|={1e3*np.max(np.abs(xref-xb)):.2f} mm  "
              f"pA [{y[2].min()/1e5:.1f},{y[2].max()/1e5:.1f}] bar  "
              f"pB [{y[3].min()/1e5:.1f},{y[3].max()/1e5:.1f}] bar  "
              f"x [{y[0].min():.3f},{y[0].max():.3f}]")
