"""Ideal constant flow source."""

from blocks.block import Block, Param, hydraulic
from blocks.registry import register


@register("flow_source")
class FlowSource(Block):
    """Ideal constant flow source: moves the volume flow q from net a to net b whatever the pressures.

    q_a = -q,  q_b = +q   [m^3/s]

    Sign convention: q > 0 is taken out of net a and delivered into net b (connect a to a tank for a pump
    drawing from the reservoir). The source does no work accounting: it is ideal and pressure-independent.
    """

    ports = (hydraulic("a", "suction side: q is taken from this net"), hydraulic("b", "delivery side: q enters this net"))
    params = (Param("q", "m^3/s", None, -10.0, 10.0, "volume flow from a to b"),)

    @staticmethod
    def derivatives(q):
        return -q, q
