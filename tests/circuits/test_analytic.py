"""Tier-2 tests: small circuits, netlist -> Circuit -> solver, against closed-form solutions.

Each netlist lives in ``tests/circuits/netlists/``. Several independent small circuits share one netlist where
that costs nothing in clarity (each numba compile of a new circuit structure takes ~8-15 s on a cold cache).

Tolerances
----------
The compiled Rosenbrock solver (Rodas4P2, order 4) accepts a step when the RMS over the states of its local error estimate, each
state's error divided by ``atol*nominal + rtol*|x|``, is <= 1 (blocks/solve/rosenbrock.py). The netlists here
set rtol = atol = 1e-9 (the drive-line test uses the example's own 1e-6). For one state of magnitude up to
``scale`` and nominal size ``nominal`` (1e5 Pa for a pressure, 1 rad/s for a speed, 1 for a signal) the local
tolerance per step is therefore ``rtol*scale + atol*nominal``. All the systems tested are contracting
(dissipative), so the global error stays within a small multiple of that; the order-3 dense output used for
the output samples and the RMS norm (one state may take sqrt(n) of the budget) add another small factor.
``solver_tol`` allows FACTOR = 100 times the local tolerance. The errors actually measured are 0.005x to 2x of
the local tolerance (down to round-off where the exact solution is a polynomial), so the margin is 50x or
more; a sign error or a factor-2 error in any model (checked explicitly with ``distinct_from``) misses the
simulation by 4 to 7 decades more than the tolerance.
"""

from __future__ import annotations

import math
import re
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq

from blocks.circuit import Circuit
from blocks.errors import SimulationError
from blocks.library.hydraulic.cavitation import cavity_volume

HERE = Path(__file__).parent
NETLISTS = HERE / "netlists"
DRIVE_LINE = HERE.parents[1] / "netlists" / "examples" / "drive_line.yaml"

RTOL = ATOL = 1e-9  # what the netlists in tests/circuits/netlists set (checked in test_netlist_tolerances)
FACTOR = 100.0
P_NOM, W_NOM, S_NOM = 1e5, 1.0, 1.0  # nominal sizes of a pressure, a speed and a signal state


def solver_tol(scale: float, nominal: float, rtol: float = RTOL, atol: float = ATOL) -> float:
    """FACTOR times the solver's local error tolerance for a state of size up to ``scale``."""
    return FACTOR * (rtol * scale + atol * nominal)


@lru_cache(maxsize=None)
def circuit(name: str) -> Circuit:
    return Circuit.from_file(NETLISTS / f"{name}.yaml")


@lru_cache(maxsize=None)
def default_run(name: str):
    return circuit(name).simulate()


def assert_matches(what: str, sim: np.ndarray, exact: np.ndarray, tol: float, distinct_from: dict | None = None):
    """max|sim - exact| <= tol; and every wrong model in ``distinct_from`` misses sim by more than 1000*tol,
    which shows that the comparison can fail (the test would catch that sign or factor error)."""
    err = float(np.max(np.abs(sim - exact)))
    assert err <= tol, f"{what}: max error {err:.3g} exceeds the tolerance {tol:.3g}"
    for label, wrong in (distinct_from or {}).items():
        miss = float(np.max(np.abs(sim - wrong)))
        assert miss > 1000 * tol, f"{what}: the test cannot tell the model from '{label}' ({miss:.3g} vs tol {tol:.3g})"
    return err


def test_netlist_tolerances():
    """The tolerances above assume the netlists' rtol/atol: keep them in step."""
    for name in ("hydraulic_fill", "second_order_step", "mechanical_decay", "actuators"):
        s = circuit(name).settings
        assert (s.solver, s.rtol, s.atol) == ("rodas", RTOL, ATOL), name


# ---------------------------------------------------------------------------------------------------------
# Hydraulic fill: laminar, turbulent, two volumes (netlist hydraulic_fill.yaml)
# ---------------------------------------------------------------------------------------------------------
BETA, RHO = 8e8, 850.0
PS, P0, V = 100e5, 10e5, 1e-3
G_LAM = 1e-11
CD, A_T = 0.7, 5e-7


def test_laminar_fill_is_exponential():
    """V/beta * dp/dt = G*(ps - p), p(0) = p0  =>  p(t) = ps + (p0 - ps)*exp(-t*beta*G/V).

    beta*G/V = 8e8*1e-11/1e-3 = 8 1/s (time constant 125 ms, run for 8 of them). Tolerance: pressures up to
    ps = 100 bar -> solver_tol = 100*(1e-9*1e7 + 1e-9*1e5) Pa = 1.01 Pa (1e-7 of the 90 bar swing). A sign
    error does not fill at all, a factor 2 on G/V or beta moves p by up to 30 bar.
    """
    r = default_run("hydraulic_fill")
    t = r.t
    rate = BETA * G_LAM / V
    exact = PS + (P0 - PS) * np.exp(-rate * t)
    assert_matches("laminar fill", r["pL"], exact, solver_tol(PS, P_NOM), {
        "rate x2": PS + (P0 - PS) * np.exp(-2 * rate * t),
        "rate /2": PS + (P0 - PS) * np.exp(-rate * t / 2),
        "sign of the flow": PS + (P0 - PS) * np.exp(+rate * t),
    })


