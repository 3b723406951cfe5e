"""Tank (reservoir) at constant pressure."""

from blocks.block import Block, Param, hydraulic
from blocks.registry import register


@register("tank")
class Tank(Block):
    """Tank (reservoir): the net at ``port`` is held at the tank pressure p whatever flow it takes.

    p_port = p   [Pa, gauge; 0 = atmospheric]

    An ideal pressure source: it prescribes the net's pressure (the net has no pressure state of its own)
    and absorbs or supplies any flow the rest of the net delivers.

    The flow it delivers to the net, logged as ``<name>.port.flow`` [m^3/s], is what holds the pressure:
    q = -sum(q_k), the flows the other blocks deliver to the net (positive: the source supplies the net; a
    tank taking the return flow logs it negative). It is computed where it is logged, not by the solver.
    """

    ports = (hydraulic("port", "the net held at the tank pressure"),)
    params = (Param("p", "Pa", 0.0, -1e5, 1e9, "tank pressure (gauge)"),)
    prescribes = ("port",)

    @staticmethod
    def outputs(p):
        return (p,)
