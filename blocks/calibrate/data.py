"""Measured data mapped onto an experiment's channels, in SI: steady operating points or a time series (one
run or several).

Steady points (no ``t`` column): one row per operating point, the group label of each row (the grouping
column, or "all"), the measured inputs (imposed through a parameter per point) and outputs. Steady points
may come from several files (``data: [a.csv, b.csv]``, each an experiment of its own): their rows are
joined in order and each row remembers its file (``sources``; held out as a whole by
``leave_one_experiment_out``); every file needs every channel's column, in any unit of its dimension. A time series
(a ``t`` column): strictly increasing times, every channel sampled at them; held-out folds are contiguous
blocks of samples. A time series with a grouping column holds several runs (e.g. the same test at
different loads), each a block of rows with its own increasing times, simulated each with its group's
parameter values (``groups:``); held out one run at a time by ``leave_one_group_out`` (or
``leave_one_experiment_out``). Several time-series files (``data: [run1.csv, run2.csv]``) are one run each,
named by the file name without extension.

Noise: given in the experiment file, or estimated here from the data itself:

- ``repeats`` (steady): the pooled standard deviation of the channel over repeated points,
  sigma^2 = sum_sets sum_k (y_k - mean)^2 / sum_sets (n - 1). A set of repeats is the rows of one group
  and file with the same value in the experiment's ``repeats:`` column (a point number: one operating point
  set up again, its readings noisy, inputs included), or, without that column, with the same imposed input
  readings to 1e-12 (exact set points, as typed in by hand).
- ``diff`` (time series): from the second differences d_k = y_{k+1} - 2 y_k + y_{k-1}, which remove a
  signal that is smooth on the sample scale: var(d) = 6 sigma^2 for white noise, estimated robustly as
  sigma = 1.4826 * median|d - median(d)| / sqrt(6) (steps in the signal are outliers of d, not noise).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from blocks.calibrate.experiment import Experiment, described, unit_problem
from blocks.datafile import DataFileError, Table, header_of, is_number, read_table
from blocks.errors import NetlistError
from blocks.netlist.yaml_source import shown_key
from blocks.units import nearest, parse_unit, quantity_name, si_name, split_quantity


@dataclass
class Dataset:
    kind: str  # "steady" or "time"
    n: int
    t: np.ndarray | None
    labels: list[str]
    measured: dict[str, np.ndarray]
    sigma: dict[str, float]
    table: Table  # the first file's
    noise_notes: dict[str, str]
    sources: list[str] | None = None  # steady points: the data file of each row (None: one file)
    repeat_ids: np.ndarray | None = None  # the repeats: column, when the experiment names one

    @property
    def groups(self) -> dict[str, np.ndarray]:
        found: dict[str, list[int]] = {}
        for k, label in enumerate(self.labels):
            found.setdefault(label, []).append(k)
        return {label: np.array(rows, dtype=int) for label, rows in found.items()}


MIXED = " (the files of one experiment are all time series or all steady points)"
MIN_DIFFERENCES = 5  # second differences that noise: diff estimates a channel's noise from, at least


def load_data(exp: Experiment) -> Dataset:
    data = _load_data(exp)
    if data.kind == "time" and len(data.groups) > 1 and exp.exact_columns:
        column, param = exp.exact_columns[0]
        raise exp.error(("data",), f"data: the netlist reads the column {column} ({param}) from one data file and "
                                   f"imposes it exactly, which would drive all {len(data.groups)} runs with one "
                                   f"run's recording; list it under inputs: as a latent trace (each run gets its "
                                   f"own), or give the runs their own experiment files")
    return data


def _load_data(exp: Experiment) -> Dataset:
    files = exp.data_files or [exp.data]
    parts = [_load_file(exp, f, first=k == 0, several=len(files) > 1) for k, f in enumerate(files)]
    found = {label for p in parts for label in p.labels}
    unused = [str(label) for label in exp.spec.groups if str(label) not in found]
    if unused and exp.spec.group is not None:  # a group_table may list more settings than were run
        raise exp.error(("groups", unused[0]), f"groups.{unused[0]}: no rows of group '{unused[0]}' in column "
                                               f"'{exp.spec.group}' of {', '.join(f.name for f in files)} "
                                               f"(groups there: {', '.join(sorted(found, key=str))})")
    if len(parts) == 1:
        return parts[0]
    kinds = {p.kind for p in parts}
    if len(kinds) > 1:
        first_time = next(f for p, f in zip(parts, files) if p.kind == "time")
        raise exp.error(("data",), f"data: {first_time.name} is a time series, other files are steady points; the "
                                   f"files of one experiment are all of one kind")
    if kinds == {"time"}:
        return _join_runs(exp, parts, files)
    measured = {name: np.concatenate([p.measured[name] for p in parts]) for name in parts[0].measured}
    labels = [label for p in parts for label in p.labels]
    sources = [f.name for p, f in zip(parts, files) for _ in range(p.n)]
    if len(set(sources)) < len(files):  # two files of the same name in different folders
        sources = [str(f) for p, f in zip(parts, files) for _ in range(p.n)]
    sigma, notes = {}, {}
    keys = [f"{source}:{label}" for source, label in zip(sources, labels)]  # repeats only within a file
    ids = np.concatenate([p.repeat_ids for p in parts]) if exp.spec.repeats else None
    for ch in exp.channels:
        if ch.noise_method == "repeats":  # pooled over every file's repeated points
            sigma[ch.name], notes[ch.name] = _from_repeats(exp, measured, keys, ch, ids)
        else:
            sigma[ch.name], notes[ch.name] = parts[0].sigma[ch.name], parts[0].noise_notes[ch.name]
    return Dataset("steady", len(labels), None, labels, measured, sigma, parts[0].table, notes, sources, ids)


def _load_file(exp: Experiment, file, first: bool = True, several: bool = False) -> Dataset:
    """One data file; ``first``: its units are the channels' display units; ``several``: one of several
    files (steady points only; repeated-point noise is estimated over all of them in :func:`load_data`)."""
    group = exp.spec.group
    if group:
        table = read_table(file, group=group)
    else:  # no grouping column: a column without unit is the repeats: column, a plain number's, or an error
        plain = tuple({c.name for c in exp.channels if c.si_unit in ("", "1")} | {exp.spec.repeats} - {None})
        _check_unitless(exp, file, plain)
        table = read_table(file, plain=plain)
    if group is None and table.group is not None:
        raise table.error(UNITLESS, table.group)
    kind = "time" if "t" in table.columns else "steady"
    if several and kind == "time" and group is not None:
        raise exp.error(("group",), f"group: {file.name} is one of several time-series files, each of them a run; "
                                    f"a grouping column inside them is not supported (give the runs of one file, "
                                    f"or one run per file)")
    if kind == "steady" and any(c.role == "input" and c.signal is not None for c in exp.channels):
        ch = next(c for c in exp.channels if c.role == "input" and c.signal is not None)
        raise exp.error(("inputs", ch.name), f"inputs.{ch.name}: steady data (no t column in {file.name}) "
                                             f"impose inputs through 'parameter', not 'signal'" + MIXED * several)
    if kind == "time" and any(c.role == "input" and c.parameter is not None for c in exp.channels):
        ch = next(c for c in exp.channels if c.role == "input" and c.parameter is not None)
        raise exp.error(("inputs", ch.name), f"inputs.{ch.name}: {file.name} is a time series (a t column), "
                                             f"which imposes its inputs through a logged 'signal' with 'latent' "
                                             f"levels, not a 'parameter'" + MIXED * several)
    n = len(next(iter(table.columns.values()))) if table.columns else 0
    measured = {}
    for ch in exp.channels:
        if ch.name not in table.columns:
            raise _missing_column(exp, table, ch.name, (f"{ch.role}s", ch.name))
        values = table.columns[ch.name]
        bad = np.nonzero(~np.isfinite(values))[0]
        if bad.size:
            raise table.error("empty cell in a compared or imposed column", ch.name, int(bad[0]))
        _check_unit(exp, table, ch, file)
        if first:
            ch.unit = table.units[ch.name]
        measured[ch.name] = values
    t = None
    if kind == "time":
        if not parse_unit(table.units["t"]).same_dimension(parse_unit("s")):
            raise table.error(f"unit '{table.units['t']}' is not a time", "t")
        t = table.columns["t"]
    labels = list(table.labels) if table.labels is not None else ["all"] * n
    if kind == "time":
        _check_runs(table, t, labels)
    ids = None
    if exp.spec.repeats is not None:
        if kind != "steady":
            raise exp.error(("repeats",), "repeats: marks repeated steady points; a time series has none")
        ids = _repeat_numbers(exp, table, exp.spec.repeats)
    if exp.groups:
        missing = sorted(set(labels) - set(exp.groups), key=str)
        if missing and group is not None:
            raise exp.error(("groups",), f"groups: no parameter values for group(s) {', '.join(missing)} of "
                                         f"column '{group}' in {file.name}")
    sigma, notes = {}, {}
    for ch in exp.channels:
        if several and (ch.noise_method == "repeats" or (ch.noise_method == "diff" and kind == "time")):
            continue  # estimated over all the files (load_data, _join_runs)
        if ch.noise_method == "given":
            sigma[ch.name] = float(ch.noise)
            notes[ch.name] = "given"
        elif ch.noise_method == "repeats":
            if kind != "steady":
                raise exp.error((f"{ch.role}s", ch.name, "noise"), "noise: repeats needs steady points; use diff")
            sigma[ch.name], notes[ch.name] = _from_repeats(exp, measured, labels, ch, ids)
        else:
            if kind != "time":
                raise exp.error((f"{ch.role}s", ch.name, "noise"), "noise: diff needs a time series; use repeats")
            sigma[ch.name] = _from_differences(exp, ch, measured[ch.name])
            notes[ch.name] = "estimated from second differences"
    return Dataset(kind, n, t, labels, measured, sigma, table, notes, repeat_ids=ids)


def _missing_column(exp: Experiment, table: Table, name: str, path: tuple) -> NetlistError:
    """A column ``name`` that the experiment asks for at ``path`` (its key: ``outputs.p4``, ``repeats``) and
    the data file lacks: said at that key, where the mistake usually is (a misspelt or renamed column), with
    the data file, the columns nearest ``name`` and every column it has."""
    columns = list(table.positions) or list(table.columns)
    near = nearest(name, columns)
    hint = f"did you mean {', '.join(near)}? " if near else ""
    where = ".".join(shown_key(p) for p in path)
    return exp.error(path, f"{where}: no column '{name}' in {table.file} ({hint}its columns: {', '.join(columns)})")


def _repeat_numbers(exp: Experiment, table: Table, name: str) -> np.ndarray:
    """The column ``name`` that numbers repeated points (the experiment's ``repeats:``), a number in every row.
    Beside a grouping column a column with a text cell is read as labels (:func:`blocks.datafile.read_table`):
    its first text cell is the error, not a column said to be missing."""
    if name in table.text:
        k, cell = next((k, c) for k, c in enumerate(table.text[name]) if not is_number(c))
        raise table.error(f"'{cell}' is not a number: the experiment's repeats: column numbers the repeated points "
                          f"(rows of a group with the same number are one operating point set up again)", name, k)
    if name not in table.columns:
        raise _missing_column(exp, table, name, ("repeats",))
    ids = table.columns[name]
    bad = np.nonzero(~np.isfinite(ids))[0]
    if bad.size:
        raise table.error("empty cell in the column that marks repeated points", name, int(bad[0]))
    return ids


UNITLESS = ("has no unit; name it as the experiment's 'group:' (the grouping column) or 'repeats:' (the column "
            "that numbers repeated points), or give it a unit")


def _check_unitless(exp: Experiment, file, plain: tuple[str, ...]) -> None:
    """Without a grouping column, the first header cell without a unit that may not go without one, named
    with the unit the experiment expects for it (the column of an imposed input or a compared output, the
    times of a time series), before the table is read (which would take it for a grouping column and blame
    the next one without unit)."""
    line, cells = header_of(file)
    channels = {c.name: c for c in exp.channels}
    for col, (name, unit) in enumerate(cells, start=1):
        if unit is not None or name in plain:
            continue
        ch = channels.get(name)
        if ch is not None:
            message = (f"column '{name}' has no unit: write '{name} [{ch.written or ch.si_unit}]' (it is {ch.place}, "
                       f"{quantity_name(parse_unit(ch.si_unit))})")
        elif name == "t":
            message = "column 't' has no unit: write 't [s]' (the sample times of a time series)"
        else:
            message = f"column '{name}' {UNITLESS}"
        raise DataFileError(str(file), message, line, col)


def _check_unit(exp: Experiment, table: Table, ch, file) -> None:
    """A channel's column in a unit of the channel's dimension (:func:`blocks.calibrate.experiment.unit_problem`:
    the netlist's, for inputs and outputs alike); a column without unit only for a dimensionless channel.
    Where the netlist does not give the dimension (``ch.si_unit`` "", :func:`~blocks.calibrate.experiment.
    channel_unit`) the first file's column gives it, and the given noise and sensor offset are checked against
    that (:func:`_check_given`)."""
    given = table.units[ch.name]
    if ch.si_unit in ("", "SI"):
        ch.si_unit = si_name(parse_unit(given))
        raw = (exp.spec.inputs if ch.role == "input" else exp.spec.outputs)[ch.name].noise
        if ch.noise_method == "given":
            _check_given(exp, table, ch, file, (f"{ch.role}s", ch.name, "noise"), raw)
        offset = exp.spec.corrections.get(ch.name, {}).get("offset")
        if offset is not None:
            _check_given(exp, table, ch, file, ("corrections", ch.name, "offset"), offset)
        return
    problem = unit_problem(given, ch)
    if problem is None:
        return
    if given != "1":
        raise table.error(problem, ch.name)
    if ch.role == "output":
        raise table.error(f"dimensionless (no unit in brackets?), but '{ch.name}' is in {ch.si_unit}: write it as "
                          f"'{ch.name} [<unit>]'", ch.name)
    raise table.error(f"dimensionless (no unit in brackets?), but it is {ch.place}, {described(ch.si_unit)}: write "
                      f"it as '{ch.name} [<unit>]'", ch.name)


def _check_given(exp: Experiment, table: Table, ch, file, where: tuple, raw) -> None:
    """A value the experiment gives in the unit of a channel whose dimension its data column decides (its noise,
    its sensor offset, at ``where``), checked against the column: a unit of another dimension is refused, and
    so is a bare number where the column has a dimension (read in SI, 0.01 as 0.01 Pa where it is in bar)."""
    column = f"in the column '{table.header(ch.name)}' of {Path(file).name}"
    unit = split_quantity(raw)[1] if isinstance(raw, str) else ""
    label = ".".join(where)
    if unit:
        problem = unit_problem(unit, ch, ch.name, column)
        if problem:
            raise exp.error(where, f"{label}: wrong unit: '{raw}' is {problem}")
    elif ch.si_unit != "1":
        raise exp.error(where, f"{label}: {raw} has no unit, but {ch.name} is {column}, {described(ch.si_unit)}: "
                               f"write it with one (e.g. \"{raw} {table.units[ch.name]}\")")


def _join_runs(exp: Experiment, parts: list[Dataset], files: list) -> Dataset:
    """Several time-series files: each one run, named by its file name without extension (its key under
    ``groups:``); noise estimated from differences is pooled over the files."""
    names = [Path(f).stem for f in files]
    if len(set(names)) < len(names):
        names = [str(f) for f in files]
    labels = [name for p, name in zip(parts, names) for _ in range(p.n)]
    unknown = [str(label) for label in exp.spec.groups if str(label) not in names]
    if unknown:
        raise exp.error(("groups", unknown[0]), f"groups.{unknown[0]}: no run of that name; the runs are the data "
                                                f"files, named without extension: {', '.join(names)}")
    measured = {name: np.concatenate([p.measured[name] for p in parts]) for name in parts[0].measured}
    sigma, notes = {}, {}
    for ch in exp.channels:
        if ch.noise_method == "repeats":
            raise exp.error((f"{ch.role}s", ch.name, "noise"), "noise: repeats needs steady points; use diff")
        if ch.noise_method == "diff":
            sigma[ch.name] = _from_differences(exp, ch, *(p.measured[ch.name] for p in parts))
            notes[ch.name] = f"estimated from second differences, pooled over {len(parts)} files"
        else:
            sigma[ch.name], notes[ch.name] = parts[0].sigma[ch.name], parts[0].noise_notes[ch.name]
    return Dataset("time", len(labels), np.concatenate([p.t for p in parts]), labels, measured, sigma,
                   parts[0].table, notes, sources=labels)


def _check_runs(table: Table, t: np.ndarray, labels: list[str]) -> None:
    """A time series's groups are runs: each one block of rows, its times increasing strictly."""
    seen = {labels[0]} if labels else set()
    for k in range(1, len(labels)):
        if labels[k] != labels[k - 1]:
            if labels[k] in seen:
                raise table.error(f"the rows of group '{labels[k]}' are not together: each group of a time series "
                                  f"is one run, a block of rows", table.group, k)
            seen.add(labels[k])
            continue
        if not t[k] > t[k - 1]:
            what = "repeats" if t[k] == t[k - 1] else "goes back from"
            raise table.error(f"time {what} the previous row's (times must increase strictly"
                              + (" within a run)" if table.group else ")"), "t", k)


def _from_repeats(exp: Experiment, measured: dict, labels: list[str], ch, ids) -> tuple[float, str]:
    """The pooled standard deviation of channel ``ch`` over the sets of repeated points (module docstring)."""
    where = (f"{ch.role}s", ch.name, "noise")
    said = f"{ch.role}s.{ch.name}.noise"
    inputs = [c.name for c in exp.inputs]
    if ids is None and ch.role == "input":
        raise exp.error(where, f"{said}: repeats of the imposed input '{ch.name}' need a column that marks the "
                               f"repeated points (repeats: <column>); matched by their own readings they always agree")
    sets: dict[tuple, list[int]] = {}
    for k, label in enumerate(labels):
        key = (label, float(ids[k])) if ids is not None else \
            (label,) + tuple(round(float(measured[i][k]), 12) for i in inputs)
        sets.setdefault(key, []).append(k)
    ss, dof = 0.0, 0
    for rows in sets.values():
        if len(rows) > 1:
            y = measured[ch.name][rows]
            ss += float(np.sum((y - y.mean()) ** 2))
            dof += len(rows) - 1
    if dof == 0:
        how = (f"the same value of '{exp.spec.repeats}'" if ids is not None else
               "the same imposed input readings; with noisy input readings, mark them with a column (repeats: "
               "<column>)")
        raise exp.error(where, f"{said}: no repeated points (same group, same data file and {how}) to estimate "
                               f"the noise of '{ch.name}' from; give it")
    if not ss > 0:
        raise exp.error(where, f"{said}: the {dof + len([r for r in sets.values() if len(r) > 1])} repeated "
                               f"readings of '{ch.name}' agree exactly; give its noise")
    return float(np.sqrt(ss / dof)), f"estimated from repeated points ({dof} degrees of freedom)"


def _from_differences(exp: Experiment, ch, *series: np.ndarray) -> float:
    """The noise of a time series's channel from its second differences, pooled over ``series`` (runs): for
    white noise sigma, y[k+1] - 2 y[k] + y[k-1] has the deviation sqrt(6) sigma; the median absolute deviation
    (times 1.4826) estimates it robustly, the signal's own curvature being small between samples."""
    d = np.concatenate([y[2:] - 2.0 * y[1:-1] + y[:-2] for y in series])
    where = (f"{ch.role}s", ch.name, "noise")
    if d.size < MIN_DIFFERENCES:
        raise exp.error(where, f"noise: diff estimates the noise of '{ch.name}' from its second differences, "
                               f"which needs at least {MIN_DIFFERENCES} of them ({MIN_DIFFERENCES + 2} samples in one "
                               f"run); the data give {d.size}: give the noise")
    sigma = float(1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(6.0))
    if not sigma > 0:
        raise exp.error(where, f"noise: the second differences of '{ch.name}' are the same in over half the samples "
                               f"(a constant or coarsely quantised column), which gives no noise estimate: give the "
                               f"noise")
    return sigma
