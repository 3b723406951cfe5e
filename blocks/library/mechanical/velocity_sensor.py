"""Ideal velocity sensor."""

from blocks.block import Block, signal_out, translational
from blocks.registry import register


@register("velocity_sensor")
class VelocitySensor(Block):
    """Ideal velocity sensor: outputs the velocity of its net, applies no force.

    v = v_port   [m/s],  f_port = 0
    """

    ports = (translational("port", "the measured body net"), signal_out("v", "measured velocity", "m/s"))

    @staticmethod
    def outputs(port):
        return (port,)

    @staticmethod
    def derivatives():
        return (0.0,)