def regularised_decay(t: np.ndarray, x0: float, k: float, dp_t: float) -> np.ndarray:
    """Exact solution of dx/dt = -k*x/(x^2 + dp_t^2)^(1/4), x(0) = x0 > 0 (x = the pressure drop across a
    regularised turbulent orifice that empties or fills a volume; k = (beta/V)*Cd*A*sqrt(2/rho)).

    With w = (x^2 + d^2)^(1/4), c = sqrt(d), d = dp_t, the integral of (x^2 + d^2)^(1/4)/x dx is
        F(x) = 2w + (c/2)*ln((w - c)/(w + c)) - c*atan(w/c)
    (substitute x^2 = w^4 - c^4: the integrand becomes 2w^4/(w^4 - c^4) dw = 2 + 2c^4/(w^4 - c^4) dw, and
    partial fractions give the log and atan terms; differentiate F to check). So k*t = F(x0) - F(x), exact,
    inverted here for x(t) by bisection in ln x. For d -> 0, F -> 2*sqrt(x): the square-root law.
    w - c is evaluated as x^2/((w + c)(w^2 + c^2)) (no cancellation for x << d).
    """
    c = math.sqrt(dp_t)

    def F(x: float) -> float:
        w = (x * x + dp_t * dp_t) ** 0.25
        log_ratio = 2.0 * math.log(x) - math.log((w + c) ** 2 * (w * w + c * c))
        return 2.0 * w + 0.5 * c * log_ratio - c * math.atan(w / c)

    f0 = F(x0)
    lo = math.log(1e-300)
    out = np.empty_like(t)
    for i, ti in enumerate(t):
        target = f0 - k * ti
        if ti == 0.0:
            out[i] = x0
        elif F(1e-300) >= target:
            out[i] = 0.0  # below 1e-300 Pa
        else:
            u = brentq(lambda u: F(math.exp(u)) - target, lo, math.log(x0), xtol=1e-14, rtol=1e-15)
            out[i] = math.exp(u)
    return out


def test_turbulent_fill_square_root_law():
    """The same fill through a turbulent orifice with dp_t = 1 Pa (the block's lower bound):
        dp/dt = k*(ps - p)/((ps - p)^2 + dp_t^2)^(1/4),   k = (beta/V)*Cd*A*sqrt(2/rho) = 13582 Pa^0.5/s.
    For dp_t -> 0 (square-root law) x = ps - p obeys dx/dt = -k*sqrt(x), so
        p(t) = ps - (sqrt(ps - p0) - k*t/2)^2   until t* = 2*sqrt(ps - p0)/k = 0.442 s, then p = ps.

    Bound on the regularisation: (x^2 + d^2)^(1/4) - sqrt(x) <= d^2/(4 x^(3/2)) (concavity of y^(1/4)), so the
    regularised solution reaches a level x later than the square-root law by at most d^2/(6 k x^(3/2)), and
    at the same time t it lies above it by at most 0 <= x_reg - x_sqrt <= d^2/(6 x_sqrt(t)). On the window
    x_sqrt >= 1 kPa that is <= 1.7e-4 Pa, 4 decades below the tolerance (1.01 Pa, as the laminar test), so
    the square-root law is compared there; the exact regularised solution (see ``regularised_decay``) is
    compared on the whole run, including the last 1 kPa where the laminar tail takes over.
    """
    r = default_run("hydraulic_fill")
    t, p = r.t, r["pR"]
    k = BETA / V * CD * A_T * math.sqrt(2.0 / RHO)
    x0 = PS - P0
    x_sqrt = np.clip(math.sqrt(x0) - k * t / 2.0, 0.0, None) ** 2
    tol = solver_tol(PS, P_NOM)
    window = x_sqrt >= 1e3
    assert window.sum() > 100 and not window[-1]  # most of the run, and the run reaches ps
    bound = 1.0 ** 2 / (6.0 * 1e3)
    x_reg = regularised_decay(t, x0, k, 1.0)
    assert np.all(x_reg[window] - x_sqrt[window] <= bound) and np.all(x_reg >= x_sqrt - 1e-6)
    assert_matches("turbulent fill, square-root law", p[window], PS - x_sqrt[window], tol, {
        "k x2": (PS - np.clip(math.sqrt(x0) - k * t / 1.0, 0.0, None) ** 2)[window],
        "k /2": (PS - np.clip(math.sqrt(x0) - k * t / 4.0, 0.0, None) ** 2)[window],
        "laminar law": (PS - x0 * np.exp(-k / math.sqrt(x0) * t))[window],
    })
    assert_matches("turbulent fill, exact regularised", p, PS - x_reg, tol)
    assert np.all(np.diff(p) >= -tol)  # fills monotonically, never overshoots ps
    assert np.all(p <= PS + tol)


