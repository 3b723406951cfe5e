"""Turbulent orifice of fixed area."""

from blocks.block import Block, Param, fluid_params, hydraulic
from blocks.library.hydraulic.flow import turbulent_flow
from blocks.registry import register


@register("orifice")
class Orifice(Block):
    """Turbulent orifice of fixed area, regularised (linear) near zero pressure drop.

    q = Cd*A*sqrt(2/rho) * (p_a - p_b) / ((p_a - p_b)^2 + dp_t^2)^(1/4)

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet (positive flow leaves this net)"), hydraulic("b", "outlet"))
    params = (
        Param("A", "m^2", None, 0.0, 1.0, "orifice area"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @staticmethod
    def derivatives(a, b, A, Cd, dp_t, rho):
        q = turbulent_flow(a - b, A, Cd, rho, dp_t)
        return -q, q
