"""Saturation (hard limiter)."""

from blocks.block import Block, Param, signal_in, signal_out
from blocks.library.signal.linear import clamp
from blocks.registry import register


@register("saturation")
class Saturation(Block):
    """Saturation: the input limited to [lower, upper].

    y = min(max(u, lower), upper)

    lower <= upper is checked by ``check_values``. Units: u, y, lower and upper in the same (SI) unit.
    """

    ports = (signal_in("u", "input"), signal_out("y", "limited input"))
    same_quantity = (("u", "y"),)
    signal_dimensions = {"u": ("lower", "upper"), "y": ("lower", "upper")}
    params = (
        Param("lower", "SI", None, None, None, "lower limit (SI)"),
        Param("upper", "SI", None, None, None, "upper limit (SI)"),
    )

    @staticmethod
    def outputs(u, lower, upper):
        return (clamp(u, lower, upper),)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        if values["lower"] > values["upper"]:
            return f"lower = {values['lower']:g} is above upper = {values['upper']:g}"
        return None