def test_turbulent_fill_wide_transition_exact_regularised_solution():
    """With dp_t = 1 bar the regularisation matters (the square-root law is off by up to 0.22 bar): the
    simulation follows the exact implicit solution k*t = F(x0) - F(x) of ``regularised_decay``. Same
    tolerance as above (1.01 Pa)."""
    r = default_run("hydraulic_fill")
    t = r.t
    k = BETA / V * CD * A_T * math.sqrt(2.0 / RHO)
    x0 = PS - P0
    x_reg = regularised_decay(t, x0, k, 1e5)
    x_sqrt = np.clip(math.sqrt(x0) - k * t / 2.0, 0.0, None) ** 2
    assert_matches("turbulent fill, dp_t = 1 bar", r["pR2"], PS - x_reg, solver_tol(PS, P_NOM), {
        "square-root law (dp_t ignored)": PS - x_sqrt,
        "dp_t = 2 bar": PS - regularised_decay(t, x0, k, 2e5),
    })


def test_two_volumes_conserve_and_equalise():
    """Two closed volumes V1 = 1 l (100 bar) and V2 = 3 l (20 bar) joined by a turbulent orifice (dp_t = 1 bar):
    V1*dp1/dt = -beta*q, V2*dp2/dt = +beta*q, so V1*p1 + V2*p2 is conserved and both tend to
    p_inf = (V1*p1_0 + V2*p2_0)/(V1 + V2) = 40 bar. The difference d = p1 - p2 obeys
    dd/dt = -beta*(1/V1 + 1/V2)*q(d): the fill equation with k = beta*(1/V1 + 1/V2)*Cd*A*sqrt(2/rho), so
    p1 = p_inf + d*V2/(V1 + V2), p2 = p_inf - d*V1/(V1 + V2) with d from ``regularised_decay``.

    Conservation: Rosenbrock methods keep linear invariants up to round-off (every stage increment lies in
    the invariant's null space, also with the finite-difference Jacobian), so the volume-weighted mean is
    required to stay at 40 bar within rtol*40 bar = 4 mPa, i.e. below a single step's local tolerance, while
    the individual pressures move by 60 and 20 bar. Trajectories: solver_tol(100 bar) = 1.01 Pa.
    """
    r = default_run("hydraulic_fill")
    V1, V2 = 1e-3, 3e-3
    p1, p2 = r["p1"], r["p2"]
    p_inf = (V1 * 100e5 + V2 * 20e5) / (V1 + V2)
    mean = (V1 * p1 + V2 * p2) / (V1 + V2)
    assert_matches("V1*p1 + V2*p2 conserved", mean, np.full_like(mean, p_inf), RTOL * p_inf, {
        "V1*p1 + V2*p2 with V swapped": (V2 * p1 + V1 * p2) / (V1 + V2),
    })
    k = BETA * (1 / V1 + 1 / V2) * CD * A_T * math.sqrt(2.0 / RHO)
    d = regularised_decay(r.t, 80e5, k, 1e5)
    tol = solver_tol(100e5, P_NOM)
    assert_matches("p1", p1, p_inf + d * V2 / (V1 + V2), tol, {"mean of p1_0, p2_0": 60e5 + d / 2})
    assert_matches("p2", p2, p_inf - d * V1 / (V1 + V2), tol)
    assert abs(p1[-1] - p_inf) < tol and abs(p2[-1] - p_inf) < tol  # equalised by the end of the run


