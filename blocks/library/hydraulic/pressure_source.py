"""Ideal pressure source."""

from blocks.block import Block, Param, hydraulic
from blocks.registry import register


@register("pressure_source")
class PressureSource(Block):
    """Ideal constant pressure source: the net at ``port`` is held at p whatever flow it takes.

    p_port = p   (the net then has no pressure state of its own)

    The flow it delivers to the net, logged as ``<name>.port.flow`` [m^3/s], is what holds the pressure:
    q = -sum(q_k), the flows the other blocks deliver to the net (positive: the source supplies the net; a
    tank taking the return flow logs it negative). It is computed where it is logged, not by the solver.
    """

    ports = (hydraulic("port", "the net held at pressure p"),)
    params = (Param("p", "Pa", 0.0, -1e5, 1e9, "source pressure (gauge)"),)
    prescribes = ("port",)

    @staticmethod
    def outputs(p):
        return (p,)
