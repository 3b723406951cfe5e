"""Simulation time as a signal."""

from blocks.block import Block, signal_out
from blocks.registry import register


@register("clock")
class Clock(Block):
    """Simulation time as a signal: y = t.

    Units: y in s.
    """

    ports = (signal_out("y", "simulation time", "s"),)

    @staticmethod
    def outputs(t):
        return (t,)
