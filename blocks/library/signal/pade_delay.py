"""Transport delay approximated by a second-order Pade filter."""

from blocks.block import Block, Param, State, signal_in, signal_out
from blocks.registry import register


@register("pade_delay")
class PadeDelay(Block):
    """Transport delay y(t) ~ u(t - T) as the second-order Pade approximant, with pass-through for T < T_min.

    G(s) = (1 - sT/2 + (sT)^2/12) / (1 + sT/2 + (sT)^2/12) = 1 - sT / (1 + sT/2 + (sT)^2/12)
    realised as  x1' = x2,  (T^2/12)*x2' = u - x1 - (T/2)*x2,  y = u - T*x2      (T >= T_min)
                 x1' = x2' = 0,  y = u                                           (T <  T_min)
    The filter has unit gain, a phase lag that matches e^(-sT) to 4th order in sT, natural frequency
    sqrt(12)/T and damping 0.866; it follows a step with a brief inverse response. The pass-through below
    the declared T_min (regularisation: the filter's poles go to infinity as T -> 0) makes T = 0 exactly
    "no delay", so calibration can insert the block with a zero parameter; the jump at T_min is
    O(T_min*du/dt). States start at rest (0): give u(0) = 0 or expect a start transient of length ~T.
    Units: T in s; y in the unit of u (SI).
    Tolerance: x1 and x2 have the nominal magnitude of u's quantity where the netlist fixes it (x2, a rate,
    keeps x1's: stricter than it needs where the rate is over 1/s, which costs only steps;
    looser where it is slower), else 1.
    """

    ports = (signal_in("u", "input"), signal_out("y", "the input delayed by about T"))
    same_quantity = (("u", "y"),)
    params = (
        Param("T", "s", 0.0, 0.0, 100.0, "delay time"),
        Param("T_min", "s", 1e-5, 1e-9, 1.0, "below this delay the block passes u through (regularisation)"),
    )
    states = (
        State("x1", "SI", 0.0, 1.0, "filter state: u filtered by 1/(1 + sT/2 + (sT)^2/12)", scale_of="u"),
        State("x2", "SI", 0.0, 1.0, "time derivative of x1", scale_of="u"),
    )

    @staticmethod
    def outputs(u, x2, T, T_min):
        if T < T_min:
            return (u,)
        return (u - T * x2,)

    @staticmethod
    def derivatives(u, x1, x2, T, T_min):
        if T < T_min:
            return 0.0, 0.0
        return x2, 12.0 * (u - x1 - 0.5 * T * x2) / (T * T)
