"""Rotational viscous friction against the frame."""

from blocks.block import Block, Param, rotational
from blocks.registry import register


@register("rot_damper")
class RotDamper(Block):
    """Rotational viscous friction against the fixed frame: torque opposing the shaft speed.

    tau = -b*w   [N*m], b [N*m*s/rad], w the speed of the net [rad/s]

    tau is the torque acting on the net (negative for w > 0: it brakes the shaft).
    """

    ports = (rotational("port", "the braked shaft net"),)
    params = (Param("b", "N*m*s/rad", None, 0.0, 1e9, "viscous friction coefficient"),)

    @staticmethod
    def derivatives(port, b):
        return (-b * port,)
