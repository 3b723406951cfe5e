"""Hydraulic blocks. Each module registers one block."""

from blocks.library.hydraulic import (  # noqa: F401
    accumulator,
    check_valve,
    cylinder,
    flow_control_valve,
    flow_sensor,
    flow_source,
    flow_source_signal,
    hydraulic_motor,
    laminar_orifice,
    line_loss,
    orifice,
    pressure_reducing_valve,
    pressure_sensor,
    pressure_source,
    relief_valve,
    spool_relief_valve,
    tank,
    valve_4_3,
    variable_orifice,
    volume,
)
