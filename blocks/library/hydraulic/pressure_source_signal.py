"""Ideal pressure source driven by a signal."""

from blocks.block import Block, hydraulic, signal_in
from blocks.registry import register


@register("pressure_source_signal")
class PressureSourceSignal(Block):
    """Ideal pressure source driven by a signal: the net at ``port`` is held at p(t) whatever flow it takes.

    p_port = p   [Pa, gauge], p read from the signal input ``p`` (the net has no pressure state of its own)

    A pressure ramp or a measured pressure trace imposed on a circuit (a test rig's supply, a load-sense
    line). The signal passes straight to the net: a block whose outputs read that net's pressure and feed
    back into p closes an algebraic loop, which the netlist check reports. The signal is taken as given,
    unbounded: below the fluid's vapour pressure (at most, absolute vacuum: -1.013 bar gauge) it holds a
    pressure no oil can have, and the run cannot warn of it (the net has no state to check), unlike the
    constant `pressure_source`, whose p is checked against -1 bar.

    The flow it delivers to the net, logged as ``<name>.port.flow`` [m^3/s], is what holds the pressure:
    q = -sum(q_k), the flows the other blocks deliver to the net (positive: the source supplies the net; a
    tank taking the return flow logs it negative). It is computed where it is logged, not by the solver.
    """

    ports = (hydraulic("port", "the net held at pressure p"), signal_in("p", "pressure to hold (gauge)", "Pa"))
    prescribes = ("port",)

    @staticmethod
    def outputs(p):
        return (p,)
