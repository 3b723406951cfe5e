"""Lower guiding arm: the slewing inertia J_S(theta1, d2) on the slewing motor's shaft (thesis 2.8.3-2.8.4)."""

from blocks.block import Block, Param, rotational, signal_in, signal_out, translational
from blocks.registry import register
from vphs_blocks.lga_geometry import LGA, THESIS, disc_inertia, slewing_inertia, slewing_inertia_slopes
from vphs_blocks.lga_jib_load import GEOMETRY

# J_S does not depend on where the jib cylinder is hinged: joints B and C are not parameters here.
_JOINTS = ("cx", "cy", "bx", "by")


@register("lga_slewing_load")
class LgaSlewingLoad(Block):
    """LGA arm on the slewing motor's shaft: J_S(theta1, d2)/n_tot^2, coupled to the jib and telescope (eqs. 2.46-2.53).

    J_S  = J_S(theta1, d2)   (eqs. 2.46-2.51, lga_geometry.slewing_inertia)                    [kg*m^2]
    J_shaft   = J_S/n_tot^2  (eq. 2.53)                                                         [kg*m^2]
    W = w/n_tot, the slewing axis's speed;  S1 = dJ_S/dtheta1,  S2 = dJ_S/dd2
    tau_shaft = -k_vel*(S1*k1*v1 + S2*v2)/n_tot^2 * w    (= -dJ_shaft/dt*w)                     [N*m]
    f_jib     = +k_vel*1/2*S1*W^2*k1                     (on the jib cylinder's rod)             [N]
    f_tel     = +k_vel*1/2*S2*W^2                        (on the telescope cylinder's rod)       [N]
    output J_S [kg*m^2] (about the slewing axis)

    w is the shaft net's speed (the motor shaft: the slewing axis turns at W = w/n_tot), v1 and v2 the
    speeds of the jib and telescope cylinders' rod nets (v > 0 extends each), theta1 the jib angle below
    the horizontal and k1 = dtheta1/dd1 (the outputs `theta1` and `k1` of `lga_jib_load`: the jib turns at
    k1*v1), d2 = d2_0 + x2 the telescope's extension.

    Why: the kinetic energy of the slewing, T = 1/2*J_S(theta1, d2)*W^2, depends on the jib's and the
    telescope's positions, so Lagrange's equations couple the three axes.
    - The slewing angle does not appear in T: its momentum J_S*W is conserved but for the motor's torque,
      d(J_shaft*w)/dt = sum(tau). The shaft net integrates J_shaft*dw/dt = sum(tau), so the block adds
      -dJ_shaft/dt*w: an arm that reaches out while slewing slows down, one that draws in speeds up.
    - Each of the other coordinates q feels +dT/dq: the centrifugal pull 1/2*S2*W^2 on the telescope (out,
      while reaching out raises J_S) and the moment 1/2*S1*W^2 on the jib, on its cylinder's rod as
      1/2*S1*W^2*dtheta1/dd1 (virtual work).
    Together they conserve the energy: the shaft term takes dJ_S/dt*W^2 from the slewing, the two pulls give
    1/2*dJ_S/dt*W^2 to the jib and the telescope, and T itself changes by the other half. The thesis
    neglects centripetal forces; at its 30 deg/s the pull on the telescope is 217 N at the start pose
    (theta1 = 45 deg, d2 = 0.2 m: 7 % of its weight along the arm) and 424 N near the horizontal (theta1 = 5
    deg, d2 = 0.5 m: more than that weight), the jib's moment 838 N*m at the start pose, raising the arm
    (1.7 kN on its cylinder). k_vel = 0 leaves all three out (J_S still follows the pose: the thesis's
    J_sm*dw/dt = tau). Not here: the jib's and the telescope's coupling to each other (the jib's effective
    mass follows the telescope's extension), which `lga_jib_load` neglects as the thesis does; the energy
    is kept exactly only while one of the two is still.

    Parameters of the arm's geometry and masses as in `lga_jib_load` (the thesis's LGA, section 2.8); e, the
    distance of joint A from the slewing axis, is not given in the text (0.6 m chosen, the baseplate's
    inner radius); the baseplate (m4, R4, r4) is a disc of outer and inner radius R4 and r4, J4 =
    m4*(R4^2 + r4^2)/2. Where `lga_jib_load` clamps the jib angle, k1 = 0: the jib does not turn.
    """

    ports = (
        rotational("shaft", "the slewing motor's shaft net (turns n_tot times the slewing axis)", stores=True),
        translational("jib_rod", "the jib-tilt cylinder's rod net (v > 0 extends)"),
        translational("tel_rod", "the telescope cylinder's rod net (v > 0 extends)"),
        signal_in("theta1", "jib angle below the horizontal (lga_jib_load's theta1)", "rad"),
        signal_in("k1", "dtheta1/dd1, the jib angle per cylinder extension (lga_jib_load's k1)", "rad/m"),
        signal_in("x2", "telescope cylinder position (extension from d2_0; 0 if unconnected)", "m", optional=True),
        signal_out("J_S", "slewing inertia about the slewing axis", "kg*m^2"),
    )
    params = (
        Param("n_tot", "1", None, 1e-3, 1e6, "reduction motor shaft -> slewing axis (eq. 2.52)"),
        Param("d2_0", "m", 0.0, -10.0, 10.0, "telescope extension (A to its rear end) at x2 = 0"),
        Param("e", "m", THESIS["e"], -10.0, 10.0, "joint A's distance from the slewing axis (chosen: 0.6 m)"),
        Param("m4", "kg", THESIS["m4"], 0.0, 1e5, "baseplate mass (turns with the arm)"),
        Param("R4", "m", THESIS["R4"], 0.0, 10.0, "baseplate outer radius"),
        Param("r4", "m", THESIS["r4"], 0.0, 10.0, "baseplate inner radius"),
        Param("k_vel", "1", 1.0, 0.0, 1.0, "weight of the coupling terms: the shaft's -dJ/dt*w and the pulls (1: on, 0: off)"),
    ) + tuple(p for p in GEOMETRY if p.name not in _JOINTS)

    @staticmethod
    def outputs(theta1, x2, d2_0, e, m4, R4, r4, m1, xi1, eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2,
                m3, xi3, eta3, a3, b3, c3):
        geo = LGA(0.0, 0.0, 0.0, 0.0, m1, xi1, eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3,
                  a3, b3, c3)
        return (slewing_inertia(theta1, d2_0 + x2, e, disc_inertia(m4, R4, r4), geo),)

    @staticmethod
    def derivatives(shaft, jib_rod, tel_rod, theta1, k1, x2, n_tot, d2_0, e, m4, R4, r4, k_vel, m1, xi1,
                    eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3, a3, b3, c3):
        geo = LGA(0.0, 0.0, 0.0, 0.0, m1, xi1, eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3,
                  a3, b3, c3)
        d2 = d2_0 + x2
        n2 = n_tot * n_tot
        j_s = slewing_inertia(theta1, d2, e, disc_inertia(m4, R4, r4), geo)
        s1, s2 = slewing_inertia_slopes(theta1, d2, e, geo)
        half_w2 = 0.5 * shaft * shaft / n2  # 1/2*W^2
        tau = -k_vel * (s1 * k1 * jib_rod + s2 * tel_rod) / n2 * shaft
        return tau, k_vel * s1 * half_w2 * k1, k_vel * s2 * half_w2, j_s / n2

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        if values["r4"] > values["R4"]:
            return f"r4 = {values['r4']:g} m must not exceed R4 = {values['R4']:g} m (the baseplate's radii)"
        if values["m1"] + values["m2"] + values["m3"] + values["m4"] <= 0.0:
            return "m1 + m2 + m3 + m4 must be positive: the arm must have an inertia"
        return None
