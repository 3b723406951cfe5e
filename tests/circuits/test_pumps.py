"""The pumps and the induction motor in small circuits (netlist tests/circuits/netlists/pumps.yaml) against
closed-form solutions computed here: a pump filling a volume that drains through a laminar orifice (an
exact first-order response), a motor-pump set finding its operating point on Kloss's curve against a relief
valve, and a pressure-compensated pump dead-headed against a small orifice; then the example
netlists/components/power_unit.yaml, phase by phase.

Tolerances as in test_analytic.py: ``solver_tol`` is 100 times the solver's local tolerance (the netlist
sets rtol = atol = 1e-9); each ``assert_matches`` also shows that plausible wrong models miss by 1000 times
more. The example's own tolerances are in its test's docstring.
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from blocks.circuit import Circuit
from tests.circuits.test_analytic import P_NOM, S_NOM, W_NOM, assert_matches, solver_tol

NETLIST = Path(__file__).parent / "netlists" / "pumps.yaml"

BETA, RHO, V = 8e8, 850.0, 1e-3
RPM = 2 * math.pi / 60
G_LEAK = 1e-12
D = 28e-6 / (2 * math.pi)  # 28 cm^3/rev in m^3/rad


@lru_cache(maxsize=None)
def circuit() -> Circuit:
    return Circuit.from_file(NETLIST)


@lru_cache(maxsize=None)
def run(eps_max: float = 1.0):
    return circuit().simulate(None if eps_max == 1.0 else {"eps_max": eps_max})


def test_netlist_tolerances():
    s = circuit().settings
    assert (s.solver, s.rtol, s.atol) == ("rodas", 1e-9, 1e-9)


# ---------------------------------------------------------------- fill: pump -> volume -> laminar orifice
def fill(t, q, g, volume=V):
    """V/beta*dp/dt = q - g*p, p(0) = 0."""
    return q / g * (1 - np.exp(-t * BETA * g / volume))


def test_pump_fills_a_volume_first_order():
    """A speed source turns the pump at 1500 rpm: it delivers D*w = 42 l/min, less its leakage, into 1 l
    draining through G_a = 6.9e-11: p_ss = D*w/(G_a + G_leak) = 100 bar, time constant
    V/(beta*(G_a + G_leak)) = 17.9 ms. solver_tol(100 bar) = 1.01 Pa."""
    r = run()
    t, w, g_a = r.t, 1500 * RPM, 6.9e-11
    g = g_a + G_LEAK
    p_ss, time_constant = D * w / g, V / (BETA * g)
    assert p_ss == pytest.approx(100e5, rel=1e-3) and time_constant == pytest.approx(17.86e-3, rel=1e-3)
    assert_matches("pump fill", r["pa"], fill(t, D * w, g), solver_tol(p_ss, P_NOM), {
        "no leakage": fill(t, D * w, g_a),
        "leakage adding to the flow": fill(t, D * w + 2 * G_LEAK * p_ss, g),
        "D per rev, not per rad": fill(t, 2 * math.pi * D * w, g),
        "time constant x2": fill(t, D * w, g, 2 * V),
    })
    assert abs(r["pa"][-1] - p_ss) < solver_tol(p_ss, P_NOM)


# ---------------------------------------------------------------- drive: induction motor -> pump -> relief valve
W_SYNC, T_B, S_B, ETA_HM = 1500 * RPM, 275.0, 0.1444, 0.9
RELIEF = dict(p_set=150e5, p_open=160e5, A_max=20e-6, A_leak=1e-9, Cd=0.7, dp_t=1e5)
G_B = 1e-11


def kloss(w, w_sync=W_SYNC, T_b=T_B, s_b=S_B):
    """Kloss's formula as the data books write it, and its limit 0 at synchronous speed."""
    s = (w_sync - w) / w_sync
    return 2 * T_b / (s / s_b + s_b / s) if s != 0.0 else 0.0


