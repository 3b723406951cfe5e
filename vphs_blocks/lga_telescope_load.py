"""Lower guiding arm: telescope and gripper mass and weight on the telescope cylinder's rod (thesis 2.8.6, 2.9)."""

from blocks.block import Block, Param, signal_in, signal_out, translational
from blocks.registry import register
from vphs_blocks.lga_geometry import THESIS, telescope_gravity_force


@register("lga_telescope_load")
class LgaTelescopeLoad(Block):
    """LGA telescope on the telescope cylinder's rod: mass m2 + m3 and the weight's component along the arm (eqs. 2.62, 2.65).

    m_rod = m2_eff = m2 + m3                 [kg]   (2.62)
    f_rod = +Fc2 = sin(theta1)*(m2 + m3)*g   [N]    (2.65)
    output F_g = Fc2 [N]

    The cylinder translates the telescope arm (m2) and the gripper head (m3) along the main arm, so the
    effective mass is their sum. theta1 is the jib angle below the horizontal (the `theta1` output of
    `lga_jib_load`, or a constant); in the frame settled on in :mod:`vphs_blocks.lga_geometry` (Y down)
    the weight pulls the telescope out, so for theta1 in (0, pi) Fc2 > 0 acts in the extension direction
    (v > 0 extends). g < 0 reads the frame with Y up (the weight then pushes the telescope in).
    Neglected, as in the thesis: the centrifugal pull m2_eff*r*theta1_dot^2 and the Coriolis coupling with
    the jib's rotation, and the telescope's friction (a separate block).
    """

    ports = (
        translational("rod", "the telescope cylinder's rod net (v > 0 extends)", stores=True),
        signal_in("theta1", "jib angle below the horizontal", "rad"),
        signal_out("F_g", "gravity force Fc2 along the telescope, > 0 pulling it out", "N"),
    )
    params = (
        Param("m2", "kg", THESIS["m2"], 0.0, 1e5, "telescope arm mass"),
        Param("m3", "kg", THESIS["m3"], 0.0, 1e5, "gripper head mass (add a gripped load here)"),
        Param("g", "m/s^2", THESIS["g"], -20.0, 20.0, "gravity along +Y (down); negative for a Y-up frame"),
    )

    @staticmethod
    def outputs(theta1, m2, m3, g):
        return (telescope_gravity_force(theta1, m2, m3, g),)

    @staticmethod
    def derivatives(theta1, m2, m3, g):
        return telescope_gravity_force(theta1, m2, m3, g), m2 + m3
