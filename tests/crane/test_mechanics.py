"""The crane's mechanics (issue 3, part C): bridge-crane axis inertias, tool point, lower guiding arm (LGA).

Tier 1: the functions of vphs_blocks.lga_geometry and the blocks' raw equation functions (called by
keyword) against routes written here independently: the thesis's printed eq. 2.31 (in mm) run forwards, the
closed-form inverse theta1 = phi + acos(...), the printed constants C1, C2 of eq. 2.33, finite differences,
kinetic energy, parallel-axis sums typed out by hand from the thesis's numbers, table 2.14, eqs. 2.66-2.67.
Tier 2: one netlist (written to a temporary folder) with three independent circuits: a mass-less cylinder
fed by a flow source retracts the telescope against its weight and settles at p_B = Fc2/A_B; a cylinder
lifts the jib and settles at p_A = Fc1/A_A; the jib coasts with g = 0 and keeps its kinetic energy.

Tolerances: the geometry is exact up to round-off (the Newton inverse converges to 1e-15 rad; dtheta/dd1 is
at most 11 on [0, 90 deg]), so round trips and identities use 1e-12; finite differences with step 1e-5
(central, error ~ step^2 * third derivative ~ 1e-10 relative) use 1e-7. The circuits run at rtol = atol =
1e-9; their static end states are reached to e^-25 or better (decay rates and times in the netlist's
comments), so 1e-6 relative leaves a margin of 100x over the accumulated solver error while any sign,
area or factor error misses by 10 % or more.
"""

from __future__ import annotations

import inspect
import math
import textwrap

import numpy as np
import pytest

from blocks.circuit import Circuit
from blocks.units import quantity
from vphs_blocks import lga_geometry as lga
from vphs_blocks.bc_axis_inertia import BcAxisInertia
from vphs_blocks.lga_jib_load import LgaJibLoad
from vphs_blocks.lga_telescope_load import LgaTelescopeLoad
from vphs_blocks.tool_point import ToolPoint

G = lga.thesis_geometry()
HALF_PI = math.pi / 2.0
GRAV = 9.81

# The thesis's numbers, typed here again (section 2.8), SI.
M1, M2, M3 = 401.3, 265.2, 175.2
S1, L1, S2, L2 = 0.300, 3.0, 0.250, 3.13
A3, B3, C3 = 1.26, 0.40, 0.43
C1_MM2, C2_MM2 = -263500.0, -1698025.0  # eq. 2.33


def d1_thesis(theta: float) -> float:
    """Eq. 2.31 as printed (mm), returned in m."""
    c, s = math.cos(theta), math.sin(theta)
    return math.sqrt((2191 * c - 340 * s + 775) ** 2 + (2191 * s + 340 * c) ** 2) / 1000.0


def theta_closed_form(d1: float) -> float:
    """Eq. 2.31 inverted in closed form: d1^2 = K0 + K1 cos t + K2 sin t = K0 + R cos(t - phi) (mm^2)."""
    k0 = 2191.0**2 + 340.0**2 + 775.0**2
    k1, k2 = 2.0 * 775.0 * 2191.0, -2.0 * 775.0 * 340.0
    phi = math.atan2(k2, k1)
    return phi + math.acos(((d1 * 1000.0) ** 2 - k0) / math.hypot(k1, k2))


def lever_thesis(theta: float) -> float:
    """d1*dd1/dtheta1 from eq. 2.33's printed constants, m^2."""
    return (C1_MM2 * math.cos(theta) + C2_MM2 * math.sin(theta)) * 1e-6


def x_g_by_hand(theta: float, d2: float) -> float:
    """Horizontal centre of parts 1-3 (eq. 2.55), the three centres written out."""
    c, s = math.cos(theta), math.sin(theta)
    x1 = 1.5 * c - 0.05 * s
    x2 = (d2 + 1.565) * c - (-0.05 + 0.075) * s
    x3 = (d2 + 3.13) * c - (-0.05) * s + 0.63  # the telescope's tip, then the horizontal gripper's centre
    return (M1 * x1 + M2 * x2 + M3 * x3) / (M1 + M2 + M3)


def jib_defaults(**overrides) -> dict:
    values = {p.name: p.default for p in LgaJibLoad.params if p.default is not None}
    values.update(overrides)
    return values