def regularised_orifice(dp, area, cd=0.7, dp_t=1e5, rho=RHO):
    """The blocks' turbulent law written out: Cd*A*sqrt(2/rho)*dp/(dp^2 + dp_t^2)^(1/4)."""
    return cd * area * math.sqrt(2 / rho) * dp / (dp * dp + dp_t * dp_t) ** 0.25


def relief_flow(p, p_set, p_open, A_max, A_leak, Cd, dp_t, rho=RHO):
    """The relief valve's law written out: a cubic opening from p_set to p_open, the regularised orifice."""
    u = min(max((p - p_set) / (p_open - p_set), 0.0), 1.0)
    return regularised_orifice(p, A_leak + (A_max - A_leak) * (3 * u**2 - 2 * u**3), Cd, dp_t, rho)


def operating_point(eta_hm=ETA_HM, leak=G_LEAK, displacement=D):
    """(w, p) where the pump's flow D*w - G_leak*p leaves through the valve and the load orifice, and the
    motor's torque equals the pump's D*p/eta_hm (tanh(w/w_w) = 1 at these speeds)."""
    def pressure(w):
        return brentq(lambda p: displacement * w - leak * p - G_B * p - relief_flow(p, **RELIEF), 0.0, 400e5,
                      xtol=1e-9, rtol=1e-15)

    w = brentq(lambda w: kloss(w) - displacement * pressure(w) / eta_hm, (1 - S_B) * W_SYNC, W_SYNC,
               xtol=1e-13, rtol=1e-15)
    return w, pressure(w)


def test_motor_and_pump_settle_where_kloss_meets_the_pump_torque():
    """A 15 kW four-pole motor (Kloss: T_b = 275 N*m at s_b = 0.1444) starts the 28 cm^3/rev pump
    (eta_hm = 0.9) from rest. The relief valve (150 bar cracking, 160 bar full open) takes what the 10 l/min
    load orifice does not: the set runs at w = 153.9 rad/s (1470 rpm, slip 2 %) against 152.8 bar.
    Tolerances: solver_tol(154 rad/s) = 1.6e-5 rad/s, solver_tol(153 bar) = 1.5 Pa."""
    r = run()
    w, p = operating_point()
    assert 1460 * RPM < w < 1480 * RPM and 150e5 < p < 160e5  # the valve is cracked: it sets the pressure
    tol_w, tol_p = solver_tol(w, W_NOM), solver_tol(p, P_NOM)
    assert_matches("motor speed", r["wb"][-1:], np.array([w]), tol_w, {
        "eta_hm ignored": np.array([operating_point(eta_hm=1.0)[0]]),
        "torque D*p*eta_hm": np.array([operating_point(eta_hm=ETA_HM**2)[0]]),
    })
    assert_matches("pump pressure", r["pb"][-1:], np.array([p]), tol_p, {
        "no leakage": np.array([operating_point(leak=0.0)[1]]),
        "leakage x2": np.array([operating_point(leak=2 * G_LEAK)[1]]),
    })
    # the power balance at the operating point: the oil gets eta_hm*eta_v of the motor's shaft power
    shaft = kloss(r["wb"][-1]) * r["wb"][-1]
    hydraulic = (D * r["wb"][-1] - G_LEAK * r["pb"][-1]) * r["pb"][-1]
    eta_v = 1 - G_LEAK * r["pb"][-1] / (D * r["wb"][-1])
    assert hydraulic / shaft == pytest.approx(ETA_HM * eta_v, rel=1e-6)
    # it started from rest, direct on line, and never passed synchronous speed
    assert r["wb"][0] == 0.0 and np.all(r["wb"] < W_SYNC) and not r.warnings


# ---------------------------------------------------------------- compensator: variable pump dead-headed
D_MAX, W_C, P_C, DP_C, G_C = 45e-6 / (2 * math.pi), 1500 * RPM, 200e5, 5e5, 1e-11


def compensator_target(p):
    u = min(max((p - P_C) / DP_C, 0.0), 1.0)
    return 1.0 - (3 * u**2 - 2 * u**3)


