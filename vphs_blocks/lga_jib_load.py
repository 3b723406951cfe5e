"""Lower guiding arm: the jib's effective mass and weight on the jib-tilt cylinder's rod (thesis 2.8.6, 2.9)."""

import math

from blocks.block import Block, Param, ValidRange, signal_in, signal_out, translational
from blocks.registry import register
from vphs_blocks.lga_geometry import (
    LGA,
    THESIS,
    cylinder_length,
    dead_centres,
    jib_effective_mass,
    jib_effective_mass_slope,
    jib_gravity_force,
    jib_pose,
)

# The LGA's geometry and masses, shared with lga_geometry.LGA (defaults: the thesis's LGA, section 2.8).
GEOMETRY = (
    Param("cx", "m", THESIS["cx"], -10.0, 10.0, "joint C on the main arm, along the arm (eq. 2.30: 2191 mm)"),
    Param("cy", "m", THESIS["cy"], -10.0, 10.0, "joint C on the main arm, across the arm (340 mm)"),
    Param("bx", "m", THESIS["bx"], -10.0, 10.0, "joint B (cylinder base) from joint A, horizontal (-775 mm)"),
    Param("by", "m", THESIS["by"], -10.0, 10.0, "joint B from joint A, vertical, positive down (0 mm)"),
    Param("m1", "kg", THESIS["m1"], 0.0, 1e5, "main arm mass"),
    Param("xi1", "m", THESIS["xi1"], -20.0, 20.0, "main arm mass centre, along the arm from A"),
    Param("eta1", "m", THESIS["eta1"], -5.0, 5.0, "main arm mass centre, across the arm"),
    Param("S1", "m", THESIS["S1"], 0.0, 5.0, "main arm square section side"),
    Param("L1", "m", THESIS["L1"], 0.0, 50.0, "main arm length"),
    Param("m2", "kg", THESIS["m2"], 0.0, 1e5, "telescope arm mass"),
    Param("xi2", "m", THESIS["xi2"], -20.0, 20.0, "telescope mass centre from its rear end, along the arm"),
    Param("eta2", "m", THESIS["eta2"], -5.0, 5.0, "telescope mass centre across the arm, from its own axis"),
    Param("S2", "m", THESIS["S2"], 0.0, 5.0, "telescope square section side"),
    Param("L2", "m", THESIS["L2"], 0.0, 50.0, "telescope length"),
    Param("eta_cs2", "m", THESIS["eta_cs2"], -5.0, 5.0, "telescope axis across the main arm's axis (-50 mm)"),
    Param("m3", "kg", THESIS["m3"], 0.0, 1e5, "gripper head mass (add a gripped load here)"),
    Param("xi3", "m", THESIS["xi3"], -10.0, 10.0, "gripper centre from the telescope tip, horizontal (chosen: a/2)"),
    Param("eta3", "m", THESIS["eta3"], -10.0, 10.0, "gripper mass centre from the telescope tip, down (chosen 0)"),
    Param("a3", "m", THESIS["a3"], 0.0, 10.0, "gripper box length, horizontal in the arm's plane"),
    Param("b3", "m", THESIS["b3"], 0.0, 10.0, "gripper box width, out of the arm's plane"),
    Param("c3", "m", THESIS["c3"], 0.0, 10.0, "gripper box height"),
)