def call(fn, values: dict):
    """Call an equation function as the compiler does: by argument name."""
    return fn(**{name: values[name] for name in inspect.signature(fn).parameters})


# ---------------------------------------------------------------------------------------------- kinematics
def test_theta1_round_trip_over_the_range():
    """theta1_from_d1(d1(theta)) = theta over [0, 90 deg] and over nearly the whole monotonic branch, d1 from
    the printed eq. 2.31; agrees with the closed-form inverse; d1 beyond the range clamps to its ends."""
    for lo, hi in ((0.0, HALF_PI), (math.radians(-8.0), math.radians(170.0))):
        for theta in np.linspace(lo, hi, 241):
            d1 = d1_thesis(theta)
            assert lga.cylinder_length(theta, G) == pytest.approx(d1, rel=1e-14)
            got = lga.theta1_from_d1(d1, G, lo, hi)
            assert abs(got - theta) < 1e-12, (math.degrees(theta), got - theta)
            assert abs(got - theta_closed_form(d1)) < 1e-12
    assert lga.theta1_from_d1(d1_thesis(0.0) + 0.01, G, 0.0, HALF_PI) == 0.0
    assert lga.theta1_from_d1(d1_thesis(HALF_PI) - 0.01, G, 0.0, HALF_PI) == HALF_PI
    # the thesis's dead centres (h = 0): d1 is extreme there
    lo, hi = lga.dead_centres(G)
    assert math.degrees(lo) == pytest.approx(-8.8208, abs=1e-4)
    assert math.degrees(hi) == pytest.approx(171.1792, abs=1e-4)
    assert abs(lga.lever(lo, G)) < 1e-14 and abs(lga.lever(hi, G)) < 1e-14


def test_theta1_inverse_for_random_brackets():
    """Any bracket on the monotonic branch, at least 0.01 rad from the dead centres (where d1 is stationary
    and theta1 ill-conditioned): the result lies in the bracket and inverts eq. 2.31 (round-off there is
    ~2e-15*d1^2/(2*|h|) < 1e-12 rad)."""
    dead_lo, dead_hi = lga.dead_centres(G)
    rng = np.random.default_rng(20240521)
    for _ in range(2000):
        lo, hi = np.sort(rng.uniform(dead_lo + 0.01, dead_hi - 0.01, 2))
        theta = rng.uniform(lo, hi)
        got = lga.theta1_from_d1(d1_thesis(theta), G, lo, hi)
        assert lo <= got <= hi and abs(got - theta) < 1e-11, (lo, hi, theta, got)


def test_lever_is_eq_2_33_with_the_printed_constants():
    """h = d1*dd1/dtheta1 from the geometry equals C1 cos + C2 sin with C1 = -263500, C2 = -1698025 mm^2."""
    for theta in np.linspace(-0.5, 3.0, 50):
        assert lga.lever(theta, G) == pytest.approx(lever_thesis(theta), rel=1e-12, abs=1e-15)
        # and it is the derivative of d1^2/2, its slope that of h: central differences with step 1e-4 have a
        # truncation error <= step^2/6 * max|third derivative| = 1e-8/6 * 1.72 m^2, round-off ~ 1e-11 m^2
        eps = 1e-4
        fd = (lga.cylinder_length(theta + eps, G) ** 2 - lga.cylinder_length(theta - eps, G) ** 2) / (4 * eps)
        assert lga.lever(theta, G) == pytest.approx(fd, rel=0, abs=1e-8)
        fd_slope = (lga.lever(theta + eps, G) - lga.lever(theta - eps, G)) / (2 * eps)
        assert lga.lever_slope(theta, G) == pytest.approx(fd_slope, rel=0, abs=1e-8)


