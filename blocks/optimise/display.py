"""The unit each parameter of a job is shown in, and its SI values converted into it where they are written.

The rule: a parameter is shown in the unit the job wrote it in -- its bounds under ``parameters:`` (the
unit of min:, else of max:), else its ``sweep:`` values (min:/max:, or the first value of a list written
with a unit). Where the job wrote bare numbers only (SI), it is shown in the unit the netlist writes the
parameter's value in (``D: "30 cm^3/rev"``), else in its declared unit when that is a named one ("Pa",
"m^3/rad"), else in the SI unit of its dimension ("Pa" for a pressure, not "m^-1*kg*s^-2"), else as a plain
number (""). The dimensionless unit "1" (as a block declares a ratio) is a plain number too: "1.5",
never "1.5 1" (nor a column ``R_pilot [1]``).

Inside the job every value stays SI (the methods, the log's ``parameters``, the ``vphs run --set`` lines);
report.md, sweep.csv, sweep.png, the console and best.json's ``shown`` convert with :func:`in_unit` when
they write.
"""

from __future__ import annotations

from blocks.units import UnitError, display_factor, parse_unit, split_quantity


def written_unit(*raws) -> str:
    """The unit of the first of ``raws`` written as "<number> <unit>" ("" if every one is a bare number)."""
    for raw in raws:
        if isinstance(raw, str):
            try:
                unit = split_quantity(raw)[1]
                parse_unit(unit)
            except UnitError:  # not a quantity (an expression, a signal's name)
                continue
            if unit:
                return unit
    return ""


PLAIN = ("", "1")
"""Units that mean a plain number: shown as the number alone."""


def plain(unit: str) -> str:
    """``unit``, or "" for a plain number ("1"): what reports write after a value and in a header."""
    return "" if unit.strip() in PLAIN else unit


def in_unit(value: float, unit: str) -> float:
    """An SI value in the display unit ``unit`` ("" or "1": a plain number, unchanged)."""
    return value / display_factor(unit)


def shown(value: float, unit: str, digits: int = 6) -> str:
    """An SI value as text in the display unit: ``shown(2.5e6, "bar")`` -> "25 bar"."""
    return f"{in_unit(value, unit):.{digits}g} {plain(unit)}".strip()


def as_written(raw) -> str:
    """A job value quoted as the job wrote it, for messages ("250 mm^2", or a bare number as a number)."""
    return f"{raw:g}" if isinstance(raw, (int, float)) and not isinstance(raw, bool) else str(raw)