# ---------------------------------------------------------------------------------------------------------
# Second-order step responses (netlist second_order_step.yaml)
# ---------------------------------------------------------------------------------------------------------
def unit_responses(t: np.ndarray, wn: float, zeta: float) -> tuple[np.ndarray, np.ndarray]:
    """For D(s) = s^2 + 2*zeta*wn*s + wn^2: g = step response of 1/D (g(0) = 0, g(inf) = 1/wn^2) and
    h = g' = impulse response of 1/D.
    zeta < 1: sigma = zeta*wn, wd = wn*sqrt(1 - zeta^2),
        h = exp(-sigma t) sin(wd t)/wd,   g = (1 - exp(-sigma t)(cos(wd t) + sigma/wd sin(wd t)))/wn^2
    zeta > 1: real poles s1,2 = -wn*(zeta -+ sqrt(zeta^2 - 1)),
        h = (exp(s1 t) - exp(s2 t))/(s1 - s2),   g = 1/(s1 s2) + exp(s1 t)/(s1 (s1 - s2)) + exp(s2 t)/(s2 (s2 - s1))
    """
    if zeta < 1:
        sigma, wd = zeta * wn, wn * math.sqrt(1 - zeta * zeta)
        e = np.exp(-sigma * t)
        h = e * np.sin(wd * t) / wd
        g = (1 - e * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))) / wn**2
    else:
        root = wn * math.sqrt(zeta * zeta - 1)
        s1, s2 = -zeta * wn + root, -zeta * wn - root
        h = (np.exp(s1 * t) - np.exp(s2 * t)) / (s1 - s2)
        g = 1 / (s1 * s2) + np.exp(s1 * t) / (s1 * (s1 - s2)) + np.exp(s2 * t) / (s2 * (s2 - s1))
    return g, h


@pytest.mark.parametrize("zeta", [0.3, 2.5], ids=["underdamped", "overdamped"])
def test_second_order_step_response(zeta):
    """A unit step at t = 0 into k*wn^2/D(s) (second_order and transfer_function num = [k*wn^2]) gives
    y = k*wn^2*g(t); into N(s)/D(s) with N = n2 s^2 + n1 s + n0 (transfer_function with a zero and direct
    feedthrough) it gives y = n2 + (n1 - n2*a1)*h(t) + (n0 - n2*a0)*g(t), a1 = 2*zeta*wn, a0 = wn^2
    (divide N by D: N/D = n2 + ((n1 - n2 a1) s + (n0 - n2 a0))/D). wn = 10 rad/s, k = 2, N = [0.5, 3, 200].
    Tolerance: outputs up to ~2.6, signal states nominal 1: solver_tol = 100*(1e-9*3 + 1e-9) = 4e-7.
    """
    wn, k = 10.0, 2.0
    n2, n1, n0 = 0.5, 3.0, 200.0
    r = circuit("second_order_step").simulate({"zeta": zeta})
    t = r.t
    g, h = unit_responses(t, wn, zeta)
    a1, a0 = 2 * zeta * wn, wn**2
    tol = solver_tol(3.0, S_NOM)
    g_wrong_zeta, _ = unit_responses(t, wn, 2 * zeta if zeta < 1 else zeta / 2)
    g_wrong_wn, _ = unit_responses(t, 2 * wn, zeta)
    wrong = {"zeta x2 (or /2)": k * wn**2 * g_wrong_zeta, "wn x2": k * (2 * wn) ** 2 * g_wrong_wn,
             "gain sign": -k * wn**2 * g}
    assert_matches("second_order", r["so"], k * wn**2 * g, tol, wrong)
    assert_matches("transfer_function", r["tf"], k * wn**2 * g, tol, wrong)
    full = n2 + (n1 - n2 * a1) * h + (n0 - n2 * a0) * g
    assert_matches("transfer_function with a zero and feedthrough", r["tf_full"], full, tol, {
        "no feedthrough term": full - n2,
        "reversed numerator": n0 + (n1 - n0 * a1) * h + (n2 - n0 * a0) * g,
    })
    assert r["tf_full"][0] == pytest.approx(n2, abs=1e-12)  # direct feedthrough at t = 0


# ---------------------------------------------------------------------------------------------------------
# Rigid bodies: inertia, gear, rack and pinion, speed source (netlist mechanical_decay.yaml)
# ---------------------------------------------------------------------------------------------------------
def test_inertia_viscous_decay():
    """J*dw/dt = -b*w, w(0) = w0 from the net's initial:  w = w0*exp(-b*t/J); J = 0.5, b = 2, w0 = 100 rad/s.
    Tolerance: speeds up to 100 rad/s, nominal 1 rad/s: solver_tol = 100*(1e-9*100 + 1e-9) = 1e-5 rad/s."""
    r = default_run("mechanical_decay")
    t = r.t
    J, b, w0 = 0.5, 2.0, 100.0
    assert_matches("inertia decay", r["w1"], w0 * np.exp(-b * t / J), solver_tol(w0, W_NOM), {
        "b/J x2": w0 * np.exp(-2 * b * t / J), "b/J /2": w0 * np.exp(-b * t / (2 * J)),
        "friction driving": w0 * np.exp(b * t / J),
    })


