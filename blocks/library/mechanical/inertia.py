"""Rotational inertia."""

from blocks.block import Block, Param, rotational
from blocks.registry import register


@register("inertia")
class Inertia(Block):
    """Rotational inertia: adds J to the inertia of its shaft net, applies no torque.

    tau_port = 0,  J_port = J   [kg*m^2]

    The net then obeys J_net * dw/dt = sum(tau), J_net the sum of the inertias stored on it.
    """

    ports = (rotational("port", "the shaft net carrying this inertia", stores=True),)
    params = (Param("J", "kg*m^2", None, 0.0, 1e9, "moment of inertia"),)

    @staticmethod
    def derivatives(J):
        return 0.0, J