def test_theta1_dot_against_a_finite_difference():
    """theta1_dot(d1, d1_dot, theta1) (eq. 2.35) against d/dt of theta1(d1(t)), d1(t) = 2.6 + 0.3 sin(1.7 t)."""
    step = 1e-5
    for t in np.linspace(0.0, 3.0, 13):
        d1 = 2.6 + 0.3 * math.sin(1.7 * t)
        d1_dot = 0.3 * 1.7 * math.cos(1.7 * t)
        theta = lga.theta1_from_d1(d1, G, 0.0, HALF_PI)
        fd = (lga.theta1_from_d1(2.6 + 0.3 * math.sin(1.7 * (t + step)), G, 0.0, HALF_PI)
              - lga.theta1_from_d1(2.6 + 0.3 * math.sin(1.7 * (t - step)), G, 0.0, HALF_PI)) / (2 * step)
        got = lga.theta1_dot(d1, d1_dot, theta, G)
        assert got == pytest.approx(fd, rel=1e-7, abs=1e-11)
        assert got * d1_dot <= 0.0  # extending the cylinder lowers theta1 (lifts the arm)


# ---------------------------------------------------------------------------------------------- inertias
def test_jib_inertia_by_the_parallel_axis_theorem():
    """J_A (eqs. 2.55-2.58, via the centre of gravity) equals the sum of each part's own transverse inertia
    plus m*r^2 to joint A, typed out for theta1 = 0, d2 = 0.5 m with the thesis's numbers."""
    d2 = 0.5
    j1 = 7 / 24 * M1 * S1**2 + M1 * L1**2 / 12 + M1 * (1.5**2 + 0.05**2)
    j2 = 7 / 24 * M2 * S2**2 + M2 * L2**2 / 12 + M2 * ((d2 + 1.565) ** 2 + 0.025**2)
    j3 = M3 * (A3**2 + C3**2) / 12 + M3 * ((d2 + 3.13 + 0.63) ** 2 + 0.05**2)
    assert lga.jib_inertia(0.0, d2, G) == pytest.approx(j1 + j2 + j3, rel=1e-12)


def test_jib_inertia_rigid_body_and_slope():
    """With the gripper's centre at the telescope tip (xi3 = eta3 = 0) parts 1-3 are one rigid body about A:
    J_A does not depend on theta1. With the thesis's horizontal gripper offset it does, and the analytic
    slope dJ_A/dtheta1 matches a finite difference."""
    rigid = G._replace(xi3=0.0, eta3=0.0)
    reference = lga.jib_inertia(0.0, 0.3, rigid)
    for theta in np.linspace(-0.1, 1.6, 9):
        assert lga.jib_inertia(theta, 0.3, rigid) == pytest.approx(reference, rel=1e-12)
        assert abs(lga.jib_inertia_slope(theta, 0.3, rigid)) < 1e-9
        eps = 1e-6
        fd = (lga.jib_inertia(theta + eps, 0.3, G) - lga.jib_inertia(theta - eps, 0.3, G)) / (2 * eps)
        assert lga.jib_inertia_slope(theta, 0.3, G) == pytest.approx(fd, rel=1e-7, abs=1e-6)


def test_effective_mass_from_kinetic_energy():
    """1/2*m1_eff*d1_dot^2 = 1/2*J_A*theta1_dot^2 (eqs. 2.59-2.61), theta1_dot from a finite difference of
    the inverse theta1(d1) (not from eq. 2.35); and the magnitude the thesis's LGA gives at the range ends."""
    d1_dot, eps = 0.05, 1e-6
    for theta in np.linspace(0.0, HALF_PI, 7):
        for d2 in (0.0, 0.8):
            d1 = d1_thesis(theta)
            dtheta_dd1 = (lga.theta1_from_d1(d1 + eps, G, -0.1, 1.7)
                          - lga.theta1_from_d1(d1 - eps, G, -0.1, 1.7)) / (2 * eps)
            kinetic_rot = 0.5 * lga.jib_inertia(theta, d2, G) * (dtheta_dd1 * d1_dot) ** 2
            kinetic_lin = 0.5 * lga.jib_effective_mass(theta, d1, d2, G) * d1_dot**2
            assert kinetic_lin == pytest.approx(kinetic_rot, rel=1e-7)
    # the moment arm of the cylinder about A is |h|/d1: 88 mm at theta1 = 0, 760 mm at 90 deg
    assert abs(lga.lever(0.0, G)) / d1_thesis(0.0) == pytest.approx(0.08826, abs=1e-5)
    assert lga.jib_effective_mass(0.0, d1_thesis(0.0), 0.0, G) / lga.jib_effective_mass(
        HALF_PI, d1_thesis(HALF_PI), 0.0, G) > 80.0