def test_variable_pump_settles_inside_its_compensator_band():
    """At full stroke the pump would deliver 67.5 l/min into a net that only G_c + G_leak = 1.1e-11 drains
    (1000 bar). It rises as a fixed pump, exactly, until p_c = 200 bar (eps stays 1: the target is full
    stroke below p_c); then the compensator strokes back and the pressure settles where
    eps*D_max*w = (G_c + G_leak)*p with eps the compensator's target, inside [p_c, p_c + dp_c].
    Tolerances: solver_tol(205 bar) = 2.1 Pa, solver_tol(1, nominal 1) = 2e-7 on eps."""
    r = run()
    g = G_C + G_LEAK
    p = brentq(lambda p: compensator_target(p) * D_MAX * W_C - g * p, P_C, P_C + DP_C, xtol=1e-9, rtol=1e-15)
    eps = compensator_target(p)
    assert P_C < p < P_C + DP_C and 0.1 < eps < 0.3
    tol_p, tol_eps = solver_tol(p, P_NOM), solver_tol(1.0, S_NOM)
    assert_matches("compensated pressure", r["pc"][-1:], np.array([p]), tol_p, {
        "at p_c": np.array([P_C]), "at p_c + dp_c": np.array([P_C + DP_C]),
        "linear ramp": np.array([brentq(lambda p: (1 - (p - P_C) / DP_C) * D_MAX * W_C - g * p, P_C, P_C + DP_C)]),
    })
    assert_matches("displacement", r["eps"][-1:], np.array([eps]), tol_eps, {"flow over D_max*w": np.array([g * p])})
    below = fill(r.t, D_MAX * W_C, g) < P_C
    assert below.sum() > 5 and not below[-1]
    assert_matches("fixed-pump rise below p_c", r["pc"][below], fill(r.t[below], D_MAX * W_C, g), tol_p)
    assert np.all(r["eps"][below] == 1.0)


def test_displacement_limiter_makes_a_smaller_fixed_pump():
    """eps_max = 0.1 < the 0.2 the orifice would take at p_c: the pump is a fixed pump of 0.1*D_max and
    the pressure rises to 0.1*D_max*w/(G_c + G_leak) = 102 bar, below p_c, as a first-order fill. The
    state starts at full stroke and lags down to 0.1, but the displacement in use is 0.1 from the start."""
    r = run(0.1)
    g = G_C + G_LEAK
    exact = fill(r.t, 0.1 * D_MAX * W_C, g)
    assert exact[-1] < P_C
    assert_matches("limited pump fill", r["pc"], exact, solver_tol(exact[-1], P_NOM), {
        "full displacement": fill(r.t, D_MAX * W_C, g),
        "lagging displacement": fill(r.t, D_MAX * W_C * (0.1 + 0.9 * np.exp(-r.t / 0.03)), g),
    })
    assert np.max(np.abs(r["eps"] - 0.1)) <= solver_tol(1.0, S_NOM)


# ---------------------------------------------------------------- the example: netlists/components/power_unit.yaml
POWER_UNIT = Path(__file__).resolve().parents[2] / "netlists" / "components" / "power_unit.yaml"


@lru_cache(maxsize=None)
def power_unit():
    c = Circuit.from_file(POWER_UNIT)
    return c.simulate(), c.vectors().values


def drop(q, area, v):
    """The pressure drop that passes q through a valve edge of the given area (the orifice law inverted)."""
    return brentq(lambda dp: regularised_orifice(dp, area, v["valve.Cd"], v["valve.dp_t"], v["relief.rho"]) - q,
                  0.0, 1e9, xtol=1e-6, rtol=1e-15)


def relief_leak(p, v):
    names = ("p_set", "p_open", "A_max", "A_leak", "Cd", "dp_t", "rho")
    return relief_flow(p, *(v[f"relief.{name}"] for name in names))


def motor_speed(torque, v):
    """The speed on Kloss's stable branch at which the motor gives ``torque``."""
    w_sync, s_b = v["motor.w_sync"], v["motor.s_b"]
    return brentq(lambda w: kloss(w, w_sync, v["motor.T_b"], s_b) - torque, (1 - s_b) * w_sync, w_sync,
                  xtol=1e-12, rtol=1e-15)


