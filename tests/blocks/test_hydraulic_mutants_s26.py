"""Gaps in the hydraulic block library found by mutation testing (session 26): each test checks a law the
blocks' docstrings state (a limit case, a symmetry, a conservation law, a closed form) that no earlier test
pinned down, so that a wrong operator, comparison or constant in the equation functions fails it.

The mutation tool and its log are outside the repository (the session's report says how to rerun it)."""

from __future__ import annotations

import math

import pytest
from scipy.integrate import quad

from blocks.library.hydraulic.cavitation import (CAVITY_COMPLIANCE, CAVITY_ONSET, cavitating_pressure_rate,
                                                 cavity_volume)
from blocks.library.hydraulic.check_valve import CheckValve
from blocks.library.hydraulic.counterbalance_valve import CounterbalanceValve
from blocks.library.hydraulic.cylinder import Cylinder
from blocks.library.hydraulic.entrained_air import aerated_pressure_rate, effective_bulk_modulus
from blocks.library.hydraulic.flow import smooth_max0, smooth_step
from blocks.library.hydraulic.flow_control_valve import FlowControlValve
from blocks.library.hydraulic.laminar_orifice import LaminarOrifice
from blocks.library.hydraulic.orifice import Orifice
from blocks.library.hydraulic.pipe import Pipe
from blocks.library.hydraulic.pressure_reducing_valve import PressureReducingValve
from blocks.library.hydraulic.relief_valve import ReliefValve
from blocks.library.hydraulic.shuttle_valve import ShuttleValve
from blocks.library.hydraulic.spool_relief_valve import SpoolReliefValve, rounded_unit
from blocks.library.hydraulic.valve_4_3 import Valve43
from blocks.library.hydraulic.variable_orifice import VariableOrifice

BAR = 1e5
RHO = 850.0


def named(cls, values) -> dict[str, float]:
    names = cls.derivative_names()
    assert len(values) == len(names), (cls.__name__, names, values)
    return dict(zip(names, values))


# ---------------------------------------------------------------- flow.py's helper laws at zero width
def test_smooth_step_of_zero_width_is_the_unit_step():
    """smooth_step(x, x0, width): '0 below x0, 1 above x0 + width'. With width = 0 (a cylinder's dx_stop = 0
    is allowed) there is no ramp left: the unit step, exactly 0 below x0 and exactly 1 above it (no division
    by the zero width). The values are exact: the law is piecewise constant there."""
    for x0 in (0.0, 1e-4, -3.0):
        for below in (1e-9, 1.0, 1e6):
            assert smooth_step(x0 - below, x0, 0.0) == 0.0
            assert smooth_step(x0 + below, x0, 0.0) == 1.0


def test_smooth_max0_of_zero_width_is_the_plain_max():
    """smooth_max0(x, width) is 'max(x, 0) ... (width <= 0: the plain max)': exact on both sides of 0."""
    for x in (-1e6, -1.0, -1e-9, 0.0, 1e-9, 1.0, 1e6):
        assert smooth_max0(x, 0.0) == max(x, 0.0)


# ---------------------------------------------------------------- cylinder end stop without a fade-in band
CYL = dict(A_A=3e-3, A_B=1.8e-3, stroke=0.5, V0_A=1e-4, V0_B=8e-5, k_stop=1e8, c_stop=1e5)


def cyl(x, v, pA=100 * BAR, pB=20 * BAR, **over):
    return named(Cylinder, Cylinder.derivatives(A=pA, B=pB, rod=v, x=x, **{**CYL, "dx_stop": 1e-4, **over}))