def test_effective_mass_slope_against_a_finite_difference():
    """dm1_eff/dd1 (the Lagrange term's m') against a central difference of m1_eff(theta1(d1), d1)."""
    def mass(d1, d2):
        return lga.jib_effective_mass(lga.theta1_from_d1(d1, G, -0.1, 1.7), d1, d2, G)

    eps = 1e-5
    for theta in np.linspace(0.05, 1.55, 9):
        for d2 in (0.0, 1.0):
            d1 = d1_thesis(theta)
            fd = (mass(d1 + eps, d2) - mass(d1 - eps, d2)) / (2 * eps)
            got = lga.jib_effective_mass_slope(theta, d1, d2, G)
            assert got == pytest.approx(fd, rel=1e-6)
            assert got > 0.0  # the mass grows towards the horizontal (longer d1)


def test_slewing_and_trolley_inertias_by_hand():
    """J_S (eqs. 2.46-2.51) typed out at theta1 = 0 and 90 deg (d2 = 0, e = 0.6 m); the gearing of eqs.
    2.52-2.53; the trolley's eq. 2.54 with n_g^2 (the printed n_g would be 39.1 times larger)."""
    e = 0.6
    j4 = 362.0 * (1.2**2 + 0.6**2) / 2
    assert lga.disc_inertia(362.0, 1.2, 0.6) == pytest.approx(325.8, rel=1e-12)
    trans1 = 7 / 24 * M1 * S1**2 + M1 * L1**2 / 12
    trans2 = 7 / 24 * M2 * S2**2 + M2 * L2**2 / 12
    j3_eta = M3 * (A3**2 + B3**2) / 12
    at_0 = (M1 * (e + 1.5) ** 2 + trans1 + M2 * (e + 1.565) ** 2 + trans2
            + M3 * (e + 3.13 + 0.63) ** 2 + j3_eta + j4)
    at_90 = (M1 * (e - 0.05) ** 2 + M1 * S1**2 / 3 + M2 * (e - 0.025) ** 2 + M2 * S2**2 / 3
             + M3 * (e + 0.05 + 0.63) ** 2 + j3_eta + j4)
    assert lga.slewing_inertia(0.0, 0.0, e, j4, G) == pytest.approx(at_0, rel=1e-12)
    assert lga.slewing_inertia(HALF_PI, 0.0, e, j4, G) == pytest.approx(at_90, rel=1e-12)
    n_tot = lga.slewing_ratio(40.0, 1.2, 0.12)
    assert n_tot == pytest.approx(400.0, rel=1e-15)
    assert lga.reflected_inertia(at_0, n_tot) == pytest.approx(at_0 / 160000.0, rel=1e-15)
    assert lga.trolley_inertia(1500.0, 0.110, 39.1) == pytest.approx(0.0118720, rel=1e-5)


# ---------------------------------------------------------------------------------------------- gravity
def test_gravity_forces_at_0_and_90_deg():
    """Fc1 (eq. 2.64, via theta2 and R_c) against the moment of the weight over the moment arm |h|/d1 from
    the printed constants; Fc2 (eq. 2.65). Signs: the weight compresses the jib cylinder (the block delivers
    -Fc1, against extension) and pulls the telescope out (+Fc2)."""
    m_tot = M1 + M2 + M3
    for theta, arm in ((0.0, -C1_MM2 * 1e-6 / d1_thesis(0.0)), (HALF_PI, -C2_MM2 * 1e-6 / d1_thesis(HALF_PI))):
        expected = m_tot * GRAV * x_g_by_hand(theta, 0.0) / arm
        assert lga.jib_gravity_force(theta, 0.0, GRAV, G) == pytest.approx(expected, rel=1e-12)
        assert expected > 0.0
    assert x_g_by_hand(0.0, 0.0) == pytest.approx(1.99090, abs=1e-5)  # the numbers, for the record
    assert lga.jib_gravity_force(0.0, 0.0, GRAV, G) == pytest.approx(186252.0, rel=1e-6)
    assert lga.jib_gravity_force(HALF_PI, 0.0, GRAV, G) == pytest.approx(1192.96, rel=1e-5)
    assert lga.telescope_gravity_force(0.0, M2, M3, GRAV) == 0.0
    assert lga.telescope_gravity_force(HALF_PI, M2, M3, GRAV) == pytest.approx((M2 + M3) * GRAV, rel=1e-15)
    # eq. 2.64 (moments about A) equals the virtual work of the weight through theta1(d1) at any angle
    for theta in np.linspace(0.0, HALF_PI, 11):
        for d2 in (0.0, 1.2):
            virtual_work = m_tot * GRAV * x_g_by_hand(theta, d2) * d1_thesis(theta) / -lever_thesis(theta)
            assert lga.jib_gravity_force(theta, d2, GRAV, G) == pytest.approx(virtual_work, rel=1e-12)


