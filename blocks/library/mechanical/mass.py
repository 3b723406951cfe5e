"""Translational mass, with its weight along the direction of motion."""

from blocks.block import Block, Param, translational
from blocks.registry import register


@register("mass")
class Mass(Block):
    """Translational mass: adds m to the mass of its net and applies its weight along the motion.

    f_port = m*g_x,  m_port = m   [N], [kg]

    g_x is the acceleration of gravity along the net's positive direction: 0 for a horizontal motion (the
    default), -9.81 m/s^2 for a vertical one whose v > 0 lifts the mass (a cylinder extending upwards),
    -9.81*sin(angle) on a slope. The net then obeys m_net * dv/dt = sum(f), m_net the sum of the masses
    stored on it.
    """

    ports = (translational("port", "the rigid body net carrying this mass", stores=True),)
    params = (
        Param("m", "kg", None, 0.0, 1e9, "mass"),
        Param("g_x", "m/s^2", 0.0, -100.0, 100.0, "gravity along the positive direction (-9.81 m/s^2: v > 0 lifts)"),
    )

    @staticmethod
    def derivatives(m, g_x):
        return m * g_x, m
