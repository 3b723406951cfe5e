"""Signal blocks (causal). Each module registers one block."""

from blocks.library.signal import (  # noqa: F401
    clock,
    constant,
    dead_band,
    gain,
    highpass2,
    integrator,
    lookup_1d,
    lookup_2d,
    lowpass2,
    pid,
    product,
    profile,
    ramp,
    saturation,
    second_order,
    step,
    sum,
    switch,
    transfer_function,
    transfer_function_strict,
)
