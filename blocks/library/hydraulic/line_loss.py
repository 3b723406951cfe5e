"""Series line loss (pipe, hose, fitting, flow meter) as a pressure-drop law solved for the flow."""

import math

from blocks.block import Block, Param, hydraulic
from blocks.registry import register


@register("line_loss")
class LineLoss(Block):
    """Series line loss: dp = (R_0 + R)*q + k*q*|q| from a to b, solved for the flow q.

    dp  = p_a - p_b   [Pa],  R_s = R_0 + R   [Pa*s/m^3]
    q   = 2*dp / (R_s + sqrt(R_s^2 + 4*k*|dp|))   [m^3/s]

    q is the root of k*q*|q| + R_s*q = dp with the sign of dp (the stable form of the quadratic root:
    for dp > 0, q = (-R_s + sqrt(R_s^2 + 4*k*dp))/(2*k); for k = 0, q = dp/R_s). k [Pa*s^2/m^6] is the
    turbulent (pipe-friction, fitting) coefficient, R the laminar one. The floor R_0 > 0 is a declared
    regularisation: it keeps the flow finite when k = R = 0, so that the element with k = R = 0 is the
    "no loss" model up to a pressure drop R_0*q (1e4 Pa*s/m^3 by default: 0.17 mbar at 100 l/min), which
    lets calibration insert it with a zero parameter. q is C1 in dp (dq/ddp = 1/R_s at dp = 0).

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet (positive flow leaves this net)"), hydraulic("b", "outlet"))
    params = (
        Param("k", "Pa*s^2/m^6", 0.0, 0.0, 1e20, "turbulent loss coefficient: dp = k*q*|q|"),
        Param("R", "Pa*s/m^3", 0.0, 0.0, 1e16, "laminar loss coefficient: dp = R*q"),
        Param("R_0", "Pa*s/m^3", 1e4, 1e-6, 1e16, "floor of the laminar resistance (regularisation): dp = R_0*q when k = R = 0",
              positive=True),
    )

    @staticmethod
    def derivatives(a, b, k, R, R_0):
        dp = a - b
        rs = R_0 + R
        q = 2.0 * dp / (rs + math.sqrt(rs * rs + 4.0 * k * abs(dp)))
        return -q, q
