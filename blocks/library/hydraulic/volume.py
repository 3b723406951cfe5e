"""Hydraulic volume (fluid capacitance)."""

from blocks.block import Block, Param, hydraulic
from blocks.registry import register


@register("volume")
class Volume(Block):
    """Hydraulic volume: adds the fixed fluid volume V to the capacity of its net, passes no flow.

    q_port = 0,  V_port = V   [m^3]

    The net's pressure then obeys dp/dt = beta/V_net * sum(q), with V_net the sum of the volumes stored on
    it (lines, chambers) and beta the fluid bulk modulus (an accumulator's gas is a block of its own,
    ``accumulator``, with its oil volume as a state).
    """

    ports = (hydraulic("port", "the net whose capacity this volume adds to", stores=True),)
    params = (Param("V", "m^3", None, 1e-12, 10.0, "fluid volume"),)

    @staticmethod
    def derivatives(V):
        return 0.0, V
