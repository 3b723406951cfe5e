"""Rational transfer function with direct feedthrough."""

from blocks.block import Block, Param, State, signal_in, signal_out
from blocks.library.signal.linear import check_transfer_function, tf_derivatives, tf_numerator, tf_state_output
from blocks.registry import register


@register("transfer_function")
class TransferFunction(Block):
    """Proper rational transfer function Y(s)/U(s) = num(s)/den(s), with direct feedthrough.

    num = (b_0, ..., b_m), den = (a_0, ..., a_n): coefficients in descending powers of s, m <= n,
    a_0 != 0. Everything is normalised by a_0. Realised in controllable canonical form (the realisation of
    scipy.signal.tf2ss), with num padded in front to length n+1, b_k and a_k divided by a_0:
        dx[0]/dt = u - sum_{k=1..n} a_k*x[k-1],   dx[k]/dt = x[k-1]  (k = 1..n-1)
        y = sum_{k=1..n} (b_k - a_k*b_0)*x[k-1] + b_0*u
    The array state x has n = len(den) - 1 entries, starting at 0 (the system at rest).

    Feedthrough: ``outputs`` always takes u, so this block always declares direct feedthrough, even when
    deg num < deg den (b_0 = 0 and the output does not in fact depend on u). That is conservative: it is
    never wrong, but it can report an algebraic loop that is not there. For a strictly proper transfer
    function inside a feedback loop use ``transfer_function_strict``, which does not take u in its outputs.
    num/den are checked by ``check_values``. Units: y in the unit of u times the static gain's unit (SI).
    """

    ports = (signal_in("u", "input"), signal_out("y", "output"))
    params = (
        Param("num", "SI", None, None, None, "numerator coefficients, descending powers of s (SI)", array=True),
        Param("den", "SI", None, None, None, "denominator coefficients, descending powers of s, den[0] != 0 (SI)",
              array=True),
    )
    states = (State("x", "SI", 0.0, 1.0, "controllable canonical form state", size=lambda n: n["den"] - 1),)

    @staticmethod
    def outputs(u, x, num, den):
        return (tf_numerator(num, den, 0) * u + tf_state_output(x, num, den),)

    @staticmethod
    def derivatives(u, x, den, der_x):
        tf_derivatives(u, x, den, der_x)
        return ()

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        return check_transfer_function(values["num"], values["den"], strict=False)
