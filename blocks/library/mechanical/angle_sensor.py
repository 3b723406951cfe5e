"""Ideal angle sensor (integrates the shaft speed)."""

from blocks.block import Block, State, rotational, signal_out
from blocks.registry import register


@register("angle_sensor")
class AngleSensor(Block):
    """Ideal angle sensor: integrates the speed of its shaft net into the angle theta, applies no torque.

    dtheta/dt = w_port,  angle = theta   [rad],  tau_port = 0

    The initial angle theta0 is the start value of the state ``theta`` (default 0).
    """

    ports = (rotational("port", "the measured shaft net"), signal_out("angle", "measured shaft angle", "rad"))
    states = (State("theta", "rad", 0.0, 1.0, "shaft angle"),)

    @staticmethod
    def outputs(theta):
        return (theta,)

    @staticmethod
    def derivatives(port):
        return 0.0, port
