"""Constant signal."""

from blocks.block import Block, Param, signal_out
from blocks.registry import register


@register("constant")
class Constant(Block):
    """Constant signal: y = value."""

    ports = (signal_out("y", "the constant"),)
    params = (Param("value", "1", 0.0, None, None, "the output value (SI)"),)

    @staticmethod
    def outputs(value):
        return (value,)
