"""Strictly proper rational transfer function (no direct feedthrough)."""

from blocks.block import Block, Param, State, signal_in, signal_out
from blocks.library.signal.linear import check_transfer_function, tf_derivatives, tf_state_output
from blocks.registry import register


@register("transfer_function_strict")
class TransferFunctionStrict(Block):
    """Strictly proper rational transfer function Y(s)/U(s) = num(s)/den(s), without direct feedthrough.

    num = (b_0, ..., b_m), den = (a_0, ..., a_n): coefficients in descending powers of s, m < n (leading
    zeros of num do not count), a_0 != 0; everything is normalised by a_0. Realised in controllable
    canonical form (scipy.signal.tf2ss's realisation), num padded in front to length n+1 (so b_0 = 0):
        dx[0]/dt = u - sum_{k=1..n} a_k*x[k-1],   dx[k]/dt = x[k-1]  (k = 1..n-1)
        y = sum_{k=1..n} b_k*x[k-1]
    The array state x has n = len(den) - 1 entries, starting at 0 (the system at rest).

    Feedthrough: none -- ``outputs`` reads the state only, so the block breaks algebraic loops (use it for
    plants and filters in feedback). deg num < deg den is checked by ``check_values``; for
    deg num = deg den use ``transfer_function``. Units: y in the unit of u times the static gain's unit (SI).
    """

    ports = (signal_in("u", "input"), signal_out("y", "output"))
    params = (
        Param("num", "SI", None, None, None, "numerator coefficients, descending powers of s (SI)", array=True),
        Param("den", "SI", None, None, None, "denominator coefficients, descending powers of s, den[0] != 0 (SI)",
              array=True),
    )
    states = (State("x", "SI", 0.0, 1.0, "controllable canonical form state", size=lambda n: n["den"] - 1),)

    @staticmethod
    def outputs(x, num, den):
        return (tf_state_output(x, num, den),)

    @staticmethod
    def derivatives(u, x, den, der_x):
        tf_derivatives(u, x, den, der_x)
        return ()

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        return check_transfer_function(values["num"], values["den"], strict=True)