def test_gear_reflects_inertia_and_friction():
    """Gear n = 3 (w_b = w_a/n): inertia Ja = 0.2 on the input, Jb = 1.8 and friction bb = 9 on the output; the
    initial speed 10 rad/s is set on the OUTPUT net gb (not the body's root ga). Referred to the input:
    J_eff = Ja + Jb/n^2 = 0.4, b_eff = bb/n^2 = 1, so w_a = 3*10*exp(-2.5 t) and w_b = w_a/3 at all times.

    Second gear n = 4 with its output net k_out as the body's root (named first, so the link is walked
    backwards): Jin = 0.05 and friction bin = 0.3 on the input m_in, Jout = 0.8 on the output, initial 40 rad/s
    on the input: J_eff = Jin + Jout/n^2 = 0.1, rate 3 1/s, w_out = w_in/4.
    Tolerance: solver_tol(30 rad/s) = 3e-6 rad/s (the speed ratio is exact by construction: 1e-12 relative).
    """
    r = default_run("mechanical_decay")
    t = r.t
    n, Ja, Jb, bb = 3.0, 0.2, 1.8, 9.0
    wa = n * 10.0 * np.exp(-(bb / n**2) / (Ja + Jb / n**2) * t)
    tol = solver_tol(30.0, W_NOM)
    assert_matches("gear input speed", r["ga"], wa, tol, {
        "J_eff = Ja + Jb/n": n * 10.0 * np.exp(-(bb / n**2) / (Ja + Jb / n) * t),
        "J_eff = Ja + Jb": n * 10.0 * np.exp(-(bb / n**2) / (Ja + Jb) * t),
        "friction not reflected": n * 10.0 * np.exp(-bb / (Ja + Jb / n**2) * t),
        "initial speed on the input side": 10.0 * np.exp(-(bb / n**2) / (Ja + Jb / n**2) * t),
    })
    assert_matches("gear output speed", r["gb"], wa / n, tol / n)
    np.testing.assert_allclose(r["ga"], n * r["gb"], rtol=1e-12, atol=1e-300)

    n, Jin, Jout, bin_ = 4.0, 0.05, 0.8, 0.3
    w_in = 40.0 * np.exp(-bin_ / (Jin + Jout / n**2) * t)
    assert_matches("reversed gear input speed", r["m_in"], w_in, solver_tol(40.0, W_NOM), {
        "J_eff = Jin + Jout*n^2": 40.0 * np.exp(-bin_ / (Jin + Jout * n**2) * t),
        "initial speed on the output side": 160.0 * np.exp(-bin_ / (Jin + Jout / n**2) * t),
    })
    np.testing.assert_allclose(r["k_out"], r["m_in"] / n, rtol=1e-12, atol=1e-300)


def test_rack_and_pinion_decay():
    """Pinion (Jp = 0.01) and rack (mass m = 20, friction b = 30) joined by a rack and pinion r = 0.05 m:
    v = r*w, J_eff = Jp + m*r^2 = 0.06, b_eff = b*r^2 = 0.075 (torque r*f with f = -b*r*w), so
    w = w0*exp(-b_eff/J_eff t) with w0 = v0/r = 10 rad/s from the rack's initial v0 = 0.5 m/s.
    Tolerance: solver_tol(10 rad/s) = 1e-6 rad/s; the rack speed r times that."""
    r_ = default_run("mechanical_decay")
    t = r_.t
    r, Jp, m, b, v0 = 0.05, 0.01, 20.0, 30.0, 0.5
    w = v0 / r * np.exp(-b * r**2 / (Jp + m * r**2) * t)
    tol = solver_tol(10.0, W_NOM)
    assert_matches("pinion speed", r_["pin"], w, tol, {
        "J_eff = Jp + m*r": v0 / r * np.exp(-b * r**2 / (Jp + m * r) * t),
        "b_eff = b*r": v0 / r * np.exp(-b * r / (Jp + m * r**2) * t),
        "b_eff = b (not reflected)": v0 / r * np.exp(-b / (Jp + m * r**2) * t),
    })
    assert_matches("rack speed", r_["rack"], r * w, r * tol)
    np.testing.assert_allclose(r_["rack"], r * r_["pin"], rtol=1e-12, atol=1e-300)


