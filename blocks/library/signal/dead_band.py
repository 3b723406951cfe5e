"""Dead band (dead zone)."""

from blocks.block import Block, Param, signal_in, signal_out
from blocks.registry import register


@register("dead_band")
class DeadBand(Block):
    """Dead band: zero inside [lower, upper], the input's excursion beyond the band outside it.

    y = u - upper for u > upper,  y = 0 for lower <= u <= upper,  y = u - lower for u < lower

    lower <= upper is checked by ``check_values``. Units: u, y, lower and upper in the same (SI) unit.
    """

    ports = (signal_in("u", "input"), signal_out("y", "input minus the dead band"))
    same_quantity = (("u", "y"),)
    signal_dimensions = {"u": ("lower", "upper"), "y": ("lower", "upper")}
    params = (
        Param("lower", "SI", None, None, None, "lower edge of the band (SI)"),
        Param("upper", "SI", None, None, None, "upper edge of the band (SI)"),
    )

    @staticmethod
    def outputs(u, lower, upper):
        if u > upper:
            return (u - upper,)
        if u < lower:
            return (u - lower,)
        return (0.0,)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        if values["lower"] > values["upper"]:
            return f"lower = {values['lower']:g} is above upper = {values['upper']:g}"
        return None