# ---------------------------------------------------------------------------------------------- the blocks
def test_jib_load_block_equations():
    """lga_jib_load called by keyword: mass m1_eff, force -Fc1 - k_vel/2*m'*v^2, outputs; clamping."""
    d1_0, x1, x2, v = 2.3, 0.25, 0.4, 0.07
    values = jib_defaults(d1_0=d1_0, x1=x1, x2=x2, rod=v)
    d1 = d1_0 + x1
    theta = theta_closed_form(d1)
    d2 = 0.0 + x2
    m = lga.jib_effective_mass(theta, d1, d2, G)
    fc1 = (M1 + M2 + M3) * GRAV * x_g_by_hand(theta, d2) * d1 / -lever_thesis(theta)
    slope = lga.jib_effective_mass_slope(theta, d1, d2, G)
    f, mass = call(LgaJibLoad.derivatives, values)
    assert mass == pytest.approx(m, rel=1e-12)
    assert f == pytest.approx(-fc1 - 0.5 * slope * v * v, rel=1e-12)
    assert 0.5 * slope * v * v > 1e-3 * fc1  # the term is visible here (0.45 % of the weight at 64.5 deg, 0.07 m/s)
    f0, _ = call(LgaJibLoad.derivatives, {**values, "k_vel": 0.0})
    assert f0 == pytest.approx(-fc1, rel=1e-12)
    theta_out, w1, m_eff, f_g, k1 = call(LgaJibLoad.outputs, values)
    assert theta_out == pytest.approx(theta, abs=1e-12)
    assert w1 == pytest.approx(v * d1 / lever_thesis(theta), rel=1e-12)
    assert k1 == pytest.approx(d1 / lever_thesis(theta), rel=1e-12)
    assert (m_eff, f_g) == (pytest.approx(m, rel=1e-12), pytest.approx(fc1, rel=1e-12))
    # beyond the range: the end's mass (at the end's own d1) and weight, no Lagrange term, no turning
    beyond = {**values, "x1": 1.0}  # d1 = 3.3 m > d1(0) = 2.985 m
    f_b, m_b = call(LgaJibLoad.derivatives, beyond)
    theta_b, w1_b, m_eff_b, _, k1_b = call(LgaJibLoad.outputs, beyond)
    assert (theta_b, w1_b, k1_b) == (0.0, 0.0, 0.0)
    assert m_b == m_eff_b == pytest.approx(lga.jib_effective_mass(0.0, d1_thesis(0.0), d2, G), rel=1e-12)
    assert f_b == pytest.approx(-lga.jib_gravity_force(0.0, d2, GRAV, G), rel=1e-12)


def test_jib_load_checks_its_angle_range():
    ok = jib_defaults(d1_0=2.3)
    assert LgaJibLoad.check_values(ok) is None
    assert "dead centre at -8.821 deg" in LgaJibLoad.check_values({**ok, "theta_min": math.radians(-10)})
    assert "must be below" in LgaJibLoad.check_values({**ok, "theta_min": 1.0, "theta_max": 0.5})


def test_telescope_load_block_equations():
    """lga_telescope_load: mass m2 + m3 on the rod, +Fc2 = sin(theta1)*(m2 + m3)*g along the extension."""
    values = {p.name: p.default for p in LgaTelescopeLoad.params}
    for deg in (0.0, 30.0, 90.0, -20.0):
        f, mass = call(LgaTelescopeLoad.derivatives, {**values, "theta1": math.radians(deg)})
        assert mass == pytest.approx(M2 + M3, rel=1e-15)
        assert f == pytest.approx(math.sin(math.radians(deg)) * (M2 + M3) * GRAV, rel=1e-14, abs=1e-12)
        assert call(LgaTelescopeLoad.outputs, {**values, "theta1": math.radians(deg)})[0] == f


