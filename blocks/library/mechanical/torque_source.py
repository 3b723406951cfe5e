"""Ideal torque source driven by a signal."""

from blocks.block import Block, rotational, signal_in
from blocks.registry import register


@register("torque_source")
class TorqueSource(Block):
    """Ideal torque source against the fixed frame: applies the signal torque tau to its shaft net.

    tau_port = tau   [N*m]  (tau > 0 accelerates the shaft towards positive w)
    """

    ports = (rotational("port", "the driven shaft net"), signal_in("tau", "applied torque", "N*m"))

    @staticmethod
    def derivatives(tau):
        return (tau,)