@pytest.mark.parametrize("end", ["retracted", "extended"])
def test_cylinder_end_stop_without_fade_in_is_a_spring_and_damper_from_contact(end):
    """dx_stop = 0 (its declared lower bound): the damping is faded in over no penetration, so the stop is the
    plain spring-damper f_stop = -(k_stop*d + c_stop*v_in) pushing the piston back into the stroke from the
    first contact (the docstring's law with smooth_step(d, 0, 0) = 1 for d > 0). The piston moving further
    in at v_in = 0.1 m/s and d = 1 mm: 1e5 N of spring and 1e4 N of damping, exact in floating point to
    rounding of the sums (rel 1e-12)."""
    d, v_in = 1e-3, 0.1
    free = cyl(0.25, 0.0, dx_stop=0.0)["f_rod"]
    if end == "retracted":
        f = cyl(-d, -v_in, dx_stop=0.0)["f_rod"]
        assert f - free == pytest.approx(CYL["k_stop"] * d + CYL["c_stop"] * v_in, rel=1e-12)
    else:
        f = cyl(CYL["stroke"] + d, v_in, dx_stop=0.0)["f_rod"]
        assert f - free == pytest.approx(-(CYL["k_stop"] * d + CYL["c_stop"] * v_in), rel=1e-12)


# ---------------------------------------------------------------- only pressure differences drive an orifice

FLUID = dict(Cd=0.7, dp_t=1e4, rho=RHO)
VALVE = dict(A_max=125e-6, x_db=0.02, A_leak=1e-9, A_float=0.0, A_bypass=0.0, x_c=0.05, **FLUID)
# (block, parameters, the hydraulic ports, the other inputs at the point): the pressures below are whole
# pascals, so every shifted pressure and every difference is exact in floating point
DIFFERENCE_ONLY = [
    (Orifice, dict(A=2e-5, **FLUID), ("a", "b"), {}),
    (VariableOrifice, FLUID, ("a", "b"), {"A": 2e-5}),
    (LaminarOrifice, dict(G=2e-12), ("a", "b"), {}),
    (CheckValve, dict(A_max=2e-5, p_crack=1e5, p_open=3e5, A_leak=1e-9, **FLUID), ("a", "b"), {}),
    (ReliefValve, dict(p_set=200e5, p_open=210e5, A_max=3e-5, A_leak=1e-9, **FLUID), ("a", "b"), {}),
    (Valve43, VALVE, ("P", "T", "A", "B"), {"x": 0.4}),
    (Valve43, VALVE, ("P", "T", "A", "B"), {"x": -0.6}),
    (Valve43, {**VALVE, "A_float": 20e-6, "A_bypass": 30e-6}, ("P", "T", "A", "B"), {"x": 0.01}),
    (Valve43, {**VALVE, "A_float": 20e-6, "A_bypass": 30e-6}, ("P", "T", "A", "B"), {"x": -0.03}),
    (PressureReducingValve, dict(p_set=50e5, dp_band=5e5, dp_relief=2e5, A_max=20e-6, A_relief=5e-6, A_leak=1e-9,
                                 **FLUID), ("P", "A", "T"), {}),
    (FlowControlValve, dict(A_meter=10e-6, dp_c=10e5, knee=0.1, **FLUID), ("a", "b"), {}),
    (CounterbalanceValve, dict(p_set=200e5, R_pilot=4.0, dp_open=40e5, A_relief=20e-6, A_check=30e-6, p_check=0.5e5,
                               p_check_open=2e5, A_leak=1e-9, dp_w=1e5, **FLUID), ("V", "C", "pilot"), {}),
    (ShuttleValve, dict(A_max=10e-6, dp_w=1e5, A_leak=1e-9, **FLUID), ("a", "b", "out"), {}),
    (SpoolReliefValve, dict(p_set=80e5, k_s=100e5, A_max=2e-5, c_ff=0.2, p_fric=3e5, u_z=1e-3, wn=300.0, zeta=0.7,
                            u_w=0.01, **FLUID), ("a", "b"), {"u": 0.4, "du": 0.5, "z": 0.3}),
]
# pressures at the ports, in ports' order, chosen so that every edge of every block above passes flow in
# some row (each block reads the first len(ports) of a row); three and four ports: a supply, a low
# (tank) side and loads in between, in both orders
PRESSURE_ROWS = [
    (207e5, 3e5, 90e5, 40e5),
    (52e5, 1e5, 150e5, 60e5),
    (101e5, 100e5, 120e5, 55e5),
    (6e5, 250e5, 30e5, 180e5),
    (215e5, 2e5, 53e5, 70e5),
]


