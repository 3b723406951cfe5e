"""Ideal force source driven by a signal."""

from blocks.block import Block, signal_in, translational
from blocks.registry import register


@register("force_source")
class ForceSource(Block):
    """Ideal force source against the fixed frame: applies the signal force f to its net.

    f_port = f   [N]  (f > 0 accelerates the body towards positive v)
    """

    ports = (translational("port", "the driven body net"), signal_in("f", "applied force", "N"))

    @staticmethod
    def derivatives(f):
        return (f,)
