"""Ideal angular speed source driven by a signal."""

from blocks.block import Block, rotational, signal_in
from blocks.registry import register


@register("speed_source")
class SpeedSource(Block):
    """Ideal angular speed source: the shaft net at ``port`` turns at the signal speed w whatever the torque.

    w_port = w   [rad/s]  (the net then has no speed state of its own; w = 0 fixes it to the frame)
    """

    ports = (rotational("port", "the shaft net driven at speed w"), signal_in("w", "prescribed speed", "rad/s"))
    prescribes = ("port",)

    @staticmethod
    def outputs(w):
        return (w,)
