"""Bridge-crane tool-point position (thesis section 2.10.1)."""

import math

from blocks.block import Block, Param, signal_in, signal_out
from blocks.registry import register


@register("tool_point")
class ToolPoint(Block):
    """Bridge-crane tool-point position from bridge and trolley travel and the slewing angle (eqs. 2.66-2.67).

    x = r_tp*sin(alpha) + b_pos   [m]                     (2.66)
    y = r_tp - r_tp*cos(alpha) + t_pos   [m]              (2.67)

    The tool point sits at the radius r_tp (2100 mm) from the slewing axis; at alpha = 0 it is at the
    origin (fig. 2.43) when b_pos = t_pos = 0. b_pos and t_pos are the bridge- and trolley-travel
    positions (motor angle x pinion radius / gear ratio), alpha the slewing angle. Pure geometry: no
    states, every input feeds straight through.
    """

    ports = (
        signal_in("b_pos", "bridge-travel position", "m"),
        signal_in("t_pos", "trolley-travel position", "m"),
        signal_in("alpha", "slewing angle", "rad"),
        signal_out("x", "tool point, bridge-travel direction", "m"),
        signal_out("y", "tool point, trolley-travel direction", "m"),
    )
    params = (Param("r_tp", "m", 2.1, 0.0, 100.0, "tool-point radius from the slewing axis"),)

    @staticmethod
    def outputs(b_pos, t_pos, alpha, r_tp):
        return r_tp * math.sin(alpha) + b_pos, r_tp - r_tp * math.cos(alpha) + t_pos