def test_bridge_crane_inertias_table_2_14(tmp_path):
    """The presets, read through a netlist: J = J0 + m_L*r^2/n_g^2 (eqs. 2.28-2.29) with table 2.14's
    numbers typed here; and J0 against the table's structure masses (m*r^2/n^2; slewing 1/2*m*r_S^2/n^2)
    to half a unit of the table's last digit (0.0005 kg*m^2)."""
    n_slew = 44.6 * 1200 / 132
    table = {  # preset: (J0, r, n_g, structure mass, J0 from the mass)
        "bridge_travel": (0.085, 0.075, 39.0, 22997, 22997 * 0.075**2 / 39.0**2),
        "trolley_travel": (0.027, 0.055, 38.4, 13006, 13006 * 0.055**2 / 38.4**2),
        "slewing": (0.011, 2.1, n_slew, 5741, 0.5 * 5741 * 0.8**2 / n_slew**2),
        # section 2.8.5's r_p = 110 mm is the pinion's diameter: 78 l/min / 19 cm^3/rev * r/n_g = 600 mm/s
        "lga_trolley_travel": (1500 * 0.055**2 / 39.1**2, 0.055, 39.1, 1500, 1500 * 0.055**2 / 39.1**2),
    }
    netlist = tmp_path / "axes.yaml"
    netlist.write_text("parameters: {m_load: \"7500 kg\"}\ncomponents:\n" + "".join(
        f"  {name}: {{type: bc_axis_inertia, preset: {name}, params: {{m_L: m_load}}}}\n" for name in table)
        + "nets:\n" + "".join(f"  s_{name}: [{name}.shaft]\n" for name in table))
    values = Circuit.from_file(netlist, compile=False).vectors().values
    for name, (j0, r, n, mass, j0_from_mass) in table.items():
        got = {key: values[f"{name}.{key}"] for key in ("J0", "m_L", "r", "n_g")}
        assert got == {"J0": pytest.approx(j0, rel=1e-12), "m_L": 7500.0, "r": pytest.approx(r, rel=1e-12),
                       "n_g": pytest.approx(n, rel=1e-12)}
        tau, J = BcAxisInertia.derivatives(**got)
        assert tau == 0.0 and J == pytest.approx(j0 + 7500.0 * r**2 / n**2, rel=1e-12)
        assert abs(j0 - j0_from_mass) < 0.0005, (name, j0, j0_from_mass)
    assert BcAxisInertia.derivatives(J0=0.085, m_L=0.0, r=0.075, n_g=39.0)[1] == 0.085
    assert quantity("0.011 kg*m^2", "kg*m^2") == 0.011


def test_tool_point_eqs_2_66_2_67():
    """x = 2.1 sin(alpha) + b_pos, y = 2.1 - 2.1 cos(alpha) + t_pos; the point lies on the circle of radius
    2.1 m about (b_pos, t_pos + 2.1) and sits at (b_pos, t_pos) for alpha = 0."""
    for alpha in np.linspace(-math.pi, math.pi, 25):
        for b, t in ((0.0, 0.0), (1.3, -0.4)):
            x, y = ToolPoint.outputs(b_pos=b, t_pos=t, alpha=alpha, r_tp=2.1)
            assert (x, y) == (pytest.approx(2.1 * math.sin(alpha) + b, abs=1e-15),
                              pytest.approx(2.1 - 2.1 * math.cos(alpha) + t, abs=1e-15))
            assert math.hypot(x - b, y - (t + 2.1)) == pytest.approx(2.1, rel=1e-14)
    assert ToolPoint.outputs(b_pos=0.5, t_pos=0.2, alpha=0.0, r_tp=2.1) == (0.5, pytest.approx(0.2, abs=1e-16))
    assert ToolPoint.outputs(b_pos=0.0, t_pos=0.0, alpha=HALF_PI, r_tp=2.1) == (2.1, pytest.approx(2.1, rel=1e-15))


