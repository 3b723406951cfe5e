"""The crane's own blocks (vphs_blocks/) against laws their existing tests did not pin down; written from a
mutation test of those files (session 26), one law per test.

Tier 1: each block alone, its raw equation functions called by keyword (as in test_valves_motors.py and
test_mcv.py), checked against
- pressure-level invariance: a hydraulic component's flows, forces and torques depend on the differences of
  its port pressures only (oil is taken incompressible inside it), so adding one common p0 to every port
  (above the vapour pressure) changes nothing;
- mirror symmetry: a valve whose two lines are built alike swaps its outputs when the lines are swapped;
- closed forms written here from the docstrings' equations.

Tolerances: adding p0 = 50 bar to pressures of a few hundred bar and subtracting again loses at most an ulp
of 5e7 Pa (1e-8 Pa) in a difference of >= 1 bar: relative 1e-13 in each flow; rel 1e-9 leaves room for the
sqrt and the polynomials and still catches any change a sign or factor would make (>= 1e-3 at the points
chosen). Closed forms evaluated here in the same floating-point operations: rel 1e-12.
"""

from __future__ import annotations

import math

import pytest

from blocks.block import argument_names
from blocks.units import quantity
from vphs_blocks.lga_jib_load import LgaJibLoad
from vphs_blocks.mcv_vaa import MotionControlValveVAA as VAA
from vphs_blocks.mcv_vbso import OverCentreValveVBSO as VBSO
from vphs_blocks.motor_f12 import ParkerMotor
from vphs_blocks.pvg32 import PVG32
from vphs_blocks.servo_valve_4wrle import Servo4WRLE

RHO, CD = 850.0, 0.7
BAR = 1e5
INVARIANT = 1e-9


def preset(cls, name: str) -> dict[str, float]:
    """A preset's values in SI over the block's defaults (rho = 850 kg/m^3, beta = 8e8 Pa, p_vap = -1 bar)."""
    values = {p.name: p.default for p in cls.params if p.default is not None}
    values.update(rho=RHO, beta=8e8, p_vap=-1e5)
    for key, raw in cls.presets[name].items():
        values[key] = quantity(raw, cls.param(key).unit)
    return values


def derivs(cls, values: dict) -> dict[str, float]:
    """The block's derivatives called by argument name, returned by the names the block declares."""
    out = cls.derivatives(**{name: values[name] for name in argument_names(cls.derivatives)})
    names = cls.derivative_names()
    assert len(out) == len(names)
    return dict(zip(names, out))


def turbulent(dp, area, dp_t, cd=CD, rho=RHO):
    """The regularised orifice law of the docstrings, written out: Cd*A*sqrt(2/rho)*dp/(dp^2 + dp_t^2)^(1/4)."""
    return cd * area * math.sqrt(2.0 / rho) * dp / (dp * dp + dp_t * dp_t) ** 0.25


def same(a: dict, b: dict, keys, rel=INVARIANT):
    for k in keys:
        assert a[k] == pytest.approx(b[k], rel=rel, abs=1e-30), k


# ================================================================ Parker motor
def motor_values(**kw):
    return preset(ParkerMotor, "F12-030") | dict(a=0.0, b=0.0, drain=0.0, shaft=0.0) | kw


@pytest.mark.parametrize("w", [0.0, 80.0, -80.0])
def test_motor_depends_only_on_pressure_differences(w):
    """Flows and torque of the motor are functions of p_a - p_b, p_a - p_drain and p_b - p_drain (section
    2.5: leakages are orifices): the same motor with every port 50 bar higher delivers the same flows and
    torque (both levels above the vapour pressure, so the chambers' fill is 1 in both)."""
    base = dict(a=180 * BAR, b=30 * BAR, drain=2 * BAR, shaft=w)
    d0 = derivs(ParkerMotor, motor_values(**base))
    d1 = derivs(ParkerMotor, motor_values(**{k: (v + 50 * BAR if k != "shaft" else v) for k, v in base.items()}))
    same(d0, d1, ("q_a", "q_b", "q_drain", "tau_shaft"))


