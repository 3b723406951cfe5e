"""Direct-acting spool relief valve with spool dynamics, steady flow force and spool friction (Dahl)."""

import math

from numba import njit

from blocks.block import Block, Param, State, fluid_params, hydraulic
from blocks.library.hydraulic.flow import turbulent_flow
from blocks.library.signal.linear import lowpass2_acceleration
from blocks.registry import register


@njit(cache=True)
def rounded_unit(x, width):
    """x clipped to [0, 1] with C1-rounded corners of width ``width`` (< 0.5): exactly 0 for x <= 0 and 1 for
    x >= 1, x on [width, 1 - width], 2x^2/w - x^3/w^2 on (0, w) and its mirror image on (1 - w, 1)."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    if width <= 0.0:
        return x
    if x < width:
        s = x / width
        return width * s * s * (2.0 - s)
    if x > 1.0 - width:
        s = (1.0 - x) / width
        return 1.0 - width * s * s * (2.0 - s)
    return x


@register("spool_relief_valve")
class SpoolReliefValve(Block):
    """Spool relief valve a -> b: spring-balanced stroke u, 2nd-order spool, steady flow force, Dahl friction.

    dp   = p_a - p_b                                        [Pa]
    s    = sat(u)   (u clipped to [0, 1], corners rounded over u_w; exactly 0 for u <= 0)
    q    = Cd*A_max*s*sqrt(2/rho) * dp/(dp^2 + dp_t^2)^(1/4)    flow a -> b [m^3/s]
    p_F  = c_ff*s*dp                                        steady flow force over the spool area [Pa]
    u_eq = (dp - p_set - p_F - p_fric*z)/k_s                 spool balance, all forces over the spool area
    u''  = wn^2*(sat(u_eq) - u) - 2*zeta*wn*u'              spool dynamics (as the MCV's, thesis fig. 2.17)
    z'   = (u' - z*|u'|)/u_z                                 Dahl friction state, |z| <= 1

    The spring (preload p_set = the crack pressure, stiffness k_s per unit stroke) holds the spool shut
    until dp exceeds p_set. The steady flow force is the classical 2*Cd*Cv*A(x)*dp*cos(theta) divided by
    the spool area: proportional to the open area and the pressure drop, so c_ff (dimensionless) > 0
    closes the valve (the usual jet force) and c_ff = 0 is the valve without it; at rest inside the stroke
    the opening solves u*k_s = dp - p_set - c_ff*u*dp, u = (dp - p_set)/(k_s + c_ff*dp).
    The spool friction is Dahl's model: the friction pressure p_fric*z follows the spool motion over a
    pre-sliding stroke u_z and stays where it is when the spool stops, so a spool that came to rest going
    up sits p_fric/k_s lower than without friction and one going down p_fric/k_s higher: a hysteresis of
    width 2*p_fric in dp. The law is Dahl's exact one, (u'/u_z)*(1 - z*sign(u')): |z| <= 1 holds from any
    start inside it, z settles at sign(u') while the spool moves and stays put when it stops. (A smoothed
    sign, u'/sqrt(u'^2 + w^2), would settle at sqrt(u'^2 + w^2)/u' > 1: at a spool speed below w the
    friction grew without bound, and on a slow pressure ramp the valve stayed shut far above its setting.)
    Linearised with the spool at rest, Dahl's law sticks, as the spool does: z' = u'/u_z there, the friction
    a spring of p_fric/u_z per unit stroke (its pre-sliding), not a damper. It is the machine's kind of
    behaviour (the stick's stiffness is u_z's), so the block declares no regularised signal (Block.regularised:
    a smoothed jump whose slope the linear model takes for a damper the machine does not have).
    Pressures are gauge; u, z dimensionless; k_s, p_set, p_fric in Pa (force over the spool area).

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet: the pressure that opens the valve"), hydraulic("b", "outlet"))
    params = (
        Param("p_set", "Pa", None, 0.0, 1e9, "crack pressure: spring preload over the spool area"),
        Param("k_s", "Pa", None, 1.0, 1e10, "spring stiffness per unit stroke, over the spool area"),
        Param("A_max", "m^2", None, 0.0, 1.0, "fully open metering area"),
        Param("c_ff", "1", 0.0, -1.0, 1.0, "steady flow-force ratio: p_F = c_ff*s*dp (> 0 closes)"),
        Param("p_fric", "Pa", 0.0, 0.0, 1e9, "Coulomb friction of the spool over the spool area (Dahl model)"),
        Param("u_z", "1", 1e-3, 1e-9, 1.0, "pre-sliding stroke of the Dahl friction (regularisation width)"),
        Param("wn", "rad/s", 2.0 * math.pi * 50.0, 1e-3, 1e6, "natural angular frequency of the spool"),
        Param("zeta", "1", 1.0, 0.0, 10.0, "damping ratio of the spool"),
        Param("u_w", "1", 0.01, 0.0, 0.25, "width of the rounded corners of the stroke limits (regularisation)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient"),
        Param("dp_t", "Pa", 1e4, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]
    states = (
        State("u", "1", 0.0, 1.0, "spool stroke, 0 closed ... 1 fully open"),
        State("du", "1/s", 0.0, 10.0, "spool speed"),
        State("z", "1", 0.0, 1.0, "Dahl friction state: friction pressure = p_fric*z"),
    )

    @staticmethod
    def derivatives(a, b, u, du, z, p_set, k_s, A_max, c_ff, p_fric, u_z, wn, zeta, u_w, Cd, dp_t, rho):
        dp = a - b
        s = rounded_unit(u, u_w)
        q = turbulent_flow(dp, A_max * s, Cd, rho, dp_t)
        p_F = c_ff * s * dp
        u_eq = rounded_unit((dp - p_set - p_F - p_fric * z) / k_s, u_w)
        der_z = (du - z * abs(du)) / u_z
        return -q, q, du, lowpass2_acceleration(u_eq, u, du, wn, zeta), der_z
