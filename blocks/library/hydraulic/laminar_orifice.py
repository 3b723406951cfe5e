"""Laminar resistance (leakage path)."""

from blocks.block import Block, Param, hydraulic
from blocks.registry import register


@register("laminar_orifice")
class LaminarOrifice(Block):
    """Laminar orifice or leakage path: flow proportional to the pressure drop.

    q = G * (p_a - p_b)   [m^3/s], G the conductance [m^3/(s*Pa)]

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet (positive flow leaves this net)"), hydraulic("b", "outlet"))
    params = (Param("G", "m^3/(s*Pa)", None, 0.0, 1e-3, "laminar conductance (leakage coefficient)"),)

    @staticmethod
    def derivatives(a, b, G):
        q = G * (a - b)
        return -q, q