def test_motor_drain_leakage_is_the_orifice_law_with_drain_pressure():
    """q_drain = q_da + q_db, each the orifice law across (p_a - p_drain) and (p_b - p_drain) (section 2.5,
    fig. 2.26), with a case pressure of 3 bar: the drain's back pressure reduces both leaks."""
    v = motor_values(a=150 * BAR, b=40 * BAR, drain=3 * BAR, shaft=0.0, A_ld=1e-7)
    d = derivs(ParkerMotor, v)
    q_da = turbulent(147 * BAR, 1e-7, v["dp_t"])
    q_db = turbulent(37 * BAR, 1e-7, v["dp_t"])
    assert d["q_drain"] == pytest.approx(q_da + q_db, rel=1e-12)
    assert d["q_b"] == pytest.approx(turbulent(110 * BAR, v["A_lm"], v["dp_t"]) - q_db, rel=1e-12)


# ================================================================ VBSO over-centre valve
def vbso_values(**kw):
    return preset(VBSO, "05.42.05-10-04-35") | {"alpha": 3.2, "p_crack1": 100 * BAR, "p_crack2": 230 * BAR,
                                               "u1": 0.0, "du1": 0.0, "u2": 0.0, "du2": 0.0} | kw


VBSO_OUT = ("q_V1", "q_V2", "q_C1", "q_C2", "der_u1", "der_du1", "der_u2", "der_du2")


@pytest.mark.parametrize("ports", [
    dict(V1=120 * BAR, V2=20 * BAR, C1=60 * BAR, C2=260 * BAR, u1=0.4, u2=0.3),   # relief 2 piloted open
    dict(V1=20 * BAR, V2=125 * BAR, C1=140 * BAR, C2=121 * BAR, u1=0.5, u2=0.02),  # relief 1 piloted, check 2 open
    dict(V1=90 * BAR, V2=10 * BAR, C1=88 * BAR, C2=8 * BAR, u1=0.0, u2=0.0),       # both checks passing oil
])
def test_vbso_depends_only_on_pressure_differences(ports):
    """Every flow and spool equilibrium of eqs. 2.19-2.25 is written in pressure differences (the pilot
    force alpha*Ar*(pv1 - pv2), the spring's net pressure p_C - p_V - p_cr): a common 50 bar on all four
    ports changes nothing."""
    d0 = derivs(VBSO, vbso_values(**ports))
    shifted = {k: (v + 50 * BAR if k in ("V1", "V2", "C1", "C2") else v) for k, v in ports.items()}
    d1 = derivs(VBSO, vbso_values(**shifted))
    same(d0, d1, VBSO_OUT)


def test_vbso_lines_are_mirror_images():
    """The two lines of fig. 2.23 are built alike: swapping V1 <-> V2, C1 <-> C2, the spools and the line
    settings (p_crack, kp) swaps every output line for line."""
    p = dict(V1=110 * BAR, V2=12 * BAR, C1=70 * BAR, C2=150 * BAR, u1=0.2, du1=0.5, u2=0.6, du2=-1.0)
    d = derivs(VBSO, vbso_values(**p, kp1=800 * BAR, kp2=950 * BAR))
    m = derivs(VBSO, vbso_values(V1=p["V2"], V2=p["V1"], C1=p["C2"], C2=p["C1"], u1=p["u2"], du1=p["du2"],
                                 u2=p["u1"], du2=p["du1"], p_crack1=230 * BAR, p_crack2=100 * BAR,
                                 kp1=950 * BAR, kp2=800 * BAR))
    for k1, k2 in (("q_V1", "q_V2"), ("q_C1", "q_C2"), ("der_u1", "der_u2"), ("der_du1", "der_du2")):
        assert d[k1] == pytest.approx(m[k2], rel=1e-12, abs=1e-30)
        assert d[k2] == pytest.approx(m[k1], rel=1e-12, abs=1e-30)


def test_vbso_line_2_check_valve_is_table_2_10():
    """Check valve V2 -> C2 (table 2.10: crack 0.5 bar, fully open 82 mm^2 at 2.2 bar): at 5 bar across it
    the full area passes the orifice law, into C2 and out of V2; none flows back C2 -> V2 but the relief's
    closed leak (u2 = 0: relief area exactly 0, check valve's leak A_leak)."""
    v = vbso_values(V1=0.0, V2=65 * BAR, C1=0.0, C2=60 * BAR)
    d = derivs(VBSO, v)
    q = turbulent(5 * BAR, v["A_cv"], v["dp_t"])
    assert d["q_C2"] == pytest.approx(q, rel=1e-12)
    assert d["q_V2"] == pytest.approx(-q, rel=1e-12)
    back = derivs(VBSO, vbso_values(V1=0.0, V2=60 * BAR, C1=0.0, C2=65 * BAR))
    assert back["q_V2"] == pytest.approx(-turbulent(-5 * BAR, v["A_leak"], v["dp_t"]), rel=1e-12)


