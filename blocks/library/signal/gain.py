"""Static gain."""

from blocks.block import Block, Param, signal_in, signal_out
from blocks.registry import register


@register("gain")
class Gain(Block):
    """Static gain: y = k*u.

    Units: k is dimensionless as declared; with differing input and output units it carries their ratio (SI).
    """

    ports = (signal_in("u", "input"), signal_out("y", "k times the input"))
    params = (Param("k", "SI", 1.0, None, None, "gain (SI)"),)

    @staticmethod
    def outputs(u, k):
        return (k * u,)