def moving(v, speed):
    """Steady motion at rod speed ``speed`` (> 0 extends) with the spool at full stroke and the pump at full
    displacement: the meter-in and meter-out edges' drops from the chamber flows, the rod's force balance
    (friction Fc + b*|speed|, against the motion) and the pump's flow D_max*w - G_leak*p_Q, at the speed w
    where Kloss's torque equals D_max*p_Q/eta_hm; returns (residual of the pump's flow, pP, w)."""
    A_A, A_B, area = v["cyl.A_A"], v["cyl.A_B"], v["valve.A_max"]
    f = math.copysign(v["friction.Fc"], speed) + v["friction.b"] * speed
    if speed > 0:  # P -> A, B -> T: pA*A_A = pB*A_B + f
        p_b = drop(A_B * speed, area, v)
        p_p = (p_b * A_B + f) / A_A + drop(A_A * speed, area, v)
        q = A_A * speed
    else:  # P -> B, A -> T: pB*A_B = pA*A_A - f
        p_a = drop(-A_A * speed, area, v)
        p_p = (p_a * A_A - f) / A_B + drop(-A_B * speed, area, v)
        q = -A_B * speed
    q += relief_leak(p_p, v)
    p_q = p_p + v["q_pump.R"] * q
    w = motor_speed(v["pump.D_max"] * p_q / v["pump.eta_hm"], v)
    return v["pump.D_max"] * w - v["pump.G_leak"] * p_q - q, p_p, w


def dead_headed(v):
    """The valve closed (or the piston on its stop): the pump delivers only its leakage and the relief
    valve's, at the pressure where the compensator's target displacement does that; returns (p, eps, w)."""
    p_c, dp_c, D = v["pump.p_c"], v["pump.dp_c"], v["pump.D_max"]

    def eps(p):
        u = min(max((p - p_c) / dp_c, 0.0), 1.0)
        return 1 - (3 * u**2 - 2 * u**3)

    def speed(p):
        return motor_speed(eps(p) * D * p / v["pump.eta_hm"], v)

    p = brentq(lambda p: eps(p) * D * speed(p) - v["pump.G_leak"] * p - relief_leak(p, v), p_c, p_c + dp_c,
               xtol=1e-6, rtol=1e-15)
    return p, eps(p), speed(p)


def at(r, t):
    return int(np.argmin(np.abs(r.t - t)))


def test_power_unit_example_runs_at_its_closed_form_operating_points():
    """netlists/components/power_unit.yaml, each phase's steady state solved here from the netlist's values:
    extending and retracting at full pump flow (the cylinder's speed from the pump's flow and the motor's
    slip), and dead-headed (holding, and on the end stop) inside the compensator band.
    Tolerances: the moving phases have settled to round-off (measured 1e-11 relative), compared to 1e-8:
    eta_hm ignored moves them by 9e-4 or more, the leakage ignored by 2 %, even the flow sensor's
    68 Pa drop by 3e-7. Dead-headed, the pressure and speed to 1e-6 (measured 4e-7 and 7e-8; the
    leakage ignored is 4e-3 off, eta_hm ignored 1e-4 on the speed), the displacement (0.047, a state of
    nominal 1 at atol = rtol = 1e-6: its absolute error is ~1e-6, 2e-5 of it) to 1e-4 (the relief valve's
    closed leakage ignored is 4e-3 off)."""
    r, v = power_unit()
    assert not r.warnings
    for t, sign in ((1.99, 1.0), (4.0, -1.0)):
        k = at(r, t)
        speed = brentq(lambda s: moving(v, s)[0], 0.01 * sign, 0.5 * sign, xtol=1e-12, rtol=1e-15)
        _, p_p, w = moving(v, speed)
        assert r["v"][k] == pytest.approx(speed, rel=1e-8), t
        assert r["pP"][k] == pytest.approx(p_p, rel=1e-8), t
        assert r["speed"][k] == pytest.approx(w, rel=1e-8), t
        assert r["eps"][k] == pytest.approx(1.0, abs=1e-6)  # below p_c: full stroke
        assert r["pP"][k] < v["pump.p_c"]
        chamber = v["cyl.A_A"] * speed if sign > 0 else -v["cyl.A_B"] * speed
        assert r["q_pump"][k] == pytest.approx(chamber + relief_leak(p_p, v), rel=1e-8), t
    p, eps, w = dead_headed(v)
    for t in (2.79, 5.0):  # the valve centred; the piston held on its end stop
        k = at(r, t)
        assert r["pP"][k] == pytest.approx(p, rel=1e-6), t
        assert r["eps"][k] == pytest.approx(eps, rel=1e-4), t
        assert r["speed"][k] == pytest.approx(w, rel=1e-6), t
    assert v["pump.p_c"] < p < v["pump.p_c"] + v["pump.dp_c"]
    # the compensator's lag lets the pressure overshoot when the pump is dead-headed at full stroke; the
    # relief valve, set above it, catches that
    peak = r["pP"].max()
    assert v["relief.p_set"] < peak < v["relief.p_open"]
    assert np.all(r["speed"] < v["motor.w_sync"]) and r["x"].min() < 0.0  # reached the end stop