def test_speed_source_prescribes_speed_exactly():
    """A speed source driven by a ramp w = a*t (a = 5 rad/s^2) turns an inertia (with friction) and, through a
    gear n = 2, a second one: the prescribed speed shows up exactly (to round-off, 1e-12 relative, no solver
    error: nothing is integrated), the geared one at a*t/n, and the angle sensors integrate a*t^2/2 and
    a*t^2/(2n). The angles are states of the solver; their exact solution is a polynomial of degree 2,
    which the order-4 method reproduces, so solver_tol(10 rad) = 1e-6 rad is generous."""
    r = default_run("mechanical_decay")
    t = r.t
    a, n = 5.0, 2.0
    np.testing.assert_allclose(r["drv"], a * t, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(r["drv_out"], a * t / n, rtol=1e-12, atol=1e-12)
    tol = solver_tol(10.0, S_NOM)
    assert_matches("angle", r["th"], a * t**2 / 2, tol, {"angle x2": a * t**2})
    assert_matches("geared angle", r["th_out"], a * t**2 / (2 * n), tol, {"ratio inverted": a * t**2 * n / 2})


# ---------------------------------------------------------------------------------------------------------
# Actuators: motor on a flow source, cylinder against a force (netlist actuators.yaml)
# ---------------------------------------------------------------------------------------------------------
Q = 10e-3 / 60  # 10 l/min
D = 10e-6 / (2 * math.pi)  # 10 cm^3/rev
G_LEAK, V_A, J_TOT, B_ROT = 1.6e-12, 0.5e-3, 0.002 + 0.008, 0.076


def motor_solution(t: np.ndarray, Q=Q, D=D, G=G_LEAK, b=B_ROT, V=V_A, J=J_TOT, beta=BETA):
    """x = (pA, w):  dx/dt = M x + f,  M = [[-beta*G/V, -beta*D/V], [D/J, -b/J]],  f = (beta*Q/V, 0), x(0) = 0.
    Exact: x(t) = x_ss + expm(M t)(x(0) - x_ss), x_ss = -M^-1 f, i.e. the pair Q = D*w + G*dp, D*dp = b*w:
    w_ss = Q*D/(D^2 + G*b), dp_ss = b*w_ss/D. The eigenvalues of M set the transient (here a damped
    oscillation, -5.08 +- 19.97j 1/s: time constant 0.197 s, so the 5 s run ends 25 time constants later)."""
    M = np.array([[-beta * G / V, -beta * D / V], [D / J, -b / J]])
    f = np.array([beta * Q / V, 0.0])
    x_ss = -np.linalg.solve(M, f)
    X = np.array([x_ss + expm(M * ti) @ (-x_ss) for ti in t])
    return X[:, 0], X[:, 1], x_ss, np.linalg.eigvals(M)


def test_motor_on_flow_source_steady_speed_and_transient():
    """Flow source Q = 10 l/min (tank -> line A, 0.5 l) -> motor D = 10 cm^3/rev with leakage G = 1.6e-12
    -> tank; shaft J_m + J = 0.01 kg m^2, viscous friction b = 0.076 N m s. Steady state from the two linear
    equations (flow: Q = D*w + G*dp; torque: D*dp = b*w): w = Q*D/(D^2 + G*b) = 99.93 rad/s,
    dp = b*w/D = 47.7 bar; the whole transient is the exact linear solution of ``motor_solution``.
    Tolerances: solver_tol(55 bar) = 0.55 Pa on the pressure, solver_tol(100 rad/s) = 1e-5 rad/s on w."""
    r = default_run("actuators")
    t = r.t
    p, w, (p_ss, w_ss), eig = motor_solution(t)
    assert w_ss == pytest.approx(Q * D / (D**2 + G_LEAK * B_ROT), rel=1e-12)
    assert p_ss == pytest.approx(B_ROT * w_ss / D, rel=1e-12)
    # settled: what is left of the transient at t_end is below a tenth of the tolerance
    assert np.all(eig.real < 0) and math.exp(np.max(eig.real) * t[-1]) * w_ss < solver_tol(100.0, W_NOM) / 10
    tol_p, tol_w = solver_tol(55e5, P_NOM), solver_tol(100.0, W_NOM)
    assert_matches("motor pressure", r["pA"], p, tol_p, {
        "no leakage": motor_solution(t, G=0.0)[0],
        "leakage x2": motor_solution(t, G=2 * G_LEAK)[0],
    })
    assert_matches("motor speed", r["w"], w, tol_w, {
        "no leakage": motor_solution(t, G=0.0)[1],
        "D per rev, not per rad": motor_solution(t, D=2 * math.pi * D)[1],
        "displacement x2": motor_solution(t, D=2 * D)[1],
    })
    assert abs(r["w"][-1] - w_ss) < tol_w and abs(r["pA"][-1] - p_ss) < tol_p


def test_cylinder_against_constant_force_moves_at_q_over_area():
    """Flow source Qc = 6 l/min into chamber A (A_A = 20 cm^2) of a cylinder whose rod side returns to the
    tank; the rod pushes a 500 kg mass with viscous friction c = 2e4 N s/m against F = 10 kN, starting at
    rest at x = 0.1 m with pA = 0. The steady state is exact (no leakage): v = Qc/A_A = 0.05 m/s and
    pA = (F + c*v)/A_A = 55 bar, whatever the (growing) chamber volume. The transient is a hydraulic-spring
    oscillation (k = beta*A_A^2/V_A ~ 8e6 N/m) damped at c/(2m) = 20 1/s, gone after 5 s (e^-100).
    Tolerances: solver_tol(0.1 m/s, nominal 0.1) on v; solver_tol(55 bar) on pA."""
    r = default_run("actuators")
    Qc, A_A, F, c = 6e-3 / 60, 20e-4, 10e3, 2e4
    v_ss = Qc / A_A
    p_ss = (F + c * v_ss) / A_A
    v_end, p_end = r["v"][-1], r["pCA"][-1]
    tol_v, tol_p = solver_tol(0.1, 0.1), solver_tol(p_ss, P_NOM)
    assert abs(v_end - v_ss) < tol_v, (v_end, v_ss)
    assert abs(p_end - p_ss) < tol_p, (p_end, p_ss)
    assert abs(v_end - 6e-3 / 60 / 10e-4) > 1000 * tol_v  # not Qc/A_B
    assert abs(p_end - F / A_A) > 1000 * tol_p  # the friction counts
    # it did start from rest, was first pushed back by F, and then travelled about v*t
    assert r["v"][0] == 0.0 and r["v"].min() < -0.01
    assert 0.24 < r["x"][-1] - r["x"][0] < v_ss * r.t[-1]


# ---------------------------------------------------------------------------------------------------------
# Solvers agree on the drive-line example
# ---------------------------------------------------------------------------------------------------------
@lru_cache(maxsize=None)
def drive_line_runs():
    c = Circuit.from_file(DRIVE_LINE)
    s = c.settings
    return {
        "rodas": c.simulate(settings=s.with_(solver="rodas", rtol=1e-6)),
        "radau": c.simulate(settings=s.with_(solver="radau", rtol=1e-6)),
        "fixed": c.simulate(settings=s.with_(solver="fixed", fixed_step=1e-4)),
        "reference": c.simulate(settings=s.with_(solver="radau", rtol=1e-10, atol=1e-10)),
    }


@pytest.mark.parametrize("solver", ["rodas", "radau", "fixed"])
def test_drive_line_solvers_agree(solver):
    """The drive line (netlists/examples/drive_line.yaml) run with rodas (rtol 1e-6), scipy's radau
    (rtol 1e-6) and the fixed-step Rosenbrock method (h = 0.1 ms), each against scipy's radau at rtol = atol = 1e-10.
    Stated error: 10*1e-6 of each signal's range, |dx| <= 1e-5 m on the 1 m travel and |dpA| <= 160 Pa on
    the 20..160 bar line pressure (the closed loop is contracting, so the global error stays near the local
    tolerance; measured: x within 3e-8 m and pA within 17 Pa for rodas, 1.5e-8 m and 7 Pa for radau,
    2e-10 m and 0.5 Pa for the fixed step). The reference itself: see test_drive_line_reference_is_converged."""
    runs = drive_line_runs()
    ref, run = runs["reference"], runs[solver]
    assert ref["x"][-1] > 0.99 and np.ptp(ref["pA"]) > 100e5  # a real motion, not a trivial agreement
    for name in ("x", "pA"):
        scale = np.max(np.abs(ref[name]))
        err = np.max(np.abs(run[name] - ref[name]))
        assert err <= 10 * 1e-6 * scale, f"{solver}: {name} off by {err:.3g} (scale {scale:.3g})"
    assert not run.warnings


def test_drive_line_reference_is_converged():
    """The reference (radau, rtol = atol = 1e-10) and the compiled rodas at rtol = atol = 1e-10 agree within
    100*1e-10 of each signal's range (1e-8 m, 0.16 Pa; measured 2.3e-11 m and 0.019 Pa): two different
    methods converge to the same solution, which the 1e-6 runs above are compared with."""
    runs = drive_line_runs()
    ref = runs["reference"]
    c = Circuit.from_file(DRIVE_LINE)
    fine = c.simulate(settings=c.settings.with_(solver="rodas", rtol=1e-10, atol=1e-10))
    for name in ("x", "pA"):
        scale = np.max(np.abs(ref[name]))
        err = np.max(np.abs(fine[name] - ref[name]))
        assert err <= 100 * 1e-10 * scale, f"{name} off by {err:.3g} (scale {scale:.3g})"


# ---------------------------------------------------------------------------------------------------------
# Diagnostics: cavitation warning, solver failure
# ---------------------------------------------------------------------------------------------------------
def test_cavitation_is_reported():
    """Net C (1 l) drains to the tank (0 bar) through G = 1e-11 while a flow source pulls q = 3e-6 m^3/s out
    of it: as a liquid p_C = -(q/G)*(1 - exp(-8 t)) -> -3 bar, crossing the vapour pressure -1 bar at
    t = ln(1.5)/8 = 50.7 ms. From there a vapour cavity holds it near -1 bar (fluid cavitation): the tank
    feeds C at G*|p_C| ~ 1e-6 m^3/s, short of the 3e-6 pulled, and the cavity grows by the difference.
    The result carries one warning, naming net 'C', the first output sample below the vapour pressure (52 ms
    at dt_out = 2 ms) and the cavity's largest size, which must equal the oil balance of the net: what left
    it, less what the liquid gave up between 0 bar and p_vap. The default run (q = 0) carries none."""
    assert default_run("hydraulic_fill").warnings == []
    r = circuit("hydraulic_fill").simulate({"q_pull": 3e-6})
    assert len(r.warnings) == 1, r.warnings
    message = r.warnings[0]
    assert "cavitation" in message and "'C'" in message, message
    seen = float(re.search(r"first seen at t = ([\d.e+-]+) s", message).group(1))
    assert math.log(1.5) / 8 <= seen <= math.log(1.5) / 8 + 0.002 + 1e-9
    # before the crossing the pressure follows the laminar drain law
    liquid = r.t < math.log(1.5) / 8
    assert_matches("drained pressure", r["pC"][liquid], -3e5 * (1 - np.exp(-8.0 * r.t[liquid])), solver_tol(3e5, P_NOM))
    # after it, the cavity is the oil that left (3e-6 pulled, G*|p| fed in) less what the liquid gave up
    # between 0 bar and the lowest pressure (the end: the cavity only grows)
    p = r["pC"]
    left = np.sum(np.diff(r.t) * (3e-6 + 1e-11 * (p[1:] + p[:-1]) / 2))
    balance = left - 1e-3 * (0.0 - p.min()) / 8e8  # m^3
    reported = float(re.search(r"a vapour cavity of up to ([\d.e+-]+) cm\^3", message).group(1)) * 1e-6
    # roughly: 3e-6 - G*1 bar = 2e-6 m^3/s from the crossing to 1 s
    assert balance == pytest.approx((3e-6 - 1e-11 * 1e5) * (1 - math.log(1.5) / 8), rel=0.01)
    # the oil balanced; cavity_volume leaves out the liquid's share of the onset band, V/beta over C_cav*w/2
    assert cavity_volume(p.min(), -1e5) == pytest.approx(balance, rel=2e-3)
    assert reported == pytest.approx(balance, rel=5e-3)  # as the message gives it, to 3 digits
    assert -1.05e5 < p.min() < -1e5  # inside the onset band: under 250 cm^3 of vapour


@pytest.mark.parametrize("solver", ["rodas", "fixed"])
def test_solver_failure_names_time_state_and_block(solver):
    """An unstable transfer function 1/(s - a), a = 1000 1/s, under a unit step: x = (exp(a t) - 1)/a overflows
    near t = ln(1.8e308*a)/a = 0.717 s. simulate raises SimulationError whose message gives the time reached
    (before the overflow, and where the exact solution equals the state value it reports, to 1e-4 s: the
    relative error of an exponentially growing solution grows ~linearly in time, rtol 1e-6 per step for rodas,
    and the fixed step h = 0.1 ms has a*h = 0.1), the state (grow.x) and the block (grow)."""
    c = circuit("runaway")
    a = 1000.0
    settings = c.settings.with_(solver=solver, fixed_step=1e-4)
    with pytest.raises(SimulationError) as info:
        c.simulate(settings=settings)
    message = str(info.value)
    assert "runaway.yaml" in message and "grow.x" in message and "block grow" in message, message
    t_fail = float(re.search(r"failed at t = ([\d.e+-]+) s", message).group(1))
    value = float(re.search(r"state grow\.x = ([\d.e+-]+)", message).group(1))
    t_overflow = (math.log(np.finfo(float).max) + math.log(a)) / a
    assert 0.69 < t_fail <= t_overflow, message
    assert math.log1p(a * value) / a == pytest.approx(t_fail, abs=1e-4), message


@pytest.mark.parametrize("solver", ["radau", "bdf", "lsoda"])
def test_scipy_solver_failure_names_state_and_block(solver):
    """The same failure through the scipy solvers should be reported in the same terms."""
    c = circuit("runaway")
    with pytest.raises(SimulationError) as info:
        c.simulate(settings=c.settings.with_(solver=solver))
    message = str(info.value)
    assert "grow.x" in message and "block grow" in message, message
    t_fail = float(re.search(r"failed at t = ([\d.e+-]+) s", message).group(1))
    assert 0.6 < t_fail < 0.72, message  # the true overflow is at 0.7165 s, not the last output sample (0.7 s)
