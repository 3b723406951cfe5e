"""Generic counterbalance (load-holding, over-centre) valve."""

from blocks.block import Block, Param, fluid_params, hydraulic
from blocks.library.hydraulic.flow import leakage_problem, opening_range_problem, smooth_max0, smooth_step, turbulent_flow
from blocks.registry import register


@register("counterbalance_valve")
class CounterbalanceValve(Block):
    """Counterbalance (over-centre) valve: free flow V -> C through a check valve, pilot-assisted relief C -> V.

    Check valve V -> C (lifts the load):
        A_cv = A_check*smooth_step(p_V - p_C, p_check, p_check_open - p_check)
        q_cv = Cd*A_cv*sqrt(2/rho) * (p_V - p_C)/((p_V - p_C)^2 + dp_t^2)^(1/4)        [m^3/s]
    Pilot-assisted relief C -> V (holds the load, meters it down when piloted):
        p_ctl = (p_C - p_V) + R_pilot*smooth_max0(p_pilot - p_V, dp_w)                  [Pa]
        A_r   = A_leak + (A_relief - A_leak)*smooth_step(p_ctl, p_set, dp_open)
        q_r   = Cd*A_r*sqrt(2/rho) * (p_C - p_V)/((p_C - p_V)^2 + dp_t^2)^(1/4)           [m^3/s]
    Delivered to the nets: q_V = q_r - q_cv, q_C = q_cv - q_r, q_pilot = 0 (the pilot takes no flow).

    Opening condition: the non-vented form, spring chamber referenced to V (the thesis's VBSO, eq. 2.20:
    alpha*(pv1 - pv2) - pv2 + pc2 - pcr2), as most cartridge counterbalance valves are built: the relief
    starts to open when (p_C - p_V) + R_pilot*(p_pilot - p_V) >= p_set and is fully open (A_relief) at
    p_set + dp_open; the valve-side pressure p_V adds to the setting at the rate (1 + R_pilot). With V and
    the pilot at the tank it holds a load pressure up to p_set (set it about 1.3 times the load pressure);
    piloted, it opens at p_C = p_set - R_pilot*p_pilot (both gauge, p_V = 0). The pilot piston only
    pushes: a pilot pressure below p_V does not pull the relief shut (max(., 0), rounded over
    |p_pilot - p_V| < dp_w/2: exact outside, R_pilot*dp_w/8 at p_pilot = p_V, the load-holding case,
    which the default dp_w = 0.1 bar keeps below 0.1 bar for R_pilot < 8). dp_open is the spring's
    pressure per full stroke over the relief seat (the thesis's VBSO: 900 bar, table 2.11); the smaller
    it is, the stiffer (and less stable) the metering.
    The closed relief leaks through A_leak (the load creeps); the closed check valve is tight.
    Quasi-static: the spool has no state (the crane's mcv_vaa and mcv_vbso model the spool dynamics).
    """

    ports = (
        hydraulic("V", "valve side, from the directional valve"),
        hydraulic("C", "cylinder (load) side"),
        hydraulic("pilot", "pilot: the opposite actuator line (takes no flow)"),
    )
    params = (
        Param("p_set", "Pa", None, 0.0, 1e9, "relief setting: (p_C - p_V) + R_pilot*(p_pilot - p_V) at which it cracks"),
        Param("R_pilot", "1", None, 0.0, 100.0, "pilot ratio: pilot piston area over the relief seat area"),
        Param("dp_open", "Pa", None, 0.0, 1e10,
              "opening range of the relief: fully open at p_set + dp_open (spring rate per full stroke)", positive=True),
        Param("A_relief", "m^2", None, 0.0, 1.0, "fully open area of the relief C -> V"),
        Param("A_check", "m^2", None, 0.0, 1.0, "fully open area of the check valve V -> C"),
        Param("p_check", "Pa", 0.5e5, 0.0, 1e8, "crack pressure of the check valve (p_V - p_C)"),
        Param("p_check_open", "Pa", 2e5, 0.0, 1e8, "full-open pressure of the check valve (p_V - p_C), > p_check"),
        Param("A_leak", "m^2", 1e-9, 0.0, 1.0, "leakage area of the closed relief (regularisation; 1e-9 m^2: 9 ml/min at 200 bar)"),
        Param("dp_w", "Pa", 1e4, 0.0, 1e8, "width over which the pilot piston's contact at p_pilot = p_V is rounded (regularisation)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        return (opening_range_problem(values, "p_check", "p_check_open", "check valve")
                or leakage_problem(values, "A_relief", "relief"))

    @staticmethod
    def derivatives(V, C, pilot, p_set, R_pilot, dp_open, A_relief, A_check, p_check, p_check_open, A_leak, dp_w,
                    Cd, dp_t, rho):
        area_cv = A_check * smooth_step(V - C, p_check, p_check_open - p_check)
        q_cv = turbulent_flow(V - C, area_cv, Cd, rho, dp_t)
        p_ctl = (C - V) + R_pilot * smooth_max0(pilot - V, dp_w)
        area_r = A_leak + (A_relief - A_leak) * smooth_step(p_ctl, p_set, dp_open)
        q_r = turbulent_flow(C - V, area_r, Cd, rho, dp_t)
        return q_r - q_cv, q_cv - q_r, 0.0