@pytest.mark.parametrize("cls, params, ports, extra", DIFFERENCE_ONLY,
                         ids=lambda v: v.type_name if isinstance(v, type) else None)
@pytest.mark.parametrize("shift", [7e5, -2e5, 130e5])
def test_an_orifice_block_sees_only_pressure_differences(cls, params, ports, extra, shift):
    """Every flow of these blocks is an orifice law (or a laminar one) of a pressure difference, and every
    opening law reads a difference too (a spring chamber referenced to a port, a pilot against p_V, a ball
    between two inlets): raising all the port pressures together by the same amount changes no flow. Tank
    pressure is not zero on a machine (return-line back pressure), so this is the law that says each edge
    measures its drop to its own downstream port. The shifted and unshifted points' differences are the same
    doubles (whole pascals), so the flows agree to rounding (rel 1e-12)."""
    for row in PRESSURE_ROWS:
        base = dict(zip(ports, row))
        moved = {p: v + shift for p, v in base.items()}
        q0 = cls.derivatives(**base, **extra, **params)
        q1 = cls.derivatives(**moved, **extra, **params)
        assert q1 == pytest.approx(q0, rel=1e-12, abs=1e-300), (row, shift)
        assert any(q != 0.0 for q in q0)


# ---------------------------------------------------------------- cylinder: its signal and its stops' limits
def test_cylinder_position_signal_is_the_piston_position():
    """'position = x [m] (a signal, for a position controller)': the output is the state itself, positive
    out of the retracted end, so a controller reading it sees the rod extend as a rising position."""
    for x in (0.0, 0.125, 0.5):
        assert Cylinder.outputs(x=x) == (x,)


@pytest.mark.parametrize("dx_stop", [0.0, 1e-4])
def test_cylinder_at_the_very_end_of_its_stroke_feels_no_stop(dx_stop):
    """End stops act 'outside [0, stroke]' and the force is 'continuous at contact': at x = 0 and x = stroke
    exactly (penetration 0) there is no stop force whatever the speed, also with no fade-in band (dx_stop = 0,
    where the damping would otherwise be full at the first contact). The rod force is then exactly the
    pressures' p_A*A_A - p_B*A_B."""
    free = 100 * BAR * CYL["A_A"] - 20 * BAR * CYL["A_B"]
    for x, v_out in ((0.0, -0.3), (CYL["stroke"], 0.3)):
        for v in (v_out, 0.0, -v_out):
            assert cyl(x, v, dx_stop=dx_stop)["f_rod"] == free


@pytest.mark.parametrize("dx_stop", [0.0, 1e-4])
def test_cylinder_stop_only_pushes(dx_stop):
    """'A stop can only push': a piston leaving the stop faster than the spring relaxes (v_out > k/c*d;
    here 10 m/s against k/c*d = 1 m/s at d = 1 mm) gets no stop force at all, not a pull back into the stop:
    f_rod is exactly the pressures' force."""
    free = 100 * BAR * CYL["A_A"] - 20 * BAR * CYL["A_B"]
    d = 1e-3
    assert cyl(CYL["stroke"] + d, -10.0, dx_stop=dx_stop)["f_rod"] == free
    assert cyl(-d, 10.0, dx_stop=dx_stop)["f_rod"] == free


