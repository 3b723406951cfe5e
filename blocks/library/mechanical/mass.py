"""Translational mass."""

from blocks.block import Block, Param, translational
from blocks.registry import register


@register("mass")
class Mass(Block):
    """Translational mass: adds m to the mass of its net, applies no force.

    f_port = 0,  m_port = m   [kg]

    The net then obeys m_net * dv/dt = sum(f), m_net the sum of the masses stored on it.
    """

    ports = (translational("port", "the rigid body net carrying this mass", stores=True),)
    params = (Param("m", "kg", None, 0.0, 1e9, "mass"),)

    @staticmethod
    def derivatives(m):
        return 0.0, m
