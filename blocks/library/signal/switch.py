"""Two-way signal switch."""

from blocks.block import Block, Param, signal_in, signal_out
from blocks.registry import register


@register("switch")
class Switch(Block):
    """Two-way switch: passes u1 while control >= threshold, else u2.

    y = u1 if control >= threshold else u2
    Units: u1, u2 and y in one (SI) unit; control and threshold in another.
    """

    ports = (
        signal_in("u1", "passed while control >= threshold"),
        signal_in("control", "selects the input"),
        signal_in("u2", "passed while control < threshold"),
        signal_out("y", "the selected input"),
    )
    same_quantity = (("u1", "u2", "y"),)
    params = (Param("threshold", "SI", 0.5, None, None, "switching threshold on control (SI)"),)

    @staticmethod
    def outputs(u1, control, u2, threshold):
        return (u1 if control >= threshold else u2,)
