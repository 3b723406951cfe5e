"""Ideal angular speed sensor."""

from blocks.block import Block, rotational, signal_out
from blocks.registry import register


@register("speed_sensor")
class SpeedSensor(Block):
    """Ideal angular speed sensor: outputs the speed of its shaft net, applies no torque.

    w = w_port   [rad/s],  tau_port = 0
    """

    ports = (rotational("port", "the measured shaft net"), signal_out("w", "measured angular speed", "rad/s"))

    @staticmethod
    def outputs(port):
        return (port,)

    @staticmethod
    def derivatives():
        return (0.0,)
