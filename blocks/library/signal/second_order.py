"""Second-order system."""

from blocks.block import Block, Param, State, signal_in, signal_out
from blocks.library.signal.linear import lowpass2_acceleration
from blocks.registry import register


@register("second_order")
class SecondOrder(Block):
    """Second-order system: Y(s)/U(s) = k*wn^2/(s^2 + 2*zeta*wn*s + wn^2).

    d2x/dt2 + 2*zeta*wn*dx/dt + wn^2*x = wn^2*k*u,   y = x
    States x (= y) and dx (= dy/dt), both starting at 0; no direct feedthrough.
    Units: wn in rad/s, zeta and k dimensionless; y in the unit of u times k's (SI).
    """

    ports = (signal_in("u", "input"), signal_out("y", "output"))
    params = (
        Param("wn", "rad/s", None, 1e-6, None, "natural angular frequency"),
        Param("zeta", "1", 1.0, 0.0, None, "damping ratio"),
        Param("k", "SI", 1.0, None, None, "static gain"),
    )
    states = (
        State("x", "SI", 0.0, 1.0, "output y"),
        State("dx", "SI", 0.0, 1.0, "time derivative of the output"),
    )

    @staticmethod
    def outputs(x):
        return (x,)

    @staticmethod
    def derivatives(u, x, dx, wn, zeta, k):
        return dx, lowpass2_acceleration(k * u, x, dx, wn, zeta)