# ---------------------------------------------------------------- spool relief valve's stroke saturation
def rounded_unit_closed_form(x, w):
    """The docstring's law: 0 for x <= 0, 1 for x >= 1, x on [w, 1 - w], 2x^2/w - x^3/w^2 on (0, w) and its
    mirror image 1 - (2y^2/w - y^3/w^2), y = 1 - x, on (1 - w, 1)."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    if x < w:
        return 2 * x * x / w - x ** 3 / (w * w)
    if x > 1.0 - w:
        y = 1.0 - x
        return 1.0 - (2 * y * y / w - y ** 3 / (w * w))
    return x


@pytest.mark.parametrize("w", [0.01, 0.1, 0.25])
def test_spool_stroke_saturation_follows_its_rounded_corners(w):
    """rounded_unit (the spool's sat(u)) against its closed form across both corners and the straight part,
    and the corners join C1: value and slope continuous at 0, w, 1 - w and 1 (slope 0 at the stops, 1 on the
    straight part). The polynomial is evaluated two ways, so agreement is to rounding (abs 1e-12); the
    slopes are one-sided differences over h = 1e-7 of a cubic whose second derivative is at most 4/w, so
    they agree with the exact slope to 4/w*h (4e-5 at w = 0.01), checked at 1e-4."""
    xs = [-0.5, 0.0] + [w * k / 8 for k in range(1, 9)] + [0.5] + [1 - w * k / 8 for k in range(8, 0, -1)] + [1.0, 1.5]
    for x in xs:
        assert rounded_unit(x, w) == pytest.approx(rounded_unit_closed_form(x, w), abs=1e-12), x
    h = 1e-7
    for x, slope in ((0.0, 0.0), (w, 1.0), (1 - w, 1.0), (1.0, 0.0)):
        left = (rounded_unit(x, w) - rounded_unit(x - h, w)) / h
        right = (rounded_unit(x + h, w) - rounded_unit(x, w)) / h
        assert left == pytest.approx(slope, abs=1e-4) and right == pytest.approx(slope, abs=1e-4), x


def test_spool_stroke_saturation_without_rounding_is_the_plain_clip():
    """u_w = 0 (its declared lower bound): sat(u) = min(max(u, 0), 1), exact."""
    for x in (-1.0, 0.0, 1e-6, 0.3, 0.999, 1.0, 2.0):
        assert rounded_unit(x, 0.0) == min(max(x, 0.0), 1.0)


# ---------------------------------------------------------------- spool relief valve alone against its equations
SRV = dict(p_set=80e5, k_s=100e5, A_max=2e-5, c_ff=0.2, p_fric=3e5, u_z=1e-3, wn=300.0, zeta=0.7, u_w=0.01, Cd=0.7,
           dp_t=1e4, rho=RHO)


def srv(a, b, u, du, z, **over):
    return named(SpoolReliefValve, SpoolReliefValve.derivatives(a=a, b=b, u=u, du=du, z=z, **{**SRV, **over}))


@pytest.mark.parametrize("z", [-1.0, 0.0, 1.0])
@pytest.mark.parametrize("c_ff", [0.0, 0.2, -0.1])
def test_spool_relief_valve_rests_where_spring_flow_force_and_friction_balance(z, c_ff):
    """'At rest inside the stroke the opening solves u*k_s = dp - p_set - c_ff*u*dp' (with the Dahl friction
    p_fric*z on the right-hand side too): u = (dp - p_set - p_fric*z)/(k_s + c_ff*dp). A spool placed there
    at rest feels no acceleration, and one placed 0.05 of the stroke above feels the spring pull it back,
    wn^2*(u_eq - u) with u_eq the balance at its own opening (the flow force acting on that opening). All
    openings are on the straight part of sat(u) (u_w = 0.01), where sat(u) = u. The acceleration at the
    balance is a difference of terms of size wn^2 = 9e4 1/s^2, so it is zero to rounding, 1e-9."""
    a, b = 130e5, 4e5  # the outlet above the tank: the spring and the flow force see p_a - p_b
    dp = a - b
    p = dict(c_ff=c_ff)
    u_rest = (dp - SRV["p_set"] - SRV["p_fric"] * z) / (SRV["k_s"] + c_ff * dp)
    assert 0.05 < u_rest < 0.9
    d = srv(a, b, u_rest, 0.0, z, **p)
    assert d["der_u"] == 0.0 and d["der_z"] == 0.0  # at rest the friction state stays where it is
    assert d["der_du"] == pytest.approx(0.0, abs=1e-9)
    u = u_rest + 0.05
    u_eq = (dp - SRV["p_set"] - c_ff * u * dp - SRV["p_fric"] * z) / SRV["k_s"]
    assert srv(a, b, u, 0.0, z, **p)["der_du"] == pytest.approx(SRV["wn"] ** 2 * (u_eq - u), rel=1e-9)
    assert u_eq < u  # pulled back


def test_spool_relief_valve_flow_is_the_orifice_law_of_its_opening():
    """q = Cd*A_max*s*sqrt(2/rho)*dp/(dp^2 + dp_t^2)^(1/4) with s = sat(u) = u on the straight part: far above
    dp_t (here 126 bar against 0.1 bar) the square-root law Cd*A_max*u*sqrt(2*dp/rho) to (dp_t/dp)^2/4 ~ 2e-9,
    checked at 1e-6; a -> b for dp > 0, and what leaves a arrives at b."""
    a, b = 130e5, 4e5
    for u in (0.2, 0.5, 0.8):
        d = srv(a, b, u, 0.0, 0.0)
        assert d["q_b"] == pytest.approx(0.7 * 2e-5 * u * math.sqrt(2 * (a - b) / RHO), rel=1e-6)
        assert d["q_a"] == -d["q_b"]
    assert srv(a, b, 0.0, 0.0, 0.0)["q_b"] == 0.0  # shut: no leak


def test_spool_relief_valve_spool_dynamics_and_dahl_law():
    """u'' = wn^2*(sat(u_eq) - u) - 2*zeta*wn*u' and z' = (u' - z*|u'|)/u_z: at the balance opening the
    acceleration is the damping alone, -2*zeta*wn*u'; z settles at sign(u') (z' = 0 at z = +1 moving up,
    at z = -1 moving down) and from z = 0 it moves at u'/u_z. Exact laws; rel 1e-9 allows the rounding."""
    a, b, z = 130e5, 4e5, 0.0
    dp = a - b
    u = (dp - SRV["p_set"]) / (SRV["k_s"] + SRV["c_ff"] * dp)
    for du in (0.5, -0.5):
        d = srv(a, b, u, du, z)
        assert d["der_u"] == du
        assert d["der_du"] == pytest.approx(-2 * SRV["zeta"] * SRV["wn"] * du, rel=1e-9)
        assert d["der_z"] == pytest.approx(du / SRV["u_z"], rel=1e-12)
        assert srv(a, b, u, du, math.copysign(1.0, du))["der_z"] == 0.0
        # against the motion the friction state turns round at twice the rate
        assert srv(a, b, u, du, -math.copysign(1.0, du))["der_z"] == pytest.approx(2 * du / SRV["u_z"], rel=1e-12)


