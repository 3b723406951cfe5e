"""Tank (reservoir) at constant pressure."""

from blocks.block import Block, Param, hydraulic
from blocks.registry import register


@register("tank")
class Tank(Block):
    """Tank (reservoir): the net at ``port`` is held at the tank pressure p whatever flow it takes.

    p_port = p   [Pa, gauge; 0 = atmospheric]

    An ideal pressure source: it prescribes the net's pressure (the net has no pressure state of its own)
    and absorbs or supplies any flow the rest of the net delivers.
    """

    ports = (hydraulic("port", "the net held at the tank pressure"),)
    params = (Param("p", "Pa", 0.0, -1e5, 1e9, "tank pressure (gauge)"),)
    prescribes = ("port",)

    @staticmethod
    def outputs(p):
        return (p,)
