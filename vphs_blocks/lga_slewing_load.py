"""Lower guiding arm: the slewing inertia J_S(theta1, d2) on the slewing motor's shaft (thesis 2.8.3-2.8.4)."""

from blocks.block import Block, Param, rotational, signal_in, signal_out
from blocks.registry import register
from vphs_blocks.lga_geometry import LGA, THESIS, disc_inertia, slewing_inertia, slewing_inertia_slopes
from vphs_blocks.lga_jib_load import GEOMETRY

# J_S does not depend on where the jib cylinder is hinged: joints B and C are not parameters here.
_JOINTS = ("cx", "cy", "bx", "by")


@register("lga_slewing_load")
class LgaSlewingLoad(Block):
    """LGA arm on the slewing motor's shaft: J_S(theta1, d2)/n_tot^2 and the rate of its change (eqs. 2.46-2.53).

    J_S   = J_S(theta1, d2)   (eqs. 2.46-2.51, lga_geometry.slewing_inertia)              [kg*m^2]
    J_shaft = J_S/n_tot^2     (eq. 2.53)                                                   [kg*m^2]
    tau_shaft = -k_vel*(dJ_S/dtheta1*w1 + dJ_S/dd2*v2)/n_tot^2 * w                         [N*m]
    output J_S [kg*m^2] (about the slewing axis)

    w is the shaft net's speed (the motor shaft: the slewing axis turns at w/n_tot), theta1 the jib angle
    below the horizontal and w1 = dtheta1/dt (the outputs of the same names of `lga_jib_load`), d2 =
    d2_0 + x2 the telescope's extension and v2 = dd2/dt its speed (a velocity sensor on the telescope's
    rod net). Unconnected, w1, x2 and v2 are 0: J_S at a fixed pose.

    Why the torque: the jib and the telescope move the arm's masses radially, by forces in the arm's own
    vertical plane, which exert no moment about the slewing axis. What they conserve is the angular
    momentum J_S*w/n_tot (Lagrange's equation for the slewing angle, whose kinetic energy 1/2*J_S*w^2/n^2
    does not depend on the angle itself): d(J_shaft*w)/dt = sum(tau). The shaft net integrates
    J_shaft*dw/dt = sum(tau), so this block adds -dJ_shaft/dt*w (k_vel = 1, the default). k_vel = 0 is
    the thesis's J_sm*dw/dt = tau with J_S following the pose: an arm that reaches out while slewing then
    keeps its speed, where it should slow down.

    Neglected, as the thesis neglects centripetal forces (and as `lga_jib_load` and `lga_telescope_load`
    do): the reactions of the slewing on the other axes, the centrifugal pull 1/2*dJ_S/dd2*(w/n)^2 on the
    telescope and the moment 1/2*dJ_S/dtheta1*(w/n)^2 on the jib (about 20 N and 70 N*m at the thesis's
    30 deg/s, against forces of kN). Without them the slewing's kinetic energy is not conserved exactly:
    it changes by -1/2*dJ_S/dt*(w/n)^2 more than the motor's work, the work those reactions would do.

    Sign convention: w > 0 turns the arm one way, the torque opposes a growing J_S's effect (it brakes the
    shaft while the arm reaches out, drives it while the arm draws in). Parameters of the arm's geometry
    and masses as in `lga_jib_load` (the thesis's LGA, section 2.8); e, the distance of joint A from the
    slewing axis, is not given in the text (0.6 m chosen, the baseplate's inner radius); the baseplate
    (m4, R4, r4) is a disc of outer and inner radius R4 and r4, J4 = m4*(R4^2 + r4^2)/2.
    """

    ports = (
        rotational("shaft", "the slewing motor's shaft net (turns n_tot times the slewing axis)", stores=True),
        signal_in("theta1", "jib angle below the horizontal", "rad"),
        signal_in("w1", "jib angular speed dtheta1/dt (0 if unconnected)", "rad/s", optional=True),
        signal_in("x2", "telescope cylinder position (extension from d2_0; 0 if unconnected)", "m", optional=True),
        signal_in("v2", "telescope extension speed dd2/dt (0 if unconnected)", "m/s", optional=True),
        signal_out("J_S", "slewing inertia about the slewing axis", "kg*m^2"),
    )
    params = (
        Param("n_tot", "1", None, 1e-3, 1e6, "reduction motor shaft -> slewing axis (eq. 2.52)"),
        Param("d2_0", "m", 0.0, -10.0, 10.0, "telescope extension (A to its rear end) at x2 = 0"),
        Param("e", "m", THESIS["e"], -10.0, 10.0, "joint A's distance from the slewing axis (chosen: 0.6 m)"),
        Param("m4", "kg", THESIS["m4"], 0.0, 1e5, "baseplate mass (turns with the arm)"),
        Param("R4", "m", THESIS["R4"], 0.0, 10.0, "baseplate outer radius"),
        Param("r4", "m", THESIS["r4"], 0.0, 10.0, "baseplate inner radius"),
        Param("k_vel", "1", 1.0, 0.0, 1.0, "weight of the Lagrange term -dJ/dt*w (1: on, 0: off)"),
    ) + tuple(p for p in GEOMETRY if p.name not in _JOINTS)

    @staticmethod
    def outputs(theta1, x2, d2_0, e, m4, R4, r4, m1, xi1, eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2,
                m3, xi3, eta3, a3, b3, c3):
        geo = LGA(0.0, 0.0, 0.0, 0.0, m1, xi1, eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3,
                  a3, b3, c3)
        return (slewing_inertia(theta1, d2_0 + x2, e, disc_inertia(m4, R4, r4), geo),)

    @staticmethod
    def derivatives(shaft, theta1, w1, x2, v2, n_tot, d2_0, e, m4, R4, r4, k_vel, m1, xi1, eta1, S1, L1,
                    m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3, a3, b3, c3):
        geo = LGA(0.0, 0.0, 0.0, 0.0, m1, xi1, eta1, S1, L1, m2, xi2, eta2, S2, L2, eta_cs2, m3, xi3, eta3,
                  a3, b3, c3)
        d2 = d2_0 + x2
        n2 = n_tot * n_tot
        j_s = slewing_inertia(theta1, d2, e, disc_inertia(m4, R4, r4), geo)
        dj_dtheta, dj_dd2 = slewing_inertia_slopes(theta1, d2, e, geo)
        return -k_vel * (dj_dtheta * w1 + dj_dd2 * v2) * shaft / n2, j_s / n2

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        if values["r4"] > values["R4"]:
            return f"r4 = {values['r4']:g} m must not exceed R4 = {values['R4']:g} m (the baseplate's radii)"
        if values["m1"] + values["m2"] + values["m3"] + values["m4"] <= 0.0:
            return "m1 + m2 + m3 + m4 must be positive: the arm must have an inertia"
        return None

