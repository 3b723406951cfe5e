"""Shuttle valve (OR element): the higher of two inlet pressures reaches the outlet."""

from blocks.block import Block, Param, fluid_params, hydraulic
from blocks.library.hydraulic.flow import leakage_problem, smooth_step, turbulent_flow
from blocks.registry import register


@register("shuttle_valve")
class ShuttleValve(Block):
    """Shuttle valve: connects the higher-pressure inlet, a or b, to out (load-sense selection), smooth over a band.

    s    = smooth_step(p_a - p_b, -dp_w/2, dp_w)     ball position: 0 seated against a (b open), 1 against b
    A_a  = A_leak + (A_max - A_leak)*s,   A_b = A_leak + (A_max - A_leak)*(1 - s)
    q_ao = Cd*A_a*sqrt(2/rho) * (p_a - p_out)/((p_a - p_out)^2 + dp_t^2)^(1/4)   [m^3/s], flow a -> out
    q_bo = Cd*A_b*sqrt(2/rho) * (p_b - p_out)/((p_b - p_out)^2 + dp_t^2)^(1/4)   [m^3/s], flow b -> out
    Delivered to the nets: q_a = -q_ao, q_b = -q_bo, q_out = q_ao + q_bo (they sum to zero).

    The ball follows p_a - p_b quasi-statically (no state): for p_a - p_b >= dp_w/2 the passage a -> out is
    fully open and b -> out closed (leakage A_leak only), for p_a - p_b <= -dp_w/2 the reverse; in between
    the two areas are blended by the C1 cubic ramp, half open each at p_a = p_b. With the outlet
    dead-ended (a load-sense line, a brake port) p_out settles at the higher inlet pressure, lowered only
    by the leak into the other inlet: by x with A_max*g(x) = A_leak*g(|p_a - p_b| - x), g the regularised
    root above, so x <= 2^(1/4)*(A_leak/A_max)*sqrt(dp_t*|p_a - p_b|) while x < dp_t (the open passage's
    tiny drop is in the linear part of the law): 1 mbar at 100 bar apart with the defaults and
    A_max = 10 mm^2; x <= sqrt(2)*(A_leak/A_max)^2*|p_a - p_b| otherwise. Inside the
    band it is a weighted mean of p_a and p_b, A_a^2*(p_a - p_out) = A_b^2*(p_out - p_b) in the square-root
    law (A_a*(p_a - p_out) = A_b*(p_out - p_b) where the drops are well below dp_t and the law is linear),
    which lies at most 0.023*dp_w (0.044*dp_w in the linear law) below max(p_a, p_b). Flow out -> inlet
    (p_out above both) passes the open passage in reverse.
    """

    ports = (
        hydraulic("a", "inlet a"),
        hydraulic("b", "inlet b"),
        hydraulic("out", "outlet: the higher of p_a, p_b"),
    )
    params = (
        Param("A_max", "m^2", None, 0.0, 1.0, "fully open area of each passage (a -> out, b -> out)"),
        Param("dp_w", "Pa", 1e5, 0.0, 1e8, "band of p_a - p_b over which the ball shifts (centred on p_a = p_b)",
              positive=True),
        Param("A_leak", "m^2", 1e-9, 0.0, 1.0, "leakage area of the closed passage (regularisation; 1e-9 m^2: 9 ml/min at 200 bar)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        return leakage_problem(values, "A_max", "passage")

    @staticmethod
    def derivatives(a, b, out, A_max, dp_w, A_leak, Cd, dp_t, rho):
        s = smooth_step(a - b, -0.5 * dp_w, dp_w)
        q_ao = turbulent_flow(a - out, A_leak + (A_max - A_leak) * s, Cd, rho, dp_t)
        q_bo = turbulent_flow(b - out, A_leak + (A_max - A_leak) * (1.0 - s), Cd, rho, dp_t)
        return -q_ao, -q_bo, q_ao + q_bo
