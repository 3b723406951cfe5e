"""Data files with units: read a CSV of measured, data-sheet or simulated points into SI arrays.

The format (what ``vphs run -o`` writes, and what measurements and data-sheet readings are written in)::

    # comment lines start with '#', anywhere; blank lines are skipped
    setting,p1 [bar],Q [l/min]
    1,33.4,12.5
    1,39.3,24.6

- The first line that is not a comment is the header: each column is ``name [unit]``. The unit is any unit
  :mod:`blocks.units` reads (``bar``, ``l/min``, ``m^3/s``, ``rad/s``, ``rpm``); ``[1]`` (or ``[-]``) is a
  plain number.
- At most one column may have no unit: the grouping column (``setting``, ``run``). Its cells are labels
  (text), kept as written and never read as numbers, so a forgotten unit cannot pass silently as a number
  in SI; a second column without a unit is an error. An empty label is an error too: it is a cell left
  blank, not a group of its own (a group '' silently split the rows into one more group). A caller may
  name columns that go without a unit as plain numbers (``read_table(path, plain=("point",))``: a column
  that numbers repeated points).
- When the caller names the grouping column (``read_table(path, group="setting")``, as an experiment
  file does), several columns may go without a unit: the named one holds the group labels; any other
  column without a unit whose cells are all numbers is a dimensionless number (unit ``1``, e.g. a pilot
  ratio); one with any text cell is a column of labels, kept as written in ``Table.text`` (e.g. a
  set-screw note) and never compared. A number written with a decimal comma (``"1,5"``) is not text: such a
  column is read as numbers, and the cell is an error.
- Every other cell is a finite number. An empty cell is a missing value (NaN in the table); a cell such as
  ``abc``, ``nan`` or ``inf`` is an error.

Values are converted to SI on reading (``p1 [bar]`` 33.4 -> 3.34e6 Pa); the unit as written stays in
``Table.units`` for reports. Every error is one line naming the file, the line in it (comment lines
counted) and the column (its number and header): ``ref.csv:7:3: column 'p1 [bar]': 'abc' is not a number``.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from blocks.errors import NetlistError
from blocks.netlist.yaml_source import read_bounded
from blocks.units import UnitError, parse_unit

MAX_BYTES = 50_000_000
_HEADER = re.compile(r"^(?P<name>[^\[\]]*?)\s*(?:\[(?P<unit>[^\[\]]*)\])?$")
_DIMENSIONLESS = {"-": "1", "": None}


class DataFileError(NetlistError):
    """A problem in a data file, located by line (1-based, comment lines counted) and column (1-based)."""


@dataclass
class Table:
    """Columns of a data file in SI, with the units they were written in.

    ``columns[name]`` is the SI array (NaN where a cell was empty); ``units[name]`` the unit as written in
    the header; ``group`` names the grouping column (the one column without a unit) or is None, ``labels``
    are its cells row by row and ``groups`` maps each label to its row indices (in order of first appearance).
    ``lines[k]`` is the file line of row k (None for a table that did not come from a file) and
    ``positions[name]`` the 1-based column number, so that later checks can name the place they fail.
    """

    file: str
    columns: dict[str, np.ndarray]
    units: dict[str, str]
    group: str | None = None
    labels: list[str] | None = None
    header_line: int | None = None
    lines: list[int] | None = None
    positions: dict[str, int] = field(default_factory=dict)
    text: dict[str, list[str]] = field(default_factory=dict)
    """Columns of text labels other than the grouping column (only when the caller named the group)."""
    samples: list[int] | None = None
    """For a table not from a file whose rows were taken out (:meth:`rows`): the index each row had, so that
    errors still name the sample as the whole table numbered it."""

    def rows(self, keep: np.ndarray) -> "Table":
        """The table with only the rows ``keep`` (indices, in order): a window of a run (``vphs diff
        --t-from``). Errors about the rows kept still name their file lines, or their samples in the whole run."""
        keep = np.asarray(keep, dtype=int)
        samples = None
        if self.lines is None:
            samples = [self.samples[k] for k in keep] if self.samples is not None else [int(k) for k in keep]
        return Table(file=self.file, columns={n: c[keep] for n, c in self.columns.items()}, units=dict(self.units),
                     group=self.group, labels=[self.labels[k] for k in keep] if self.labels is not None else None,
                     header_line=self.header_line,
                     lines=[self.lines[k] for k in keep] if self.lines is not None else None,
                     positions=dict(self.positions), text={n: [v[k] for k in keep] for n, v in self.text.items()},
                     samples=samples)

    @property
    def groups(self) -> dict[str, np.ndarray]:
        """Row indices of each group label, in order of first appearance ({} without a grouping column)."""
        if self.labels is None:
            return {}
        found: dict[str, list[int]] = {}
        for k, label in enumerate(self.labels):
            found.setdefault(label, []).append(k)
        return {label: np.array(rows, dtype=int) for label, rows in found.items()}

    def in_unit(self, name: str, unit: str | None = None) -> np.ndarray:
        """A column in ``unit`` (the unit it was written in by default)."""
        return self.columns[name] / parse_unit(unit or self.units[name]).factor

    def header(self, name: str) -> str:
        unit = self.units.get(name)
        return f"{name} [{unit}]" if unit else name

    def error(self, message: str, name: str | None = None, row: int | None = None) -> DataFileError:
        """An error at row ``row`` (index into the columns; None: the header) of column ``name``."""
        column = self.positions.get(name) if name is not None else None
        if name is not None:
            message = f"column '{self.header(name)}': {message}"
        if row is None:
            return DataFileError(self.file, message, self.header_line, column if self.header_line else None)
        if self.lines is None:  # not from a file (a simulation result): name the sample instead
            sample = self.samples[row] if self.samples is not None else row
            return DataFileError(self.file, f"sample {sample + 1}: {message}")
        return DataFileError(self.file, message, self.lines[row], column)


def read_table(path: str | Path, group: str | None = None, plain: tuple[str, ...] = ()) -> Table:
    """Read a data file (format in the module docstring) into a :class:`Table` in SI.

    ``group`` names the grouping column (which must exist); other columns without a unit are then read as
    dimensionless numbers or as text labels (module docstring). Without it, the one column without a unit
    is the grouping column and a second is an error; the columns named in ``plain`` may also go without a
    unit, read as plain numbers (a column that numbers repeated points)."""
    file = str(path)
    rows = _rows(path)
    header_line, header = rows[0]
    body = rows[1:]
    if group is not None:
        return _read_named_group(file, header_line, header, body, group)
    names, units, group = _read_header(file, header_line, header, plain)
    width = len(header)
    if not body:
        raise DataFileError(file, "no data rows below the header", header_line)

    factors = {name: parse_unit(unit).factor for name, unit in units.items()}
    columns = {name: np.empty(len(body)) for name in units}
    labels: list[str] = []
    lines = []
    for k, (line_no, cells) in enumerate(body):
        if len(cells) != width:
            raise DataFileError(file, f"{len(cells)} cells, the header has {width}", line_no)
        lines.append(line_no)
        for col, (name, cell) in enumerate(zip(names, cells), start=1):
            if name == group:
                labels.append(cell)
                continue
            columns[name][k] = _number(file, line_no, col, header[col - 1], cell) * factors[name]
    return _labelled(Table(file=file, columns=columns, units=units, group=group, labels=labels if group else None,
                           header_line=header_line, lines=lines,
                           positions={n: i for i, n in enumerate(names, start=1)}))


def header_of(path: str | Path) -> tuple[int, list[tuple[str, str | None]]]:
    """The header of a data file: its line and (name, unit) of each column, the unit None where the cell has
    no brackets (checked as :func:`read_table` checks it; errors located)."""
    line_no, header = _rows(path, header_only=True)[0]
    names: list[str] = []
    out = []
    for col, cell in enumerate(header, start=1):
        name, unit = _header_cell(str(path), line_no, col, cell, names)
        names.append(name)
        out.append((name, unit))
    return line_no, out


def _rows(path: str | Path, header_only: bool = False) -> list[tuple[int, list[str]]]:
    """(line number, cells) of every line that is not blank or a comment (the first: the header)."""
    file = str(path)
    try:
        raw = read_bounded(path, MAX_BYTES)
    except NetlistError as exc:
        raise DataFileError(file, exc.message) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise DataFileError(file, f"not a UTF-8 text file (byte {exc.start})") from None

    rows: list[tuple[int, list[str]]] = []
    for line_no, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            cells = next(csv.reader([line]))
        except csv.Error as exc:
            raise DataFileError(file, f"cannot read the line as CSV: {exc}", line_no) from None
        rows.append((line_no, [c.strip() for c in cells]))
        if header_only:
            break
    if not rows:
        raise DataFileError(file, "no header line (the file is empty or has only comments)")
    return rows


def _read_named_group(file: str, header_line: int, header: list[str], body: list, group: str) -> Table:
    """read_table with the grouping column named by the caller: unitless columns are numbers or labels."""
    names: list[str] = []
    units: dict[str, str | None] = {}
    for col, cell in enumerate(header, start=1):
        name, unit = _header_cell(file, header_line, col, cell, names)
        names.append(name)
        units[name] = unit
    if group not in names:
        raise DataFileError(file, f"no grouping column '{group}' (columns: {', '.join(names)})", header_line)
    if not body:
        raise DataFileError(file, "no data rows below the header", header_line)
    width = len(header)
    cells_of: dict[str, list[str]] = {name: [] for name in names}
    lines = []
    for line_no, cells in body:
        if len(cells) != width:
            raise DataFileError(file, f"{len(cells)} cells, the header has {width}", line_no)
        lines.append(line_no)
        for name, cell in zip(names, cells):
            cells_of[name].append(cell)
    columns: dict[str, np.ndarray] = {}
    out_units: dict[str, str] = {}
    text: dict[str, list[str]] = {}
    for col, name in enumerate(names, start=1):
        if name == group:
            continue
        unit = units[name]
        if unit is None and not all(is_number(c) or _decimal_comma(c) for c in cells_of[name]):
            text[name] = cells_of[name]
            continue
        unit = unit or "1"
        factor = parse_unit(unit).factor
        columns[name] = np.array([_number(file, line_no, col, header[col - 1], cell) * factor
                                  for line_no, cell in zip(lines, cells_of[name])])
        out_units[name] = unit
    return _labelled(Table(file=file, columns=columns, units=out_units, group=group, labels=cells_of[group],
                           header_line=header_line, lines=lines,
                           positions={n: i for i, n in enumerate(names, start=1)}, text=text))


def _labelled(table: Table) -> Table:
    """``table``, refused at its first empty group label: a blank cell of the grouping column is a missing
    label (as an empty numeric cell is a missing value), not a group named '' that would take the row into a
    group of its own (a held-out fold of one point, a group no ``groups:`` entry can name)."""
    blank = next((k for k, label in enumerate(table.labels or []) if label == ""), None)
    if blank is not None:
        raise table.error("empty cell: every row needs its group label", table.group, blank)
    return table


def _decimal_comma(cell: str) -> bool:
    """Whether a cell is a number written with a decimal comma ('1,5'): not read as a number, but not a label
    either (a column of them is refused as numbers, not kept as text where a grouping column allows text)."""
    return "," in cell and is_number(cell.replace(",", ".", 1))


def is_number(cell: str) -> bool:
    """Whether a cell reads as a finite number (an empty cell, a missing value, does)."""
    if cell == "":
        return True
    try:
        return math.isfinite(float(cell))
    except ValueError:
        return False


def _read_header(file: str, line_no: int, header: list[str], plain: tuple[str, ...] = ()) \
        -> tuple[list[str], dict[str, str], str | None]:
    names: list[str] = []
    units: dict[str, str] = {}
    group = None
    for col, cell in enumerate(header, start=1):
        name, unit = _header_cell(file, line_no, col, cell, names)
        names.append(name)
        if unit is None and name in plain:
            unit = "1"
        if unit is None:
            if group is not None:
                raise DataFileError(file, f"column '{name}' has no unit in brackets; only one column (the "
                                          f"grouping column, here '{group}') may go without; write "
                                          f"'{name} [1]' for a plain number", line_no, col)
            group = name
            continue
        units[name] = unit
    return names, units, group


def _header_cell(file: str, line_no: int, col: int, cell: str, seen: list[str]) -> tuple[str, str | None]:
    """(name, unit) of one header cell, the unit checked (None: no brackets); errors located."""
    m = _HEADER.match(cell)
    if not m or not m.group("name"):
        hint = next((f"; the columns look separated by {label}: vphs reads comma-separated files"
                     for sep, label in ((";", "';'"), ("\t", "tabs")) if sep in cell), "")
        raise DataFileError(file, f"column header '{cell}': expected 'name [unit]'{hint}", line_no, col)
    name, unit = m.group("name").strip(), m.group("unit")
    if name in seen:
        raise DataFileError(file, f"column '{name}' appears twice in the header", line_no, col)
    if unit is None:
        return name, None
    unit = _DIMENSIONLESS.get(unit.strip(), unit.strip())
    if unit is None:
        raise DataFileError(file, f"column '{cell}': empty unit; write [1] for a plain number", line_no, col)
    try:
        parse_unit(unit)
    except UnitError as exc:
        raise DataFileError(file, f"column '{cell}': {exc}", line_no, col) from None
    return name, unit


def _number(file: str, line_no: int, col: int, header: str, cell: str) -> float:
    if cell == "":
        return math.nan  # a missing value
    try:
        value = float(cell)
    except ValueError:
        value = None
    if value is None or not math.isfinite(value):
        hint = " (a decimal comma? numbers are read with a '.')" if _decimal_comma(cell) else ""
        raise DataFileError(file, f"column '{header}': '{cell}' is not a number{hint}", line_no, col)
    return value