# ---------------------------------------------------------------- the cavitation law: cavity volume and compliance


@pytest.mark.parametrize("below", [0.0, 0.1 * CAVITY_ONSET, 0.5 * CAVITY_ONSET, 0.9 * CAVITY_ONSET, CAVITY_ONSET,
                                   1.5 * CAVITY_ONSET, 0.3e5, 2e5])
def test_cavity_volume_is_the_integral_of_the_compliance_beyond_the_liquids(below):
    """The module's law: a net's compliance C(p) = dV/dp is the liquid's V/beta above p_vap and
    w*V/beta + (1 - w)*C_cav below (dp/dt = q/C(p), read back from cavitating_pressure_rate with q = 1), and
    the cavity at p is V_cav = integral from p to p_vap of (C(u) - V/beta) du. That integrand is
    (1 - w)*(C_cav - V/beta), so V_cav = (1 - V/(beta*C_cav))*cavity_volume(p): checked by quadrature
    (scipy's quad, with the onset band's edge as a break point; rel 1e-9, far above its error on a cubic),
    inside the onset band as well as beyond it. Also the cavity is 0 at p_vap and grows as p falls."""
    p_vap, beta, V = -0.9e5, 8e8, 1e-3
    p = p_vap - below

    def excess(u):
        return 1.0 / cavitating_pressure_rate(u, beta, V, 1.0, p_vap) - V / beta

    if below == 0.0:
        assert cavity_volume(p, p_vap) == 0.0
        return
    edge = p_vap - CAVITY_ONSET
    points = [edge] if p < edge else None
    integral, _ = quad(excess, p, p_vap, points=points, epsabs=0.0, epsrel=1e-12, limit=200)
    assert integral == pytest.approx((1.0 - V / (beta * CAVITY_COMPLIANCE)) * cavity_volume(p, p_vap), rel=1e-9)
    assert cavity_volume(p, p_vap) > cavity_volume(p + 0.01 * below, p_vap)


