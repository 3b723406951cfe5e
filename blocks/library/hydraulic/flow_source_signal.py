"""Ideal flow source driven by a signal."""

from blocks.block import Block, hydraulic, signal_in
from blocks.registry import register


@register("flow_source_signal")
class FlowSourceSignal(Block):
    """Ideal flow source driven by a signal: moves the volume flow q(t) from net a to net b.

    q_a = -q,  q_b = +q   [m^3/s], q read from the signal input ``q``

    Sign convention: q > 0 is taken out of net a and delivered into net b (connect a to a tank for a pump
    drawing from the reservoir); q < 0 reverses the flow.
    """

    ports = (
        hydraulic("a", "suction side: q is taken from this net"),
        hydraulic("b", "delivery side: q enters this net"),
        signal_in("q", "volume flow from a to b", "m^3/s"),
    )

    @staticmethod
    def derivatives(q):
        return -q, q
