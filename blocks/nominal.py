"""The nominal magnitude of a quantity by its dimension: the size it typically has in these machines (SI).

The solver's absolute tolerance of a state is ``atol`` times its nominal magnitude
(:mod:`blocks.solve.run`), so that one ``atol`` suits a pressure of 200 bar and a flow of 1 l/min alike.
The table is the one the engine's own states use: a net's pressure 1 bar, a shaft's speed 1 rad/s, a
body's velocity 0.1 m/s (:data:`blocks.compiler.structure.PHYSICAL_STATE_NOMINAL` is read from it), a
pipe's flow 1e-4 m^3/s (6 l/min), a cylinder's stroke 0.1 m, an accumulator's oil volume 1 l.
A dimension not listed (a plain number, an angle, a mass, anything else) has the nominal 1.
"""

from __future__ import annotations

from blocks.units import Unit, parse_unit

NOMINAL_MAGNITUDE: tuple[tuple[str, float], ...] = (
    ("Pa", 1e5),  # pressure: 1 bar
    ("m^3/s", 1e-4),  # volume flow: 6 l/min
    ("m", 0.1),  # length, position
    ("m/s", 0.1),  # velocity
    ("rad/s", 1.0),  # angular velocity
    ("N", 1e3),  # force
    ("N*m", 10.0),  # torque
    ("m^3", 1e-3),  # volume: 1 l
)
"""(SI unit of the dimension, nominal magnitude in that unit)."""

OTHER = 1.0
"""The nominal magnitude of every other dimension (dimensionless, angle, unknown)."""


def nominal_magnitude(dims: Unit) -> float:
    """The nominal magnitude [SI] of a quantity of dimension ``dims`` (its unit's factor does not matter)."""
    for unit, nominal in NOMINAL_MAGNITUDE:
        if parse_unit(unit).same_dimension(dims):
            return nominal
    return OTHER
