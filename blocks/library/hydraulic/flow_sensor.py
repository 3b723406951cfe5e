"""Flow sensor modelled as a laminar resistance."""

from blocks.block import Block, Param, hydraulic, signal_out
from blocks.registry import register


@register("flow_sensor")
class FlowSensor(Block):
    """Flow sensor with a laminar internal resistance R: outputs the flow that passes through it.

    q = (p_a - p_b) / R   [m^3/s], R [Pa*s/m^3]

    An ideal (zero-resistance) sensor would need an algebraic constraint p_a = p_b, which nets do not have;
    a real flow meter has a small pressure drop, modelled here as the laminar resistance R.
    q > 0 flows from a to b: the block delivers -q to net a and +q to net b, and outputs q.
    """

    ports = (
        hydraulic("a", "inlet (positive flow leaves this net)"),
        hydraulic("b", "outlet"),
        signal_out("q", "measured flow from a to b", "m^3/s"),
    )
    params = (Param("R", "Pa*s/m^3", None, 1e-3, 1e20, "laminar resistance of the sensor"),)

    @staticmethod
    def outputs(a, b, R):
        return ((a - b) / R,)

    @staticmethod
    def derivatives(a, b, R):
        q = (a - b) / R
        return -q, q
