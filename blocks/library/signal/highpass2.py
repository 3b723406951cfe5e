"""Second-order high-pass filter."""

from blocks.block import Block, Param, State, signal_in, signal_out
from blocks.library.signal.linear import lowpass2_acceleration
from blocks.registry import register


@register("highpass2")
class Highpass2(Block):
    """Second-order high-pass filter: Y(s)/U(s) = s^2/(s^2 + 2*zeta*wn*s + wn^2).

    Realised through the low-pass state (well scaled: x is in the unit of u whatever wn is):
    d2x/dt2 + 2*zeta*wn*dx/dt + wn^2*x = wn^2*u,   y = u - x - (2*zeta/wn)*dx  (= (d2x/dt2)/wn^2)
    since 1 - L(s) - (2*zeta/wn)*s*L(s) = s^2/(s^2 + 2*zeta*wn*s + wn^2) with L the low-pass.
    States x and dx start at 0; direct feedthrough of u (a step passes straight through).
    Units: wn in rad/s; u and y in one (SI) unit.
    Tolerance: x and dx have the nominal magnitude of u's quantity where the netlist fixes it (dx, a rate,
    keeps x's: stricter than it needs where the rate is over 1/s, which costs only steps;
    looser where it is slower), else 1.
    """

    ports = (signal_in("u", "signal to filter"), signal_out("y", "high-passed signal"))
    same_quantity = (("u", "y"),)
    params = (
        Param("wn", "rad/s", None, 1e-6, None, "corner (natural) angular frequency"),
        Param("zeta", "1", 0.7071067811865476, 0.0, None, "damping ratio (1/sqrt(2): Butterworth)"),
    )
    states = (
        State("x", "SI", 0.0, 1.0, "low-pass part of the input", scale_of="u"),
        State("dx", "SI", 0.0, 1.0, "time derivative of the low-pass part", scale_of="u"),
    )

    @staticmethod
    def outputs(u, x, dx, wn, zeta):
        return (u - x - 2.0 * zeta / wn * dx,)

    @staticmethod
    def derivatives(u, x, dx, wn, zeta):
        return dx, lowpass2_acceleration(u, x, dx, wn, zeta)
