"""4/3 proportional directional valve."""

from numba import njit

from blocks.block import Block, Param, fluid_params, hydraulic, signal_in
from blocks.library.hydraulic.flow import turbulent_flow
from blocks.registry import register


@njit(cache=True)
def metering_area(s, A_max, x_db):
    """Area of one metering edge at spool opening s (>0 opens it): A_max*max(0, s - x_db)/(1 - x_db)."""
    return A_max * max(0.0, s - x_db) / (1.0 - x_db)


@register("valve_4_3")
class Valve43(Block):
    """4/3 proportional directional valve, closed centre with a dead band: four turbulent metering edges.

    A_PA = A_BT = A_max*max(0,  x - x_db)/(1 - x_db) + A_leak     (open for x > 0)
    A_PB = A_AT = A_max*max(0, -x - x_db)/(1 - x_db) + A_leak     (open for x < 0)
    q_XY = Cd*A_XY*sqrt(2/rho) * (p_X - p_Y) / ((p_X - p_Y)^2 + dp_t^2)^(1/4)   flow X -> Y [m^3/s]

    Delivered to the nets: q_P = -(q_PA + q_PB), q_T = q_BT + q_AT, q_A = q_PA - q_AT, q_B = q_PB - q_BT,
    so q_P + q_T + q_A + q_B = 0 for every state (the valve stores no oil). x is the dimensionless spool
    position in [-1, 1] (not clipped: values beyond +-1 extrapolate the linear area); A_leak is a leakage
    area on every edge (default 0).
    """

    ports = (
        hydraulic("P", "supply (pressure) port"),
        hydraulic("T", "return (tank) port"),
        hydraulic("A", "work port A (P -> A for x > 0)"),
        hydraulic("B", "work port B (P -> B for x < 0)"),
        signal_in("x", "spool position, -1 ... 1", "1"),
    )
    params = (
        Param("A_max", "m^2", None, 0.0, 1.0, "area of one metering edge at full spool stroke"),
        Param("x_db", "1", 0.0, 0.0, 0.99, "dead band (overlap) as a fraction of the spool stroke"),
        Param("A_leak", "m^2", 0.0, 0.0, 1.0, "leakage area added to every edge"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @staticmethod
    def derivatives(P, T, A, B, x, A_max, x_db, A_leak, Cd, dp_t, rho):
        a_pos = metering_area(x, A_max, x_db) + A_leak
        a_neg = metering_area(-x, A_max, x_db) + A_leak
        q_PA = turbulent_flow(P - A, a_pos, Cd, rho, dp_t)
        q_BT = turbulent_flow(B - T, a_pos, Cd, rho, dp_t)
        q_PB = turbulent_flow(P - B, a_neg, Cd, rho, dp_t)
        q_AT = turbulent_flow(A - T, a_neg, Cd, rho, dp_t)
        return -(q_PA + q_PB), q_BT + q_AT, q_PA - q_AT, q_PB - q_BT
