"""Weighted sum of up to three signals."""

from blocks.block import Block, Param, signal_in, signal_out
from blocks.registry import register


@register("sum")
class Sum(Block):
    """Weighted sum of up to three signals: y = k1*u1 + k2*u2 + k3*u3.

    Sign convention: the signs are the gains, e.g. k2 = -1 forms the error e = u1 - u2. u2 and u3 are
    optional and read 0 when unconnected. Units: y in SI; each k_i dimensionless where u_i is in y's unit,
    else the unit that converts it (a feed-forward Kv in s/m turns a velocity into a valve command). The
    solver's tolerance takes the inputs and y as one quantity: the smallest nominal among them
    (:mod:`blocks.compiler.signal_scale`).
    """

    ports = (
        signal_in("u1", "first input"),
        signal_in("u2", "second input (0 if unconnected)", optional=True),
        signal_in("u3", "third input (0 if unconnected)", optional=True),
        signal_out("y", "weighted sum"),
    )
    same_quantity = (("u1", "u2", "u3", "y"),)
    params = (
        Param("k1", "SI", 1.0, None, None, "gain (sign) of u1"),
        Param("k2", "SI", 1.0, None, None, "gain (sign) of u2"),
        Param("k3", "SI", 1.0, None, None, "gain (sign) of u3"),
    )

    @staticmethod
    def outputs(u1, u2, u3, k1, k2, k3):
        return (k1 * u1 + k2 * u2 + k3 * u3,)
