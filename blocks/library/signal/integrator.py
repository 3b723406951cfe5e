"""Integrator with optional output limits."""

from blocks.block import Block, Param, State, signal_in, signal_out
from blocks.library.signal.linear import UNLIMITED, clamp
from blocks.registry import register


@register("integrator")
class Integrator(Block):
    """Integrator with optional output limits and conditional-integration anti-windup: y = x, dx/dt = k*u.

    dx/dt = k*u, except dx/dt = 0 while x >= y_max and k*u > 0, or x <= y_min and k*u < 0
    y = min(max(x, y_min), y_max)
    Anti-windup: the state stops at a limit instead of winding up beyond it and leaves it as soon as the
    input reverses. The initial value is the start of state x (should lie in [y_min, y_max]). With the
    default limits (+-1e300) the block is a plain integrator; no direct feedthrough.
    Units: k in 1/s when u and y share a unit (in general unit(y)/(unit(u)*s)); y, x, y_min, y_max in y's (SI).
    Tolerance: x has the nominal magnitude of y's quantity where the netlist fixes it, else 1.
    """

    ports = (signal_in("u", "input"), signal_out("y", "integral of k*u, limited"))
    params = (
        Param("k", "1/s", 1.0, None, None, "integration gain"),
        Param("y_min", "SI", -UNLIMITED, None, None, "lower output limit (SI; default unlimited)"),
        Param("y_max", "SI", UNLIMITED, None, None, "upper output limit (SI; default unlimited)"),
    )
    states = (State("x", "SI", 0.0, 1.0, "integral of k*u (the initial value is its start)", scale_of="y"),)

    @staticmethod
    def outputs(x, y_min, y_max):
        return (clamp(x, y_min, y_max),)

    @staticmethod
    def derivatives(u, x, k, y_min, y_max):
        rate = k * u
        if (x >= y_max and rate > 0.0) or (x <= y_min and rate < 0.0):
            return (0.0,)
        return (rate,)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        if values["y_min"] > values["y_max"]:
            return f"y_min = {values['y_min']:g} is above y_max = {values['y_max']:g}"
        return None
