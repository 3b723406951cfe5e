"""The library of candidate effects: one module per candidate, registered by explicit import.

Each candidate is a parametric patch that a netlist can take at specific places, its parameter's zero
meaning "the declared model" (see :mod:`blocks.calibrate.candidates.base`):

- line_loss_turbulent, line_loss_laminar: a line_loss block in series at a port (dp = k*q|q|, dp = R*q)
- leakage: a laminar_orifice across two nets joined by a component (q = G*dp)
- coulomb_friction, viscous_friction, stribeck_friction: friction blocks on a moving body
- extra_volume: a volume block on a net (compliance)
- transport_delay: a pade_delay block between a signal's driver and its inputs
- flow_force: a block's continuous steady-flow-force gain (spool_relief_valve.c_ff)
- spool_friction: a block's spool friction with hysteresis (spool_relief_valve.p_fric, Dahl model)
- sensor_offset, sensor_gain: y' = (1 + g)*y + o on a compared channel (post-processing, not the netlist)
"""

from blocks.calibrate.candidates.base import Candidate, Context, Place, registered  # noqa: F401
from blocks.calibrate.candidates import (  # noqa: F401
    coulomb_friction,
    extra_volume,
    flow_force,
    leakage,
    line_loss_laminar,
    line_loss_turbulent,
    sensor_gain,
    sensor_offset,
    spool_friction,
    stribeck_friction,
    transport_delay,
    viscous_friction,
)
