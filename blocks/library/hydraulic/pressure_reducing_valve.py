"""Direct-operated 3-way pressure-reducing/relieving valve."""

from blocks.block import Block, Param, fluid_params, hydraulic
from blocks.library.hydraulic.flow import leakage_problem, smooth_step, turbulent_flow
from blocks.registry import register


@register("pressure_reducing_valve")
class PressureReducingValve(Block):
    """3-way pressure-reducing/relieving valve: holds p_A - p_T near p_set, reducing edge P -> A, relieving edge A -> T.

    x    = p_A - p_T   [Pa], the controlled pressure (the spring chamber drains to T)
    A_PA = A_leak + (A_max - A_leak)*(1 - smooth_step(x, p_set, dp_band))                       reducing edge
    A_AT = A_leak + (A_relief - A_leak)*smooth_step(x, p_set + dp_band + dp_relief, dp_band)    relieving edge
    q_PA = Cd*A_PA*sqrt(2/rho) * (p_P - p_A)/((p_P - p_A)^2 + dp_t^2)^(1/4)   [m^3/s], flow P -> A
    q_AT = Cd*A_AT*sqrt(2/rho) * (p_A - p_T)/((p_A - p_T)^2 + dp_t^2)^(1/4)   [m^3/s], flow A -> T

    The band lies above the setting: the reducing edge is fully open (A_max) for x <= p_set and closes over
    p_set ... p_set + dp_band (C1 cubic ramp), so while the valve regulates (the load takes less than the
    fully open edge passes) the outlet sits between p_set and p_set + dp_band. dp_relief >= 0 is the
    overlap: both edges are closed (leakage only) for p_set + dp_band <= x <= p_set + dp_band + dp_relief,
    so the two edges never open together and no oil passes straight from P to T. The relieving edge opens
    over the same width dp_band above that and reaches A_relief at p_set + 2*dp_band + dp_relief: oil pushed
    back into A (an overrunning load, thermal expansion) is let out to T there. With the outlet dead-ended
    the pressure settles in the overlap, where the two edges' leakages balance: near its top when the
    supply is high (p_P - p_A > p_A - p_T: the reducing edge's leakage is the larger, so the relieving
    edge must start to open), near its bottom, p_set + dp_band, when it is not (the reducing edge must
    start to open). The reducing edge has no check valve: with p_A above p_P and the edge open, oil flows back A -> P.
    The spool is quasi-static (no spool state).

    Delivered to the nets: q_P = -q_PA, q_A = q_PA - q_AT, q_T = q_AT (they sum to zero: no oil stored).
    """

    ports = (
        hydraulic("P", "supply (inlet) port"),
        hydraulic("A", "regulated outlet"),
        hydraulic("T", "tank / drain port: relieving outlet, and the spring chamber's reference"),
    )
    params = (
        Param("p_set", "Pa", None, 0.0, 1e9, "setting: p_A - p_T at which the reducing edge P -> A starts to close"),
        Param("dp_band", "Pa", 5e5, 0.0, 1e8,
              "regulation band: the reducing edge closes over p_set ... p_set + dp_band (and the relieving edge "
              "opens over the same width)", positive=True),
        Param("dp_relief", "Pa", 1e5, 0.0, 1e8,
              "overlap: the relieving edge A -> T starts to open at p_set + dp_band + dp_relief"),
        Param("A_max", "m^2", None, 0.0, 1.0, "fully open area of the reducing edge P -> A"),
        Param("A_relief", "m^2", None, 0.0, 1.0, "fully open area of the relieving edge A -> T"),
        Param("A_leak", "m^2", 1e-9, 0.0, 1.0, "leakage area of each closed edge (regularisation; 1e-9 m^2: 9 ml/min at 200 bar)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        return leakage_problem(values, "A_max", "edge") or leakage_problem(values, "A_relief", "edge")

    @staticmethod
    def derivatives(P, A, T, p_set, dp_band, dp_relief, A_max, A_relief, A_leak, Cd, dp_t, rho):
        x = A - T
        area_PA = A_leak + (A_max - A_leak) * (1.0 - smooth_step(x, p_set, dp_band))
        area_AT = A_leak + (A_relief - A_leak) * smooth_step(x, p_set + dp_band + dp_relief, dp_band)
        q_PA = turbulent_flow(P - A, area_PA, Cd, rho, dp_t)
        q_AT = turbulent_flow(A - T, area_AT, Cd, rho, dp_t)
        return -q_PA, q_PA - q_AT, q_AT
