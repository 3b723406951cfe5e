"""Ideal velocity source driven by a signal."""

from blocks.block import Block, signal_in, translational
from blocks.registry import register


@register("velocity_source")
class VelocitySource(Block):
    """Ideal velocity source: the net at ``port`` moves at the signal velocity v whatever the force.

    v_port = v   [m/s]  (the net then has no velocity state of its own; v = 0 fixes it to the frame)

    The force it delivers, logged as ``<name>.port.force`` [N], is what makes the rigid body follow v:
    f = m*dv/dt - sum(r_k*f_k), m = sum(r_k^2*m_k) the body's mass and f_k the forces the other blocks
    deliver to its nets; f > 0 pushes the net in its positive direction. dv/dt, and what a sample on a
    kink or a jump of v gets, as for ``speed_source``'s torque.
    """

    ports = (translational("port", "the body net driven at velocity v"), signal_in("v", "prescribed velocity", "m/s"))
    prescribes = ("port",)

    @staticmethod
    def outputs(v):
        return (v,)
