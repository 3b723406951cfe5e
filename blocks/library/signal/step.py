"""Step signal."""

from blocks.block import Block, Param, signal_out
from blocks.registry import register


@register("step")
class Step(Block):
    """Step signal: y jumps from y0 to y1 at t = t_step.

    y = y0 for t < t_step,  y = y1 for t >= t_step

    Units: t_step in s; y0, y1 and y in the (SI) unit of the signal.
    """

    ports = (signal_out("y", "the step signal"),)
    signal_dimensions = {"y": ("y0", "y1")}
    params = (
        Param("t_step", "s", 0.0, None, None, "time of the step"),
        Param("y0", "SI", 0.0, None, None, "value before the step (SI)"),
        Param("y1", "SI", 1.0, None, None, "value from the step on (SI)"),
    )

    @staticmethod
    def outputs(t, t_step, y0, y1):
        return (y1 if t >= t_step else y0,)

    @classmethod
    def breakpoints(cls, values: dict) -> tuple[float, ...]:
        return (values["t_step"],)
