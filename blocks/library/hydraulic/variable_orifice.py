"""Turbulent orifice whose area is a signal."""

from blocks.block import Block, Param, fluid_params, hydraulic, signal_in
from blocks.library.hydraulic.flow import turbulent_flow
from blocks.registry import register


@register("variable_orifice")
class VariableOrifice(Block):
    """Turbulent orifice whose area is read from a signal (clipped at 0), regularised near zero pressure drop.

    A_eff = max(A, 0)
    q = Cd*A_eff*sqrt(2/rho) * (p_a - p_b) / ((p_a - p_b)^2 + dp_t^2)^(1/4)   [m^3/s]

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (
        hydraulic("a", "inlet (positive flow leaves this net)"),
        hydraulic("b", "outlet"),
        signal_in("A", "orifice area (negative values read as 0)", "m^2"),
    )
    params = (
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @staticmethod
    def derivatives(a, b, A, Cd, dp_t, rho):
        q = turbulent_flow(a - b, max(A, 0.0), Cd, rho, dp_t)
        return -q, q
