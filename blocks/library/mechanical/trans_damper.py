"""Translational viscous friction against the frame."""

from blocks.block import Block, Param, translational
from blocks.registry import register


@register("trans_damper")
class TransDamper(Block):
    """Translational viscous friction against the fixed frame: force opposing the velocity.

    f = -b*v   [N], b [N*s/m], v the velocity of the net [m/s]

    f is the force acting on the net (negative for v > 0: it brakes the body).
    """

    ports = (translational("port", "the braked body net"),)
    params = (Param("b", "N*s/m", None, 0.0, 1e10, "viscous friction coefficient"),)

    @staticmethod
    def derivatives(port, b):
        return (-b * port,)
