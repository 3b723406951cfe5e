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
    """4/3 proportional directional valve with a dead band: four turbulent metering edges, and a centre
    position closed (the default), float, tandem or open.

    A_PA = A_BT = A_max*max(0,  x - x_db)/(1 - x_db) + A_leak     (open for x > 0)
    A_PB = A_AT = A_max*max(0, -x - x_db)/(1 - x_db) + A_leak     (open for x < 0)
    centre passages, closing as the spool leaves the centre over x_c:
    A_AT,c = A_BT,c = A_float*max(0, 1 - |x|/x_c),   A_PT,c = A_bypass*max(0, 1 - |x|/x_c)
    q_XY = Cd*A_XY*sqrt(2/rho) * (p_X - p_Y) / ((p_X - p_Y)^2 + dp_t^2)^(1/4)   flow X -> Y [m^3/s]

    Delivered to the nets: q_P = -(q_PA + q_PB + q_PT,c), q_T = q_BT + q_AT + q_AT,c + q_BT,c + q_PT,c,
    q_A = q_PA - q_AT - q_AT,c, q_B = q_PB - q_BT - q_BT,c, so q_P + q_T + q_A + q_B = 0 for every state
    (the valve stores no oil). x is the dimensionless spool position in [-1, 1] (not clipped: values beyond
    +-1 extrapolate the linear area); A_leak is a leakage area on every edge (default 0).

    Centre: closed (A_float = A_bypass = 0, the default); float (A_float > 0: A and B drain to T, so a
    motion-control valve's pilot is not held after a stop); tandem (A_bypass > 0: the pump unloads P -> T,
    A and B held); open (both).
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
        Param("A_float", "m^2", 0.0, 0.0, 1.0, "centre passages A -> T and B -> T, each (float or open centre)"),
        Param("A_bypass", "m^2", 0.0, 0.0, 1.0, "centre passage P -> T (tandem or open centre)"),
        Param("x_c", "1", 0.05, 1e-3, 1.0, "spool travel from the centre over which the centre passages close"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @staticmethod
    def derivatives(P, T, A, B, x, A_max, x_db, A_leak, A_float, A_bypass, x_c, Cd, dp_t, rho):
        a_pos = metering_area(x, A_max, x_db) + A_leak
        a_neg = metering_area(-x, A_max, x_db) + A_leak
        q_PA = turbulent_flow(P - A, a_pos, Cd, rho, dp_t)
        q_BT = turbulent_flow(B - T, a_pos, Cd, rho, dp_t)
        q_PB = turbulent_flow(P - B, a_neg, Cd, rho, dp_t)
        q_AT = turbulent_flow(A - T, a_neg, Cd, rho, dp_t)
        q_P, q_T, q_A, q_B = -(q_PA + q_PB), q_BT + q_AT, q_PA - q_AT, q_PB - q_BT
        if A_float > 0.0 or A_bypass > 0.0:  # a closed centre's sums stay exactly the four edges'
            centre = max(0.0, 1.0 - abs(x) / x_c)
            q_ATc = turbulent_flow(A - T, A_float * centre, Cd, rho, dp_t)
            q_BTc = turbulent_flow(B - T, A_float * centre, Cd, rho, dp_t)
            q_PTc = turbulent_flow(P - T, A_bypass * centre, Cd, rho, dp_t)
            q_P, q_T, q_A, q_B = q_P - q_PTc, q_T + q_ATc + q_BTc + q_PTc, q_A - q_ATc, q_B - q_BTc
        return q_P, q_T, q_A, q_B