# ================================================================ PVG 32 and 4WRLE

VALVE_OUT = ("q_P", "q_T", "q_A", "q_B", "der_x", "der_dx")


def pvg_values(**kw):
    return preset(PVG32, "jib_tilt") | dict(u=0.0, x=0.0, dx=0.0) | kw


def servo_values(**kw):
    return preset(Servo4WRLE, "4WRLE16") | dict(u=0.0, x=0.0, dx=0.0) | kw


@pytest.mark.parametrize("spool_mm", [5.0, -5.0, 0.5, 3.0])
def test_pvg_depends_only_on_pressure_differences(spool_mm):
    """The compensator's law (section 2.3.3) reads p_LS - p_port and p_P - p_port, the edges p_X - p_T: a
    common 50 bar on the four ports and on both LS settings changes no flow (tank at 4 bar, a return
    pressure the ports see through the return edges)."""
    ports = dict(P=210 * BAR, T=4 * BAR, A=120 * BAR, B=60 * BAR, u=0.3, x=spool_mm * 1e-3, dx=0.01)
    d0 = derivs(PVG32, pvg_values(**ports))
    v = pvg_values(**{k: (p + 50 * BAR if k in "PTAB" else p) for k, p in ports.items()})
    v["p_LS_A"] += 50 * BAR
    v["p_LS_B"] += 50 * BAR
    d1 = derivs(PVG32, v)
    same(d0, d1, VALVE_OUT)


@pytest.mark.parametrize("x", [0.6, -0.6, 0.1, -0.1, 0.0])
def test_servo_depends_only_on_pressure_differences(x):
    """Each 4WRLE edge is an orifice across a pressure difference (section 2.2): a common 50 bar on P, T,
    A and B (tank at 3 bar) changes no flow."""
    ports = dict(P=200 * BAR, T=3 * BAR, A=140 * BAR, B=40 * BAR, u=0.5, x=x, dx=0.2)
    d0 = derivs(Servo4WRLE, servo_values(**ports))
    d1 = derivs(Servo4WRLE, servo_values(**{k: (p + 50 * BAR if k in "PTAB" else p) for k, p in ports.items()}))
    same(d0, d1, VALVE_OUT)


# ================================================================ VAA motion-control valve
def vaa_values(**kw):
    return preset(VAA, "VF250") | {"alpha": 2.8, "p_crack": 230 * BAR, "u1": 0.0, "du1": 0.0, "u2": 0.0,
                                   "du2": 0.0, "pt": 0.0} | kw


VAA_OUT = ("q_V1", "q_V2", "q_C1", "q_C2", "der_pt", "der_u1", "der_du1", "der_u2", "der_du2")


@pytest.mark.parametrize("flow_force", [0.0, 1.0])
@pytest.mark.parametrize("ports", [
    dict(V1=60 * BAR, V2=8 * BAR, C1=150 * BAR, C2=240 * BAR, pt=6 * BAR, u1=0.3, u2=0.5, du1=0.4, du2=-0.2),
    dict(V1=9 * BAR, V2=70 * BAR, C1=245 * BAR, C2=5 * BAR, pt=12 * BAR, u1=0.6, u2=0.0),
    dict(V1=40 * BAR, V2=30 * BAR, C1=36 * BAR, C2=25 * BAR, pt=32 * BAR, u1=0.0, u2=0.0),
])
def test_vaa_depends_only_on_pressure_differences(ports, flow_force):
    """The VAA's equations (2.4, 2.7-2.15, 3.13) read only pressure differences (p_C - pt, p_pilot - pt,
    V - C, pt - V): a common 50 bar on V1, V2, C1, C2 and the inner node pt changes nothing."""
    d0 = derivs(VAA, vaa_values(**ports, flow_force=flow_force))
    shifted = {k: (p + 50 * BAR if k in ("V1", "V2", "C1", "C2", "pt") else p) for k, p in ports.items()}
    d1 = derivs(VAA, vaa_values(**shifted, flow_force=flow_force))
    same(d0, d1, VAA_OUT)


@pytest.mark.parametrize("u", [1.0, 1.05, 1.5, 40.0])
def test_pvg_command_saturates_at_full_stroke(u):
    """u is saturated to [-1, 1] (the docstring's u_c = min(max(u, -1), 1)): any u >= 1 demands x_max, so the
    spool resting at +x_max has no acceleration (and -u at -x_max likewise); a demand beyond the stroke would
    push it on."""
    v = pvg_values(P=100 * BAR, T=0.0, A=50 * BAR, B=50 * BAR)
    for sign in (1.0, -1.0):
        d = derivs(PVG32, v | dict(u=sign * u, x=sign * v["x_max"], dx=0.0))
        assert d["der_dx"] == 0.0 and d["der_x"] == 0.0