# ---------------------------------------------------------------------------------------------- circuits
NETLIST = """\
description: >
  Three independent circuits (tests/crane/test_mechanics.py).
  Telescope: a flow source pumps Qt from the tank into the rod side B of a mass-less cylinder (piston side A
  on the tank) carrying lga_telescope_load at theta1 = theta_t, with a damper b_t; the flow ramps up, holds and
  stops at 0.9 s. At rest p_B*A_B = Fc2. Oil spring k = beta*A_B^2/V_B = 1.16e6 N/m, m = 440.4 kg:
  omega = 51 rad/s, zeta = b_t/(2*m*omega) = 0.49, decay rate 25 1/s for 1.1 s (e^-27).
  Jib: a flow source pumps Qj into the piston side A of a mass-less cylinder (rod side on the tank) whose rod
  carries lga_jib_load (d1 = d1_0 + x from a position sensor) and a damper b_j; the flow stops at 0.7 s. At
  rest p_A*A_A = Fc1(d1). k = 1.56e7 N/m, m1_eff ~ 10 t: omega ~ 40 rad/s, zeta ~ 0.6, decay ~ 25 1/s
  for 1.3 s (e^-32).
  Free: lga_jib_load alone with g = 0, starting at 0.05 m/s: 1/2*m1_eff(d1)*v^2 stays constant.
fluid: {rho: "850 kg/m^3", nu: "1.8e-5 m^2/s", beta: "8e8 Pa", vapour_pressure: "-1 bar"}
parameters:
  Qt: "1 l/min"
  Qj: "10 l/min"
  theta_t: "60 deg"
  x0_j: "0.2 m"
  x0_f: "0.2 m"
components:
  tank:   {type: tank}
  q_t:    {type: profile, params: {times: [0, 0.2, 0.7, 0.9], values: [0, Qt, Qt, 0]}}
  pump_t: {type: flow_source_signal}
  cyl_t:  {type: cylinder, params: {A_A: "20 cm^2", A_B: "10 cm^2", stroke: "1 m", V0_A: "0.2 l", V0_B: "0.2 l"},
           initial: {x: "0.5 m"}}
  damp_t: {type: trans_damper, params: {b: "2.2e4 N*s/m"}}
  angle:  {type: constant, params: {value: theta_t}}
  tele:   {type: lga_telescope_load}
  q_j:    {type: profile, params: {times: [0, 0.2, 0.5, 0.7], values: [0, Qj, Qj, 0]}}
  pump_j: {type: flow_source_signal}
  cyl_j:  {type: cylinder, params: {A_A: "50 cm^2", A_B: "25 cm^2", stroke: "0.6 m", V0_A: "0.2 l", V0_B: "0.2 l"},
           initial: {x: x0_j}}
  damp_j: {type: trans_damper, params: {b: "5e5 N*s/m"}}
  pos_j:  {type: position_sensor, initial: {x: x0_j}}
  jib:    {type: lga_jib_load, params: {d1_0: "2.3 m"}}
  pos_f:  {type: position_sensor, initial: {x: x0_f}}
  free:   {type: lga_jib_load, params: {d1_0: "2.3 m", g: 0}}
nets:
  T:      [tank.port, pump_t.a, cyl_t.A, pump_j.a, cyl_j.B]
  TB:     {ports: [pump_t.b, cyl_t.B], initial: "0 bar"}
  qt:     [q_t.y, pump_t.q]
  rod_t:  [cyl_t.rod, damp_t.port, tele.rod]
  th_t:   [angle.y, tele.theta1]
  fg_t:   [tele.F_g]
  JA:     {ports: [pump_j.b, cyl_j.A], initial: "0 bar"}
  qj:     [q_j.y, pump_j.q]
  rod_j:  [cyl_j.rod, damp_j.port, jib.rod, pos_j.port]
  xj:     [pos_j.position, jib.x1]
  th_j:   [jib.theta1]
  w_j:    [jib.w1]
  m_j:    [jib.m_eff]
  fg_j:   [jib.F_g]
  rod_f:  {ports: [free.rod, pos_f.port], initial: "0.05 m/s"}
  xf:     [pos_f.position, free.x1]
  th_f:   [free.theta1]
  w_f:    [free.w1]
  m_f:    [free.m_eff]
  fg_f:   [free.F_g]
outputs:
  pTB: TB
  pJA: JA
  x_j: cyl_j.x
  xs_j: pos_j.position
  th_j: jib.theta1
  Fg_j: jib.F_g
  x_f: pos_f.position
  v_f: rod_f
  th_f: free.theta1
  w_f: free.w1
  m_f: free.m_eff
simulation: {t_end: "2 s", dt_out: "1 ms", solver: rodas, rtol: 1e-9, atol: 1e-9}
"""


