"""Ideal velocity source driven by a signal."""

from blocks.block import Block, signal_in, translational
from blocks.registry import register


@register("velocity_source")
class VelocitySource(Block):
    """Ideal velocity source: the net at ``port`` moves at the signal velocity v whatever the force.

    v_port = v   [m/s]  (the net then has no velocity state of its own; v = 0 fixes it to the frame)
    """

    ports = (translational("port", "the body net driven at velocity v"), signal_in("v", "prescribed velocity", "m/s"))
    prescribes = ("port",)

    @staticmethod
    def outputs(v):
        return (v,)
