"""Product of two signals."""

from blocks.block import Block, signal_in, signal_out
from blocks.registry import register


@register("product")
class Product(Block):
    """Product of two signals: y = u1*u2.

    Units: y in the product of the (SI) units of u1 and u2.
    """

    ports = (signal_in("u1", "first factor"), signal_in("u2", "second factor"), signal_out("y", "u1*u2"))

    @staticmethod
    def outputs(u1, u2):
        return (u1 * u2,)
