"""Ideal rack and pinion (rigid link between a shaft and a translating body)."""

from blocks.block import Block, Param, rotational, translational
from blocks.registry import register


@register("rack_pinion")
class RackPinion(Block):
    """Ideal lossless rack and pinion: a rigid link between the pinion shaft a and the rack b.

    v_b = r * w_a   [m/s], r the pinion pitch radius [m] (rack travel per radian)

    The compiler merges the shaft net and the rack net into one rigid body with the coordinate w = w_a:
    a force f on the rack appears as the torque r*f on the shaft and a mass m as the inertia r^2*m.
    Positive w moves the rack in its positive direction. The block applies no force and stores nothing.
    """

    ports = (rotational("a", "pinion shaft"), translational("b", "rack (v_b = r*w_a)"))
    params = (Param("r", "m", None, 1e-9, 1e3, "pinion pitch radius (rack travel per radian)"),)
    rigid_link = ("a", "b")

    @staticmethod
    def ratio(r):
        return r