# ================================================================ LGA loads


def block_defaults(cls, **kw):
    return {p.name: p.default for p in cls.params if p.default is not None} | kw


@pytest.mark.parametrize("k_vel", [0.25, 0.5, 0.8])
def test_jib_lagrange_term_is_weighted_linearly_by_k_vel(k_vel):
    """f_rod = -Fc1 - k_vel*1/2*dm1_eff/dd1*v^2 (eq. 2.64 with the Lagrange term, k_vel its weight in
    [0, 1]): f is affine in k_vel, so f(k) = (1 - k)*f(0) + k*f(1); the mass does not depend on k_vel.
    At theta1 = 64.5 deg and v = 0.07 m/s the term is 0.45 % of the weight (test_mechanics.py), far above
    the rel 1e-12 used."""
    v = block_defaults(LgaJibLoad, d1_0=2.3, x1=0.25, x2=0.4, rod=0.07)
    f0, m0 = LgaJibLoad.derivatives(**{k: x for k, x in (v | {"k_vel": 0.0}).items() if k in argument_names(LgaJibLoad.derivatives)})
    f1, m1 = LgaJibLoad.derivatives(**{k: x for k, x in (v | {"k_vel": 1.0}).items() if k in argument_names(LgaJibLoad.derivatives)})
    fk, mk = LgaJibLoad.derivatives(**{k: x for k, x in (v | {"k_vel": k_vel}).items() if k in argument_names(LgaJibLoad.derivatives)})
    assert abs(f1 - f0) > 1e-3 * abs(f0)
    assert fk == pytest.approx((1.0 - k_vel) * f0 + k_vel * f1, rel=1e-12)
    assert m0 == m1 == mk


def test_unrounded_saturation_is_the_plain_clip():
    """u_w = 0 (no rounding of the saturation's corners) is the plain clip of u to [0, 1] (mcv_vaa.smooth_unit's
    docstring): a relief at u1 = 0.3 then opens exactly 0.3*A_prv (eq. 2.24), one at u1 = 1.4 exactly A_prv,
    one at u1 = -0.2 none."""
    from vphs_blocks.mcv_vaa import smooth_unit

    for x, clip in ((-0.2, 0.0), (0.0, 0.0), (0.004, 0.004), (0.3, 0.3), (0.999, 0.999), (1.4, 1.0)):
        assert smooth_unit(x, 0.0) == clip
    for u1, opening in ((0.3, 0.3), (1.4, 1.0), (-0.2, 0.0)):
        v = vbso_values(V1=0.0, V2=0.0, C1=20 * BAR, C2=0.0, u1=u1, u_w=0.0)
        d = derivs(VBSO, v)
        relief = turbulent(20 * BAR, opening * v["A_prv"], v["dp_t"])
        check_back = turbulent(-20 * BAR, v["A_leak"], v["dp_t"])
        assert d["q_V1"] == pytest.approx(relief - check_back, rel=1e-12)


def test_jib_pose_beyond_the_range_returns_the_end_and_its_length():
    """jib_pose clamps theta1 to the nearer end of [lo, hi] and returns that end's own cylinder length d1 =
    |A1*c - b| (eq. 2.31: a length, positive) and k1 = 0 (the jib does not turn)."""
    from vphs_blocks.lga_geometry import cylinder_length, jib_pose, thesis_geometry

    g = thesis_geometry()
    lo, hi = math.radians(0.0), math.radians(90.0)
    d_lo, d_hi = cylinder_length(lo, g), cylinder_length(hi, g)
    for d1 in (max(d_lo, d_hi) + 0.3, min(d_lo, d_hi) - 0.3):
        theta, d, k1 = jib_pose(d1, g, lo, hi)
        assert theta in (lo, hi)
        assert d == pytest.approx(cylinder_length(theta, g), rel=1e-15) and d > 0.0
        assert k1 == 0.0
    # inside the range the pose is the given length's own (round trip) and k1 = d1/h
    theta, d, k1 = jib_pose(0.5 * (d_lo + d_hi), g, lo, hi)
    assert lo < theta < hi and d == 0.5 * (d_lo + d_hi)
    assert cylinder_length(theta, g) == pytest.approx(d, rel=1e-12)
