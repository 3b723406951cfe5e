"""Ideal position sensor (integrates the velocity)."""

from blocks.block import Block, State, signal_out, translational
from blocks.registry import register


@register("position_sensor")
class PositionSensor(Block):
    """Ideal position sensor: integrates the velocity of its net into the position x, applies no force.

    dx/dt = v_port,  position = x   [m],  f_port = 0

    The initial position x0 is the start value of the state ``x`` (default 0): it is this sensor's own and
    must agree with the body's. A cylinder's piston position is the cylinder's own ``position`` output,
    which has no second start to keep in step.
    """

    ports = (translational("port", "the measured body net"), signal_out("position", "measured position", "m"))
    states = (State("x", "m", 0.0, 1.0, "position"),)

    @staticmethod
    def outputs(x):
        return (x,)

    @staticmethod
    def derivatives(port):
        return 0.0, port
