"""The flow meter of the MCV test rig (thesis chapter 3, eq. 3.4): a flow sensor whose pressure loss is an
offset plus a laminar drop."""

from blocks.block import Block, Param, hydraulic, signal_out
from blocks.library.hydraulic.flow import smooth_max0
from blocks.registry import register


@register("flow_meter")
class FlowMeter(Block):
    """Flow meter with an offset pressure loss (test rig, thesis eqs. 3.3, 3.4, 3.15): outputs the flow through it.

    Pressure loss, as the thesis fits it to its rig (eq. 3.4, repeated as eq. 3.15):
        dp = p_a - p_b = dp0 + R*q          for q > 0        (dp0 = 1 bar, R = 3000e5 Pa*s/m^3, preset "eq_3_4")
    written as the flow for a given drop, symmetric in the flow direction, with the kinks rounded:
        q = ( smax(dp - dp0, dp_w) - smax(-dp - dp0, dp_w) ) / R    [m^3/s]
        smax(x, w) = max(x, 0), rounded over |x| < w/2: (x + w/2)^2/(2w) there (C1)
    so q = (dp - dp0)/R for dp >= dp0 + dp_w/2 (exactly eq. 3.4), q = (dp + dp0)/R for dp <= -dp0 - dp_w/2,
    and q = 0 in the dead band |dp| <= dp0 - dp_w/2: the 1 bar at (nearly) zero flow is an offset, not a
    resistance, and the meter passes no flow until it is overcome. dp0 = 0 gives the plain laminar sensor
    q = dp/R exactly (the two rounded bands cancel).

    The printed slope of eq. 3.4 is "30000*1e5 Pa*s/m^3"; read here as 3000*1e5 (a digit too many): with
    the VF250 check valve of table 2.8 in series, 3000e5 reproduces the thesis's own simulated p1 - p3 of
    table 3.4 within about 0.1 bar at every one of its 21 points, whereas 30000e5 would add 5...40 bar. The
    data sheet's law (eq. 3.3, dp0 = 2 bar, "24000e5") the thesis found not to match its measurements.

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b, and outputs q.
    """

    ports = (
        hydraulic("a", "inlet (positive flow leaves this net)"),
        hydraulic("b", "outlet"),
        signal_out("q", "measured flow from a to b", "m^3/s"),
    )
    params = (
        Param("R", "Pa*s/m^3", None, 1e-3, 1e20, "laminar part of the loss: drop per unit flow beyond the offset",
              positive=True),
        Param("dp0", "Pa", 0.0, 0.0, 1e7, "pressure-loss offset at (nearly) zero flow"),
        Param("dp_w", "Pa", 1e3, 0.0, 1e6, "width over which the kinks at +-dp0 are rounded (regularisation)"),
    )
    presets = {
        # eq. 3.4 with the slope read as 3000e5 Pa*s/m^3 (see the docstring)
        "eq_3_4": {"R": "3000e5 Pa*s/m^3", "dp0": "1 bar"},
    }

    @classmethod
    def check_values(cls, values):
        if values["dp0"] > 0.0 and values["dp_w"] > values["dp0"]:
            return f"dp_w = {values['dp_w']:g} Pa must not exceed the offset dp0 = {values['dp0']:g} Pa"
        return None

    @staticmethod
    def outputs(a, b, R, dp0, dp_w):
        dp = a - b
        return ((smooth_max0(dp - dp0, dp_w) - smooth_max0(-dp - dp0, dp_w)) / R,)

    @staticmethod
    def derivatives(a, b, R, dp0, dp_w):
        dp = a - b
        q = (smooth_max0(dp - dp0, dp_w) - smooth_max0(-dp - dp0, dp_w)) / R
        return -q, q
