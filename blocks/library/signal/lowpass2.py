"""Second-order low-pass filter."""

from blocks.block import Block, Param, State, signal_in, signal_out
from blocks.library.signal.linear import lowpass2_acceleration
from blocks.registry import register


@register("lowpass2")
class Lowpass2(Block):
    """Second-order low-pass filter: Y(s)/U(s) = wn^2/(s^2 + 2*zeta*wn*s + wn^2), unit static gain.

    d2x/dt2 + 2*zeta*wn*dx/dt + wn^2*x = wn^2*u,   y = x
    States x (= y) and dx (= dy/dt), both starting at 0; no direct feedthrough.
    zeta = 1/sqrt(2) is the Butterworth filter (-3 dB at wn). Units: wn in rad/s; u and y in one (SI) unit.
    Tolerance: x and dx have the nominal magnitude of u's quantity where the netlist fixes it (dx, a rate,
    keeps x's: stricter than it needs where the rate is over 1/s, which costs only steps;
    looser where it is slower), else 1.
    """

    ports = (signal_in("u", "signal to filter"), signal_out("y", "low-passed signal"))
    same_quantity = (("u", "y"),)
    params = (
        Param("wn", "rad/s", None, 1e-6, None, "corner (natural) angular frequency"),
        Param("zeta", "1", 0.7071067811865476, 0.0, None, "damping ratio (1/sqrt(2): Butterworth)"),
    )
    states = (
        State("x", "SI", 0.0, 1.0, "filter output y", scale_of="u"),
        State("dx", "SI", 0.0, 1.0, "time derivative of the filter output", scale_of="u"),
    )

    @staticmethod
    def outputs(x):
        return (x,)

    @staticmethod
    def derivatives(u, x, dx, wn, zeta):
        return dx, lowpass2_acceleration(u, x, dx, wn, zeta)
