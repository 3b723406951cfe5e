"""Check (non-return) valve."""

from blocks.block import Block, Param, fluid_params, hydraulic
from blocks.library.hydraulic.flow import leakage_problem, opening_range_problem, smooth_step, turbulent_flow
from blocks.registry import register


@register("check_valve")
class CheckValve(Block):
    """Check valve: opens from a to b once p_a - p_b exceeds the crack pressure, turbulent flow law.

    dp = p_a - p_b
    A  = A_leak + (A_max - A_leak) * s,  s = smooth_step(dp, p_crack, p_open - p_crack)
    q  = Cd*A*sqrt(2/rho) * dp / (dp^2 + dp_t^2)^(1/4)   [m^3/s]

    s is the C1 cubic ramp: 0 for dp <= p_crack (closed: only the leakage area A_leak passes flow, in
    either direction), 1 for dp >= p_open (fully open, area A_max), smooth in between. p_open > p_crack
    is required (checked when the values are set: p_open <= p_crack would be a step). The leakage area keeps
    the closed valve well-conditioned; A_leak <= A_max is required (checked: above it the closed valve would
    pass more than the open one).

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet (flow a -> b opens the valve)"), hydraulic("b", "outlet"))
    params = (
        Param("A_max", "m^2", None, 0.0, 1.0, "fully open area"),
        Param("p_crack", "Pa", 1e5, 0.0, 1e9, "cracking pressure (p_a - p_b at which the valve starts to open)"),
        Param("p_open", "Pa", 2e5, 0.0, 1e9, "full-open pressure (p_a - p_b at which area A_max is reached), > p_crack"),
        Param("A_leak", "m^2", 1e-9, 0.0, 1.0, "leakage area of the closed valve (regularisation; 1e-9 m^2: 9 ml/min at 200 bar)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        return opening_range_problem(values, "p_crack") or leakage_problem(values, "A_max", "valve")

    @staticmethod
    def derivatives(a, b, A_max, p_crack, p_open, A_leak, Cd, dp_t, rho):
        dp = a - b
        area = A_leak + (A_max - A_leak) * smooth_step(dp, p_crack, p_open - p_crack)
        q = turbulent_flow(dp, area, Cd, rho, dp_t)
        return -q, q
