"""2-way pressure-compensated flow-control valve."""

from blocks.block import Block, Param, fluid_params, hydraulic
from blocks.library.hydraulic.flow import smooth_max0, turbulent_flow
from blocks.registry import register


@register("flow_control_valve")
class FlowControlValve(Block):
    """2-way pressure-compensated flow-control valve a -> b: a metering orifice whose drop a compensator holds at dp_c.

    dp   = p_a - p_b                                             [Pa], the drop over the whole valve
    dp_m = dp - smooth_max0(dp - dp_c, knee*dp_c)                [Pa], the drop over the metering orifice
    q    = Cd*A_meter*sqrt(2/rho) * dp_m/(dp_m^2 + dp_t^2)^(1/4)   [m^3/s], flow a -> b

    The compensator (a spring-loaded spool in series with the metering orifice) is wide open while the
    drop is small and takes up everything beyond dp_c once the drop exceeds it: dp_m = min(dp, dp_c), so the
    flow follows the (regularised) square-root law of the whole drop, q = Cd*A_meter*sqrt(2*dp/rho), below
    dp_c and is held at q_set = Cd*A_meter*sqrt(2*dp_c/rho) above it, whatever the drop. The corner of the
    min is rounded over |dp - dp_c| < knee*dp_c/2 (smooth_max0: a parabola, exact min outside that band),
    so q is C1 in dp. It is monotone: d(dp_m)/d(dp) = 1 - smooth_max0' lies in [0, 1] (1 below the band, 0
    above it) and the regularised square-root law is strictly increasing, so q never falls as the drop
    rises (it is flat above the knee: an ideal compensator). knee <= 1 keeps the band clear of dp = 0.
    Reverse flow (dp < 0, b -> a) passes the metering orifice alone, uncompensated: dp_m = dp, the
    square-root law in reverse (put a check_valve in parallel for free reverse flow). Quasi-static: the
    compensator spool has no state.

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet (flow a -> b is compensated)"), hydraulic("b", "outlet"))
    params = (
        Param("A_meter", "m^2", None, 0.0, 1.0, "metering orifice area (sets the flow: q_set = Cd*A_meter*sqrt(2*dp_c/rho))"),
        Param("dp_c", "Pa", None, 0.0, 1e8, "compensator setting: the drop it holds over the metering orifice",
              positive=True),
        Param("knee", "1", 0.1, 0.0, 1.0, "width of the rounded knee at dp = dp_c, as a fraction of dp_c (regularisation)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient of the metering orifice"),
        Param("dp_t", "Pa", 1e4, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @staticmethod
    def derivatives(a, b, A_meter, dp_c, knee, Cd, dp_t, rho):
        dp = a - b
        dp_m = dp - smooth_max0(dp - dp_c, knee * dp_c)
        q = turbulent_flow(dp_m, A_meter, Cd, rho, dp_t)
        return -q, q