def test_the_liquid_above_the_vapour_pressure_and_the_cavity_far_below_it():
    """Above (and at) p_vap: dp/dt = beta/V*q exactly (the liquid); from CAVITY_ONSET below on: the cavity's
    compliance alone, dp/dt = q/C_cav, and the cavity grows by C_cav per pascal (0.1 bar per litre), with the
    onset band holding C_cav*dp_onset/2 (the smoothstep's mean is 1/2). Exact laws; rel 1e-12."""
    p_vap, beta, V, q = -0.9e5, 8e8, 1e-3, -2e-4
    for p in (p_vap, 0.0, 200e5):
        assert cavitating_pressure_rate(p, beta, V, q, p_vap) == beta / V * q
    for below in (CAVITY_ONSET, 2 * CAVITY_ONSET, 1e5):
        assert cavitating_pressure_rate(p_vap - below, beta, V, q, p_vap) == pytest.approx(q / CAVITY_COMPLIANCE,
                                                                                          rel=1e-12)
        assert cavity_volume(p_vap - below, p_vap) == pytest.approx(
            CAVITY_COMPLIANCE * (below - CAVITY_ONSET / 2), rel=1e-12)


# ---------------------------------------------------------------- the pipe alone: mass and its flow's sign


@pytest.mark.parametrize("q", [2e-4, -2e-4])
def test_pipe_moves_oil_from_a_to_b_and_stores_none_in_flight(q):
    """'q > 0 flows from a to b: the block delivers -q to net a and +q to net b': what leaves one end arrives
    at the other (the pipe's oil is the two half volumes stored on the end nets, so the flows must sum to 0),
    for either direction. A laminar flow (2e-4 m^3/s in 20 mm at nu = 46e-6: Re 277) held by exactly its
    Hagen-Poiseuille drop 128*mu*l*q/(pi*d^4) neither speeds up nor slows down (dq/dt = 0 to rounding of a
    difference of ~1e5 Pa terms, scaled by A/(rho*l): 1e-9 of the unbalanced rate)."""
    l, d, rho, nu = 5.0, 0.02, 870.0, 46e-6
    drop = 128 * rho * nu * l * q / (math.pi * d ** 4)
    out = named(Pipe, Pipe.derivatives(a=50e5 + drop, b=50e5, q=q, l=l, d=d, rho=rho, nu=nu))
    assert out["q_a"] == -q and out["q_b"] == q
    half = math.pi * d * d / 4 * l / 2
    assert out["V_a"] == pytest.approx(half, rel=1e-12) and out["V_b"] == pytest.approx(half, rel=1e-12)
    unbalanced = abs(drop) * (math.pi * d * d / 4) / (rho * l)
    assert abs(out["der_q"]) <= 1e-9 * unbalanced


# ---------------------------------------------------------------- entrained air below the vapour pressure


@pytest.mark.parametrize("air", [0.0, 0.01])
def test_aerated_net_below_the_vapour_pressure_without_cavitation_keeps_the_mixture_at_p_vap(air):
    """'dp/dt = sum(q) / (V/beta_e(p_vap)), p < p_vap (cavitation: false)': the mixture's compliance frozen at
    the vapour pressure, so dp/dt is continuous at p_vap (the rate just above it, beta_e(p_vap)/V*q) and the
    same at any depth below it. Exact laws, one division each way: rel 1e-12."""
    p_vap, beta, V, q, n = -0.9e5, 8e8, 1e-3, -2e-4, 1.0
    at_vap = effective_bulk_modulus(p_vap, beta, air, n) / V * q
    assert aerated_pressure_rate(p_vap, beta, V, q, p_vap, air, n, True) == pytest.approx(at_vap, rel=1e-12)
    for below in (1.0, 1e4, 5e5):
        assert aerated_pressure_rate(p_vap - below, beta, V, q, p_vap, air, n, False) == pytest.approx(at_vap,
                                                                                                      rel=1e-12)
