"""Ramp signal."""

from blocks.block import Block, Param, signal_out
from blocks.registry import register


@register("ramp")
class Ramp(Block):
    """Ramp signal from y0 starting at t_start, either unbounded with a slope or reaching y1 after a duration.

    duration = 0:  y = y0 + slope*(t - t_start) for t > t_start, y0 before (slope used, y1 ignored)
    duration > 0:  y = y0 + (y1 - y0)*(t - t_start)/duration on [t_start, t_start + duration],
                   y0 before, held at y1 after (slope ignored)

    Units: t_start and duration in s; y0, y1 and y in the (SI) unit of the signal; slope in that unit per s
    (written with its unit it is converted to SI, "100 mm/s" to 0.1, "30 rpm/s" to 3.14; its dimension is
    not checked, the signal's being generic).
    """

    ports = (signal_out("y", "the ramp signal"),)
    signal_dimensions = {"y": ("y0", "y1")}
    params = (
        Param("t_start", "s", 0.0, None, None, "time the ramp starts"),
        Param("y0", "SI", 0.0, None, None, "value before the ramp starts (SI)"),
        Param("slope", "SI", 1.0, None, None, "slope of the unbounded ramp, SI signal units per s (100 mm/s, 0.1)"),
        Param("duration", "s", 0.0, 0.0, None, "ramp time to reach y1, then hold; 0: unbounded ramp at slope"),
        Param("y1", "SI", 1.0, None, None, "final value reached after duration (used when duration > 0)"),
    )

    @staticmethod
    def outputs(t, t_start, y0, slope, duration, y1):
        if t <= t_start:
            return (y0,)
        if duration > 0.0:
            if t >= t_start + duration:
                return (y1,)
            return (y0 + (y1 - y0) * (t - t_start) / duration,)
        return (y0 + slope * (t - t_start),)

    @classmethod
    def breakpoints(cls, values: dict) -> tuple[float, ...]:
        start, duration = values["t_start"], values["duration"]
        return (start, start + duration) if duration > 0.0 else (start,)