@pytest.fixture(scope="module")
def circuit(tmp_path_factory):
    path = tmp_path_factory.mktemp("mechanics") / "lga_circuits.yaml"
    path.write_text(textwrap.dedent(NETLIST))
    return Circuit.from_file(path)


@pytest.fixture(scope="module")
def run(circuit):
    return circuit.simulate()


def test_telescope_cylinder_settles_at_fc2_over_the_annulus(circuit, run):
    """Static pressure in the rod side: p_B = Fc2/A_B = sin(60 deg)*(265.2 + 175.2 kg)*9.81/10 cm^2 = 37.4 bar;
    at 30 deg (an override, same circuit) half of it."""
    a_b, a_a = 10e-4, 20e-4
    expected = math.sin(math.radians(60)) * (M2 + M3) * GRAV / a_b
    p_end = run["pTB"][-1]
    assert p_end == pytest.approx(expected, rel=1e-6)
    assert abs(p_end - expected * a_b / a_a) > 0.4 * expected  # not the piston area
    assert not run.warnings
    other = circuit.simulate({"theta_t": math.radians(30)})
    assert other["pTB"][-1] == pytest.approx(math.sin(math.radians(30)) * (M2 + M3) * GRAV / a_b, rel=1e-6)


def test_jib_cylinder_holds_the_jib_at_fc1_over_the_piston(run):
    """Static pressure in the piston side: p_A = Fc1(d1)/A_A at the final cylinder position (the weight
    compresses the cylinder: p_A > 0); theta1 logged by the block is theta1(d1_0 + x) throughout."""
    a_a = 50e-4
    x = run["x_j"]
    # the sensor follows the cylinder's own state: both integrate the same v in the same steps, so they differ
    # by round-off only (the Rosenbrock stages solve with different Jacobian columns)
    np.testing.assert_allclose(run["xs_j"], x, rtol=0, atol=1e-12)
    d1 = 2.3 + x
    theta = np.array([theta_closed_form(v) for v in d1])
    np.testing.assert_allclose(run["th_j"], theta, rtol=0, atol=1e-12)
    d1_end, theta_end = d1[-1], theta[-1]
    fc1 = (M1 + M2 + M3) * GRAV * x_g_by_hand(theta_end, 0.0) * d1_end / -lever_thesis(theta_end)
    assert run["Fg_j"][-1] == pytest.approx(fc1, rel=1e-12)
    assert run["pJA"][-1] == pytest.approx(fc1 / a_a, rel=1e-6)
    assert run["pJA"][-1] > 15e5 and x[-1] > x[0] + 0.01  # lifted by the pumped volume, holding ~20 bar


def test_coasting_jib_keeps_its_kinetic_energy(circuit, run):
    """g = 0, no other force: with the Lagrange term 1/2*m'(d1)*v^2 the energy 1/2*m1_eff*v^2 is constant
    while m1_eff grows by 20 %; without it (k_vel = 0, the thesis's m(x)*a = F) v stays constant and the
    energy grows with the mass. w1 (eq. 2.35) is the time derivative of the logged theta1."""
    energy = 0.5 * run["m_f"] * run["v_f"] ** 2
    assert run["m_f"][-1] > 1.15 * run["m_f"][0]
    assert np.max(np.abs(energy / energy[0] - 1.0)) < 1e-6
    slope = np.gradient(run["th_f"], run.t, edge_order=2)
    np.testing.assert_allclose(run["w_f"][1:-1], slope[1:-1], rtol=1e-5)
    off = circuit.simulate({"free.k_vel": 0.0})
    np.testing.assert_allclose(off["v_f"], 0.05, rtol=1e-9)
    energy_off = 0.5 * off["m_f"] * off["v_f"] ** 2
    assert energy_off[-1] / energy_off[0] - 1.0 > 0.15