# ---------------------------------------------------------------- a starved suction: the flow the suction lets in
STARVED = """
description: a pump at 1500 rpm (42 l/min) whose suction line (laminar, G_s) lets in at most 5.4 l/min
fluid: {rho: "850 kg/m^3", nu: "1.8e-5 m^2/s", beta: "8e8 Pa", vapour_pressure: "-0.9 bar"}
components:
  tank:  {type: tank}
  line:  {type: laminar_orifice, params: {G: "1e-9 m^3/(s*Pa)"}}
  pump:  {type: pump, params: {D: "28 cm^3/rev", J_p: "0.002 kg*m^2"}}
  drive: {type: speed_source}
  speed: {type: constant, params: {value: "1500 rpm"}}
  load:  {type: laminar_orifice, params: {G: "1e-11 m^3/(s*Pa)"}}
nets:
  T: [tank.port, line.a, load.b]
  S: {ports: [line.b, pump.s], volume: "0.2 l"}
  P: {ports: [pump.p, load.a], volume: "0.5 l"}
  shaft: [drive.port, pump.shaft]
  w: [speed.y, drive.w]
outputs: {pS: {of: S}, pP: {of: P}}
simulation: {t_end: "1.5 s", dt_out: "10 ms", solver: rodas, rtol: 1e-9, atol: 1e-9}
"""


def test_a_starved_pump_delivers_what_its_suction_line_lets_in(tmp_path):
    """The suction line can pass G_s*(0 - p_vap) = 9e-5 m^3/s (5.4 l/min) at most, an eighth of D*w: the
    suction net falls to the vapour pressure, the chambers fill only partly (within 0.005 bar below it),
    and the pump delivers the suction line's flow: G_a*p_P = G_s*(-p_S) = G_s*(-p_vap) to within
    G_s*0.005 bar (0.6 %), so p_P = 9 bar, not the 70 bar of the full D*w. The suction's vapour cavity
    stays under a cm^3. (A pump that delivered D*w whatever its inlet held would draw the suction net's
    cavity ever larger, at 42 - 5.4 l/min, and hold p_P near 70 bar.)"""
    (tmp_path / "starved.yaml").write_text(STARVED)
    r = Circuit.from_file(tmp_path / "starved.yaml").simulate()
    g_s, g_a, p_vap = 1e-9, 1e-11, -0.9e5
    assert D * 1500 * RPM > 7 * g_s * -p_vap
    late = r.t > 1.3  # 20 of the outlet's time constants V_P/(beta*G_a) = 62.5 ms
    p_s, p_p = r["pS"][late], r["pP"][late]
    assert np.all((p_vap - 500.0 <= p_s) & (p_s <= p_vap))
    assert np.allclose(g_a * p_p, g_s * -p_s, rtol=1e-6)
    assert np.allclose(p_p, g_s * -p_vap / g_a, rtol=0.006)
    assert any("vapour cavity of up to" in w and "cm^3" in w for w in r.warnings)
