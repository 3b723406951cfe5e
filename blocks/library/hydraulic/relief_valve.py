"""Direct-acting pressure relief valve."""

from blocks.block import Block, Param, fluid_params, hydraulic
from blocks.library.hydraulic.flow import leakage_problem, opening_range_problem, smooth_step, turbulent_flow
from blocks.registry import register


@register("relief_valve")
class ReliefValve(Block):
    """Pressure relief valve: opens from inlet a to outlet b when p_a - p_b exceeds the setting p_set.

    dp = p_a - p_b   (p_in - p_out)
    A  = A_leak + (A_max - A_leak) * s,  s = smooth_step(dp, p_set, p_open - p_set)
    q  = Cd*A*sqrt(2/rho) * dp / (dp^2 + dp_t^2)^(1/4)   [m^3/s]

    s is the C1 cubic ramp: 0 for dp <= p_set (closed, only leakage A_leak), 1 for dp >= p_open (fully
    open, area A_max); p_open - p_set is the pressure override (regulation range) and must be > 0 for a
    smooth opening (checked when the values are set), and A_leak <= A_max (checked). Same law as the check
    valve, with a working-pressure setting.

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet: the protected line"), hydraulic("b", "outlet, usually the tank line"))
    params = (
        Param("p_set", "Pa", None, 0.0, 1e9, "setting (cracking) pressure, p_a - p_b at which it starts to open"),
        Param("p_open", "Pa", None, 0.0, 1e9, "full-open pressure (p_a - p_b at which area A_max is reached), > p_set"),
        Param("A_max", "m^2", None, 0.0, 1.0, "fully open area"),
        Param("A_leak", "m^2", 1e-9, 0.0, 1.0, "leakage area of the closed valve (regularisation; 1e-9 m^2: 9 ml/min at 200 bar)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        return opening_range_problem(values, "p_set") or leakage_problem(values, "A_max", "valve")

    @staticmethod
    def derivatives(a, b, p_set, p_open, A_max, A_leak, Cd, dp_t, rho):
        dp = a - b
        area = A_leak + (A_max - A_leak) * smooth_step(dp, p_set, p_open - p_set)
        q = turbulent_flow(dp, area, Cd, rho, dp_t)
        return -q, q
