"""Series line loss (pipe, hose, fitting, flow meter): a pressure-drop law with the flow as a state."""

from blocks.block import Block, Param, State, hydraulic
from blocks.registry import register


@register("line_loss")
class LineLoss(Block):
    """Series line loss a -> b: dp = (R_0 + R)*q + k*q*|q| at rest; the flow q is a state with a tiny inertance L.

    dp   = p_a - p_b   [Pa]
    L*dq/dt = dp - (R_0 + R)*q - k*q*|q|                 [q in m^3/s]
    at rest (dq/dt = 0):  dp = (R_0 + R)*q + k*q*|q|

    k [Pa*s^2/m^6] is the turbulent (pipe-friction, fitting) coefficient, R [Pa*s/m^3] the laminar one.
    A series element cannot be algebraic between two pressure nodes (it would have to invert dp(q), whose
    conductance is infinite at k = R = 0), so the flow is a state behind the declared inertance L
    [kg/m^4 = Pa*s^2/m^3] (a regularisation, far below a real line's rho*l/A ~ 1e6...1e7 kg/m^4) and the
    declared floor R_0 (dp = R_0*q when k = R = 0: 1e5 Pa*s/m^3 gives 1.7 mbar at 100 l/min). With a node
    of oil volume V beside it, L and the node's capacity V/beta form a series R-L-C mode, overdamped when
    L <= R_0^2*V/(4*beta): the defaults (R_0 = 1e5, L = 3e-6) keep it overdamped for V >= 1 ml (beta = 8e8
    Pa) with real eigenvalues near -R_0/L and -beta/(R_0*V), which the stiff solver steps over; an
    underdamped choice (larger L) leaves a fast oscillation that costs many steps. So the element with
    k = R = 0 is the lossless connection, up to R_0 and L, which lets calibration insert it with a zero
    parameter; at rest it is exact. The right-hand side is smooth in q (C1 through q = 0), so the solver
    sees no square-root singularity.

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet (positive flow leaves this net)"), hydraulic("b", "outlet"))
    params = (
        Param("k", "Pa*s^2/m^6", 0.0, 0.0, 1e20, "turbulent loss coefficient: dp = k*q*|q|"),
        Param("R", "Pa*s/m^3", 0.0, 0.0, 1e16, "laminar loss coefficient: dp = R*q"),
        Param("R_0", "Pa*s/m^3", 1e5, 0.0, 1e16, "floor of the laminar resistance (regularisation): dp = R_0*q when k = R = 0"),
        Param("L", "kg/m^4", 3e-6, 1e-9, 1e12, "inertance that makes the flow a state (regularisation)", positive=True),
    )
    states = (State("q", "m^3/s", 0.0, 1e-4, "flow from a to b"),)

    @staticmethod
    def derivatives(a, b, q, k, R, R_0, L):
        return -q, q, (a - b - (R_0 + R) * q - k * q * abs(q)) / L
