"""Ideal gear (rigid speed ratio between two shafts)."""

from blocks.block import Block, Param, rotational
from blocks.registry import register


@register("gear")
class Gear(Block):
    """Ideal lossless gear: a rigid link between shaft a (input) and shaft b (output), reduction n.

    w_b = w_a / n   (ratio r = 1/n)

    The compiler merges both shaft nets into one rigid body with the coordinate w = w_a: speeds
    w_k = r_k*w, equivalent inertia sum(r_k^2*J_k), generalised torque sum(r_k*tau_k); so a torque tau_b
    on the output appears as tau_b/n on the input and an inertia J_b as J_b/n^2. n > 1 is a reduction;
    both shafts turn the same way. The block itself applies no torque and stores nothing.
    """

    ports = (rotational("a", "input shaft"), rotational("b", "output shaft (w_b = w_a/n)"))
    params = (Param("n", "1", None, 1e-6, 1e6, "reduction ratio w_a/w_b"),)
    rigid_link = ("a", "b")

    @staticmethod
    def ratio(n):
        return 1.0 / n
