"""Range check: a limit a signal must keep, warned of after a run."""

from blocks.block import Block, Param, ValidRange, signal_in
from blocks.library.signal.linear import UNLIMITED
from blocks.registry import register


@register("range_check")
class RangeCheck(Block):
    """Range check: a run in which the input leaves [lower, upper] ends with a warning saying when and how far.

    No output and no effect on the circuit: a limit the machine must keep, written on the drawing sheet (a
    hose's rated pressure through a pressure sensor, a motor's top speed, a cylinder's stroke). The warning
    names the block, when the input first left the range, and its value furthest outside it. Checked at the
    output samples (``dt_out``), as every block's valid range is (blocks/valid_ranges.py). Only one limit
    may be given: the other stays unlimited (+-1e300).

    lower <= upper is checked by ``check_values``. Units: u, lower and upper in the same (SI) unit.
    """

    ports = (signal_in("u", "the checked signal"),)
    signal_dimensions = {"u": ("lower", "upper")}
    params = (
        Param("lower", "SI", -UNLIMITED, None, None, "lowest value allowed (SI; default unlimited)"),
        Param("upper", "SI", UNLIMITED, None, None, "highest value allowed (SI; default unlimited)"),
    )
    checked = ("u",)

    @classmethod
    def valid_ranges(cls, values: dict) -> tuple[ValidRange, ...]:
        return (ValidRange("u", values["lower"], values["upper"], "a limit of the machine is broken"),)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        if not values["lower"] <= values["upper"]:
            return f"lower = {values['lower']:g} must not exceed upper = {values['upper']:g}"
        return None
