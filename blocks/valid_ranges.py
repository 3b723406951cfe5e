"""Signals that left the range their block's equations hold in: observed at the output samples, warned of.

A block declares which of its signals it can judge (``Block.checked``: a signal port, a port's flow) and,
from its parameter values, their valid ranges (``Block.valid_ranges``: a lookup table's breakpoints, the
range a model was fitted on, a geometry's angle range). The compiled ``observe`` computes each checked
signal after the logged outputs, at every output sample; after a run each is compared with its range, and
a signal that left it gives one warning line: the block, the signal, when it first left the range, the
value furthest outside it and what the block does there ("the table's end value is held"). A value between
two output samples is not seen: the check is as fine as ``dt_out``.

The signals a block declares ``regularised`` (:mod:`blocks.regularisation`), and those their laws read,
are observed after the checked ones, the same way, in a circuit built to be linearised only (``Circuit(...,
regularised=True)``): they have no valid range, and are read at its operating point alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from blocks.block import Block
from blocks.library.signal.linear import UNLIMITED
from blocks.units import GENERIC

# SI units shown in the unit an engineer reads them in
_SHOWN = {"Pa": ("bar", 1e5), "m^3/s": ("l/min", 1e-3 / 60.0), "rad": ("deg", np.pi / 180.0)}


@dataclass(frozen=True)
class Monitor:
    """A checked (or regularised) signal of block ``comp``: ``ref`` relative to the block, its expression in
    the generated ``observe`` and its SI unit ("" or "SI" when no port on its net declares one)."""

    comp: str
    ref: str
    expr: str
    unit: str

    @property
    def name(self) -> str:
        return f"{self.comp}.{self.ref}"


def monitors(circuit, regularised: bool = False) -> list[Monitor]:
    """Every checked signal of every block of the circuit, then (``regularised``: a circuit built to be
    linearised) every regularised one and what their laws read (``regularised_reads``) that is not observed
    already, resolved as an output would be."""
    found = []
    refs = [(comp, ref) for comp, spec in circuit.flat.components.items() for ref in spec.cls.checked]
    for comp, spec in circuit.flat.components.items() if regularised else ():
        refs += [(comp, ref) for ref in dict.fromkeys(spec.cls.regularised + spec.cls.regularised_reads)
                 if ref not in spec.cls.checked]
    for comp, ref in refs:
        name = f"{comp}.{ref}"
        expr, unit = circuit.generator.resolve_output(name)
        if unit in ("", GENERIC):
            unit = circuit.agreed_unit(name) or unit
        found.append(Monitor(comp, ref, expr, unit))
    return found


def range_warnings(circuit, t: np.ndarray, observed: np.ndarray, values: dict) -> list[str]:
    """A line for each checked signal that left its block's valid range at an output sample; ``observed``
    holds the checked signals' columns (in :func:`monitors`' order), ``values`` the run's parameters."""
    found = []
    for column, monitor in zip(observed.T, circuit.monitors):
        cls = circuit.flat.components[monitor.comp].cls
        ranges = {r.signal: r for r in cls.valid_ranges(circuit.block_values(monitor.comp, values))}
        valid = ranges.get(monitor.ref)
        if valid is None:
            continue
        with np.errstate(invalid="ignore"):
            beyond = np.fmax(valid.lower - column, column - valid.upper)
        outside = np.flatnonzero(beyond > 0.0)
        if outside.size == 0:
            continue
        worst = outside[np.argmax(beyond[outside])]
        found.append(f"{monitor.comp}: {monitor.ref} left its valid range ({_range_text(valid, monitor.unit)}) "
                     f"at t = {t[outside[0]]:.4g} s, reaching {_shown(column[worst], monitor.unit)} at "
                     f"t = {t[worst]:.4g} s; outside it {valid.outside}")
    return found


def parameter_warnings(circuit, values: dict) -> list[str]:
    """A line for each block whose parameters (a run's ``values``) lie outside what its equations were made
    for (:meth:`Block.parameter_warnings`)."""
    return [f"{comp}: {line}" for comp, spec in circuit.flat.components.items()
            if spec.cls.parameter_warnings.__func__ is not Block.parameter_warnings.__func__
            for line in spec.cls.parameter_warnings(circuit.block_values(comp, values))]


def _range_text(valid, unit: str) -> str:
    """'[a, b] unit', or 'at most b unit' / 'at least a unit' where the other side is unlimited."""
    if valid.lower <= -UNLIMITED:
        return f"at most {_shown(valid.upper, unit)}"
    if valid.upper >= UNLIMITED:
        return f"at least {_shown(valid.lower, unit)}"
    return f"{_shown(valid.lower, unit, False)} to {_shown(valid.upper, unit)}"


def _shown(value: float, unit: str, with_unit: bool = True) -> str:
    """A value for a message, in bar, l/min or deg where SI would be unreadable, else in its SI unit."""
    name, factor = _SHOWN.get(unit, (unit, 1.0))
    text = f"{value / factor:.6g}"
    return f"{text} {name}" if with_unit and name not in ("", GENERIC, "1") else text
