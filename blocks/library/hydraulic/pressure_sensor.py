"""Ideal pressure sensor."""

from blocks.block import Block, hydraulic, signal_out
from blocks.registry import register


@register("pressure_sensor")
class PressureSensor(Block):
    """Ideal pressure sensor: outputs the pressure of its net, takes no flow.

    p = p_port   [Pa, gauge],  q_port = 0
    """

    ports = (hydraulic("port", "the measured net"), signal_out("p", "measured pressure", "Pa"))

    @staticmethod
    def outputs(port):
        return (port,)

    @staticmethod
    def derivatives():
        return (0.0,)
