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
    Tolerance: x and dx have the nominal magnitude of y's quantity where the netlist fixes it (dx, a rate,
    keeps x's: stricter than it needs where the rate is over 1/s, which costs only steps;
    looser where it is slower), else 1.
    """

    ports = (signal_in("u", "input"), signal_out("y", "output"))
    params = (
        Param("wn", "rad/s", None, 1e-6, None, "natural angular frequency"),
        Param("zeta", "1", 1.0, 0.0, None, "damping ratio"),
        Param("k", "SI", 1.0, None, None, "static gain"),
    )
    states = (
        State("x", "SI", 0.0, 1.0, "output y", scale_of="y"),
        State("dx", "SI", 0.0, 1.0, "time derivative of the output", scale_of="y"),
    )

    @staticmethod
    def outputs(x):
        return (x,)

    @staticmethod
    def derivatives(u, x, dx, wn, zeta, k):
        return dx, lowpass2_acceleration(k * u, x, dx, wn, zeta)