@register("lga_jib_load")
class LgaJibLoad(Block):
    """LGA jib on the jib-tilt cylinder's rod: variable effective mass m1_eff(d1, d2) and weight Fc1 (eqs. 2.61, 2.64).

    d1 = d1_0 + x1,  d2 = d2_0 + x2,  theta1 = f1(d1) solved from eq. 2.31 (clamped to [theta_min, theta_max])
    m_rod = m1_eff = J_A(theta1, d2)*(d1/h(theta1))^2                         [kg]   (2.61, 2.35)
    f_rod = -Fc1(theta1, d2) - k_vel*1/2*dm1_eff/dd1*v^2                      [N]    (2.64; Lagrange)
    outputs: theta1 [rad], w1 = theta1_dot = k1*v [rad/s] (2.35), m_eff [kg], F_g = Fc1 [N],
             k1 = dtheta1/dd1 = d1/h [rad/m] (the jib angle per metre of cylinder; lga_slewing_load reads it)

    All the geometry (joints B and C, eq. 2.30; h = d1*dd1/dtheta1 = C1 cos + C2 sin, eq. 2.33; J_A from
    eqs. 2.55-2.58; Fc1 = X_G*(m1+m2+m3)*g/(R_cy cos theta2 - R_cx sin theta2), theta2 the cylinder axis
    B->C) is in :mod:`vphs_blocks.lga_geometry`, whose docstring states every reading settled on. The
    defaults are the thesis's LGA (section 2.8); xi3, eta3 (the gripper's centre) are chosen, not given.

    Sign convention: x1 and v > 0 extend the jib cylinder (d1 grows, theta1 falls: the arm rises). The frame
    has Y down, theta1 > 0 the arm below the horizontal (from eq. 2.63's signs): the weight compresses the
    cylinder, Fc1 > 0, and this block delivers -Fc1 to the rod net (against extension). g < 0 reads the
    frame with Y up instead (the weight then pulls the cylinder out).

    x1 is the cylinder's position (its state x, e.g. a position_sensor on the rod net: give it the cylinder's
    initial x); x2 the telescope cylinder's position (0 if unconnected), extending the telescope.
    d1_0 and d2_0 depend on the cylinders, which the thesis does not give: the assembly chooses them.

    Position-dependent mass: the net integrates m(x)*dv/dt = sum f; the Lagrange equation of the kinetic
    energy 1/2*m(x)*v^2 is m*dv/dt + 1/2*m'(x)*v^2 = F, so the block adds -1/2*m'*v^2 (k_vel = 1, the
    default; k_vel = 0 is the thesis's m(x)*a = F, which does not conserve kinetic energy as m changes).
    m1_eff varies by a factor of ~90 over 0-90 deg (589 t at theta1 = 0, where the cylinder passes 88 mm
    from A, 6.8 t at 90 deg), so the term is not negligible in fast moves near the horizontal. Cross terms
    with the telescope's speed (dm/dd2*v1*v2) and the centrifugal pull on the telescope are neglected, as
    the thesis neglects centripetal forces.

    Outside [theta_min, theta_max] (which must not contain a dead centre, where h = 0 and m1_eff is
    infinite; checked) theta1 is clamped: mass and weight are those of the end (at the end's d1), m' = 0,
    and the jib does not turn (k1 = w1 = 0). Keep the cylinder's stroke inside this range (its end stops
    then act first); a run whose x1 leaves it (at an output sample) is warned of.
    """

    ports = (
        translational("rod", "the jib-tilt cylinder's rod net (v > 0 extends)", stores=True),
        signal_in("x1", "jib-tilt cylinder position (extension from d1_0)", "m"),
        signal_in("x2", "telescope cylinder position (extension from d2_0; 0 if unconnected)", "m", optional=True),
        signal_out("theta1", "jib angle below the horizontal", "rad"),
        signal_out("w1", "jib angular speed theta1_dot", "rad/s"),
        signal_out("m_eff", "effective mass on the rod", "kg"),
        signal_out("F_g", "gravity force Fc1 on the cylinder, > 0 compressing", "N"),
        signal_out("k1", "dtheta1/dd1: jib angle per cylinder extension (0 where clamped)", "rad/m"),
    )
    params = (
        Param("d1_0", "m", None, 0.0, 20.0, "jib cylinder length |BC| at x1 = 0 (the assembly's cylinder)"),
        Param("d2_0", "m", 0.0, -10.0, 10.0, "telescope extension (A to its rear end) at x2 = 0"),
        Param("theta_min", "rad", 0.0, -math.pi, math.pi, "lower end of the jib angle range (clamp)"),
        Param("theta_max", "rad", math.pi / 2.0, -math.pi, math.pi, "upper end of the jib angle range (clamp)"),
        Param("k_vel", "1", 1.0, 0.0, 1.0, "weight of the Lagrange term 1/2*m'(d1)*v^2 (1: on, 0: off)"),
        Param("g", "m/s^2", THESIS["g"], -20.0, 20.0, "gravity along +Y (down); negative for a Y-up frame"),
    ) + GEOMETRY
    checked = ("x1",)

    @staticmethod
    def outputs(rod, x1, x2, d1_0, d2_0, theta_min, theta_max, g, cx, cy, bx, by, m1, xi1, eta1, S1, L1,
                m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3, a3, b3, c3):
        geo = LGA(cx, cy, bx, by, m1, xi1, eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3, a3, b3, c3)
        d2 = d2_0 + x2
        theta, d1, k1 = jib_pose(d1_0 + x1, geo, theta_min, theta_max)
        return theta, k1 * rod, jib_effective_mass(theta, d1, d2, geo), jib_gravity_force(theta, d2, g, geo), k1

    @staticmethod
    def derivatives(rod, x1, x2, d1_0, d2_0, theta_min, theta_max, k_vel, g, cx, cy, bx, by, m1, xi1, eta1,
                    S1, L1, m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3, a3, b3, c3):
        geo = LGA(cx, cy, bx, by, m1, xi1, eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3, a3, b3, c3)
        d2 = d2_0 + x2
        theta, d1, k1 = jib_pose(d1_0 + x1, geo, theta_min, theta_max)
        f = -jib_gravity_force(theta, d2, g, geo)
        if k_vel != 0.0 and k1 != 0.0:
            f -= 0.5 * k_vel * jib_effective_mass_slope(theta, d1, d2, geo) * rod * rod
        return f, jib_effective_mass(theta, d1, d2, geo)

    @classmethod
    def valid_ranges(cls, values: dict) -> tuple[ValidRange, ...]:
        """x1 between the cylinder positions of theta_max and theta_min (d1 is monotonic between them)."""
        geo = LGA(*(float(values[name]) for name in LGA._fields))
        ends = [cylinder_length(values[end], geo) - values["d1_0"] for end in ("theta_min", "theta_max")]
        return (ValidRange("x1", min(ends), max(ends), "the jib angle is clamped to [theta_min, theta_max]: "
                                                       "the mass and weight of that end act"),)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        lo, hi = values["theta_min"], values["theta_max"]
        if not lo < hi:
            return f"theta_min = {lo:g} rad must be below theta_max = {hi:g} rad"
        geo = LGA(*(float(values[name]) for name in LGA._fields))
        if geo.m1 + geo.m2 + geo.m3 <= 0.0:
            return "m1 + m2 + m3 must be positive"
        if math.hypot(geo.cx, geo.cy) == 0.0 or math.hypot(geo.bx, geo.by) == 0.0:
            return "joints B and C must not coincide with joint A"
        for dead in dead_centres(geo):
            for k in (-2, -1, 0, 1, 2):
                angle = dead + 2.0 * k * math.pi
                if lo <= angle <= hi:
                    return (f"the jib angle range [{math.degrees(lo):.4g}, {math.degrees(hi):.4g}] deg contains a dead "
                            f"centre at {math.degrees(angle):.4g} deg (the cylinder's line through joint A: infinite "
                            f"effective mass); narrow theta_min/theta_max")
        return None
