"""Constant signal."""

from blocks.block import Block, Param, signal_out
from blocks.registry import register


@register("constant")
class Constant(Block):
    """Constant signal: y = value.

    y = value   (no inputs, no states; value and y in the SI unit of the signal)
    """

    ports = (signal_out("y", "the constant"),)
    signal_dimensions = {"y": ("value",)}
    params = (Param("value", "SI", 0.0, None, None, "the output value (SI)"),)

    @staticmethod
    def outputs(value):
        return (value,)
