"""Piecewise-linear time profile."""

from blocks.block import Block, Param, signal_out
from blocks.library.signal.tables import check_breakpoints, check_length, interp1
from blocks.registry import register


@register("profile")
class Profile(Block):
    """Piecewise-linear time profile through the points (times[i], values[i]), held constant outside.

    y = values[i] + (values[i+1] - values[i])*(t - times[i])/(times[i+1] - times[i])  for times[i] <= t <= times[i+1]
    y = values[0] for t < times[0],  y = values[-1] for t > times[-1]

    times must be strictly increasing and as long as values (checked by ``check_values``).
    Units: times in s; values and y in the (SI) unit of the signal.
    """

    ports = (signal_out("y", "the profile value at time t"),)
    signal_dimensions = {"y": ("values",)}
    params = (
        Param("times", "s", None, None, None, "breakpoint times, strictly increasing", array=True),
        Param("values", "SI", None, None, None, "profile values at the breakpoint times (SI)", array=True),
    )

    @staticmethod
    def outputs(t, times, values):
        return (interp1(t, times, values, False),)

    @classmethod
    def breakpoints(cls, values: dict) -> tuple[float, ...]:
        """The points where the slope changes (held constant outside: the ends count when the profile
        moves next to them); a point in a straight run, such as flat padding, is none."""
        times, values_ = values["times"], values["values"]
        slopes = [0.0] + [(values_[i + 1] - values_[i]) / (times[i + 1] - times[i])
                          for i in range(len(times) - 1)] + [0.0]
        return tuple(float(t) for i, t in enumerate(times) if slopes[i] != slopes[i + 1])

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        return check_breakpoints("times", values["times"]) or check_length(
            "values", values["values"], len(values["times"]), "one per entry of times"
        )
