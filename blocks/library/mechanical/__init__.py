"""Mechanical blocks (rotational and translational). Each module registers one block."""

from blocks.library.mechanical import (  # noqa: F401
    angle_sensor,
    force_source,
    gear,
    induction_motor,
    inertia,
    mass,
    position_sensor,
    rack_pinion,
    rot_damper,
    rot_friction,
    speed_sensor,
    speed_source,
    stribeck_friction,
    torque_source,
    trans_damper,
    trans_friction,
    trans_stribeck_friction,
    velocity_sensor,
    velocity_source,
)
