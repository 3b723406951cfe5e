"""A simulated curve against reference points (data sheet or measurement): ``vphs diff``.

For each compared curve y(x), with the simulated curve (x_s, y_s) and the reference points (x_k, y_k),
k = 1..n, all in the REFERENCE's units (converted through SI, never by guessing):

    y_s(x_k)  linear interpolation of the simulated curve at x_k (x_s strictly increasing;
              an x_k outside [x_s,min, x_s,max] is an error, never an extrapolation)
    e_k       = y_s(x_k) - y_k                       (simulated minus reference)
    RMSE      = sqrt( (1/n) * sum e_k^2 )
    mean      = (1/n) * sum e_k                      (the bias; positive: simulation above the reference)
    max |e|   = max_k |e_k|, reported with the x_k where it occurs (the first such point)

Reference points whose y cell is empty (a missing value, as the data-file reader reads it) are left out
of that curve: n counts the points used and the table says how many rows were left out. An empty x cell
is an error (the point has no place). With a grouping column in the reference, each group gets a row of
its own after the row over all points.

x at the ends of the simulated range: a reference x within 1e-9 of the span (relative) outside the range
is taken as the end point, so that "3" and a simulated end written as 2.9999999999 meet; anything further
out is an error.

Names: ``--x`` names the abscissa (default ``t``), ``--y`` (repeatable) the curves; ``sim=ref`` maps a
simulated name to a reference name. Without ``--y``, every reference column with a unit (other than x and
the grouping column) that the simulation also has, matched by name.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from blocks.datafile import DataFileError, Table
from blocks.units import nearest, parse_unit

EDGE_TOLERANCE = 1e-9  # relative to the simulated x span: how far outside the range still counts as the end


@dataclass
class CurveStats:
    sim: str
    ref: str
    group: str  # "all" or a group label
    unit: str  # the reference's unit of y
    n: int
    rmse: float
    mean: float
    max_abs: float
    x_at_max: float

    @property
    def curve(self) -> str:
        return self.sim if self.sim == self.ref else f"{self.sim}={self.ref}"


@dataclass
class CurveData:
    """One compared curve, everything in the reference's units (for tables and plots)."""

    sim: str
    ref: str
    unit: str
    x_sim: np.ndarray  # the whole simulated curve
    y_sim: np.ndarray
    x_ref: np.ndarray  # the reference points used (empty y cells left out)
    y_ref: np.ndarray
    y_at_ref: np.ndarray  # the simulated curve interpolated at x_ref
    labels: list[str] | None  # group label of each point used

    @property
    def error(self) -> np.ndarray:
        return self.y_at_ref - self.y_ref


@dataclass
class Comparison:
    simulated: str
    reference: str
    x_sim: str
    x_ref: str
    x_unit: str
    curves: list[CurveData]
    stats: list[CurveStats]
    skipped: list[str]  # reference columns with a unit that the simulation does not have (default matching)
    left_out: dict[str, int] = field(default_factory=dict)  # compared reference column -> rows with it empty
    window: str = ""  # the time window the comparison was restricted to ("t 0.6 .. 2.5 s"), or ""
    outside: int = 0  # reference points outside the window, left out

    def format(self) -> str:
        """The statistics as an aligned text table (the reference's units)."""
        head = ["curve", "group", "unit", "n", "RMSE", "mean error", "max |error|", f"at {self.x_ref} [{self.x_unit}]"]
        rows = [[s.curve, s.group, s.unit, str(s.n), _g(s.rmse), _g(s.mean), _g(s.max_abs), _g(s.x_at_max)]
                for s in self.stats]
        if not any(s.group != "all" for s in self.stats):
            head.pop(1)
            rows = [r[:1] + r[2:] for r in rows]
        widths = [max(len(r[i]) for r in [head] + rows) for i in range(len(head))]
        lines = ["  ".join(c.ljust(w) if i < 2 else c.rjust(w) for i, (c, w) in enumerate(zip(r, widths))).rstrip()
                 for r in [head] + rows]
        note = f"{self.simulated} vs {self.reference} (error = simulated - reference, in the reference's units)"
        if self.window:
            note += f"\ncompared over {self.window}" + (f"; {self.outside} reference {_points(self.outside)} "
                                                         f"outside it left out" if self.outside else "")
        lines += [f"{n} {'row' if n == 1 else 'rows'} with an empty cell in {ref} left out"
                  for ref, n in self.left_out.items()]
        return "\n".join([note] + lines) + "\n"

    def to_csv_text(self) -> str:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(["curve", "simulated", "reference", "group", "unit", "n", "rmse", "mean_error",
                         "max_abs_error", "x_at_max", "x", "x_unit"])
        for s in self.stats:
            writer.writerow([s.curve, s.sim, s.ref, s.group, s.unit, s.n, f"{s.rmse:.10g}", f"{s.mean:.10g}",
                             f"{s.max_abs:.10g}", f"{s.x_at_max:.10g}", self.x_ref, self.x_unit])
        return buffer.getvalue()

    def plot(self, path: str | Path) -> None:
        """One panel pair per curve: simulated line and reference points, and the error beneath;
        one shared x axis. Written atomically."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from blocks.result import atomic_write_figure

        n = len(self.curves)
        fig, axes = plt.subplots(2 * n, 1, sharex=True, figsize=(9, 1.2 + 3.4 * n), squeeze=False,
                                 gridspec_kw={"height_ratios": [3, 1.3] * n})
        for k, c in enumerate(self.curves):
            top, bottom = axes[2 * k, 0], axes[2 * k + 1, 0]
            top.plot(c.x_sim, c.y_sim, "-", color="C0", lw=1.2, label=f"simulated {c.sim}")
            for m, (label, idx) in enumerate(_point_groups(c.labels, len(c.x_ref))):
                idx = idx[np.argsort(c.x_ref[idx], kind="stable")]  # the error line runs along x
                name = f"reference {c.ref}" + (f" ({label})" if label is not None else "")
                top.plot(c.x_ref[idx], c.y_ref[idx], "o", ms=4, mfc="none", color=f"C{1 + m}", label=name)
                bottom.plot(c.x_ref[idx], c.error[idx], "o-", ms=3, lw=0.8, color=f"C{1 + m}")
            bottom.axhline(0.0, color="0.5", lw=0.8)
            top.set_ylabel(f"{c.ref} [{c.unit}]")
            bottom.set_ylabel(f"error [{c.unit}]")
            for ax in (top, bottom):
                ax.grid(True, alpha=0.3)
            top.legend(loc="best", fontsize="small")
        axes[-1, 0].set_xlabel(f"{self.x_ref} [{self.x_unit}]")
        fig.suptitle(f"{Path(self.simulated).name} vs {Path(self.reference).name}", fontsize="medium")
        fig.tight_layout()
        try:
            atomic_write_figure(fig, Path(path))
        finally:
            plt.close(fig)


def _point_groups(labels, n):
    if labels is None:
        return [(None, np.arange(n))]
    order: dict[str, list[int]] = {}
    for k, label in enumerate(labels):
        order.setdefault(label, []).append(k)
    return [(label, np.array(idx, dtype=int)) for label, idx in order.items()]


def _points(n: int) -> str:
    return "point" if n == 1 else "points"


def _g(value: float) -> str:
    return f"{value:.4g}"


# ---- names ----------------------------------------------------------------------------------------------
def split_pair(text: str) -> tuple[str, str]:
    """``"sim=ref"`` -> ("sim", "ref"); ``"name"`` -> ("name", "name")."""
    sim, sep, ref = text.partition("=")
    sim, ref = sim.strip(), ref.strip()
    if not sep:
        return sim, sim
    return sim, ref


def check_reference_columns(reference: Table, x: str, ys: list[str]) -> None:
    """The reference-side names exist and carry units (checked before a netlist is run)."""
    for text in [x] + list(ys):
        sim, ref = split_pair(text)
        if not sim or not ref:
            raise DataFileError(reference.file, f"'{text}': expected a column name or SIM_NAME=REF_NAME")
        _ref_column(reference, ref)


def _ref_column(reference: Table, name: str) -> str:
    if name == reference.group:
        raise reference.error("is the grouping column (no unit): it cannot be compared", name)
    if name not in reference.columns:
        hint = nearest(name, reference.columns)
        known = ", ".join(reference.header(n) for n in reference.columns)
        raise DataFileError(reference.file, f"no column '{name}' (columns: {known})"
                            + (f"; did you mean {', '.join(hint)}?" if hint else ""), reference.header_line)
    return name


def _sim_column(simulated: Table, name: str) -> str:
    if name not in simulated.columns:
        hint = nearest(name, simulated.columns)
        raise DataFileError(simulated.file, f"no simulated column '{name}' (simulated: "
                            f"{', '.join(simulated.columns)})" + (f"; did you mean {', '.join(hint)}?" if hint else ""),
                            simulated.header_line)
    return name


def _same_dimension(simulated: Table, sim: str, reference: Table, ref: str) -> None:
    a, b = parse_unit(simulated.units[sim]), parse_unit(reference.units[ref])
    if not a.same_dimension(b):
        raise reference.error(f"unit [{reference.units[ref]}] ({b.describe_dims()}) does not match the simulated "
                              f"'{simulated.header(sim)}' ({a.describe_dims()}) in {simulated.file}", ref)


# ---- the comparison -------------------------------------------------------------------------------------
def resolve(simulated: Table, reference: Table, x: str = "t", ys: list[str] | None = None):
    """The (sim, ref) names of x and of each curve, checked to exist with matching dimensions, and the
    reference columns left out by default matching. Needs only the names and units of ``simulated``."""
    x_sim, x_ref = split_pair(x)
    if reference.group is not None and reference.group in simulated.columns:
        unit = simulated.units[reference.group]
        raise reference.error(f"has no unit, so it only labels groups of points, yet the simulation has a signal "
                              f"'{reference.group}': to compare it, write its unit ('{reference.group} [{unit}]')",
                              reference.group)
    check_reference_columns(reference, x, ys or [])
    _sim_column(simulated, x_sim)
    _same_dimension(simulated, x_sim, reference, x_ref)

    skipped: list[str] = []
    if ys:
        pairs = [split_pair(y) for y in ys]
    else:
        candidates = [n for n in reference.columns if n != x_ref]
        pairs = [(n, n) for n in candidates if n in simulated.columns and n != x_sim]
        skipped = [n for n in candidates if n not in simulated.columns]
        if not pairs:
            raise DataFileError(reference.file, f"no reference column matches a simulated one (reference: "
                                f"{', '.join(candidates) or 'none'}; simulated: {', '.join(simulated.columns)}); "
                                f"name them with --y SIM_NAME=REF_NAME", reference.header_line)
    for sim, ref in pairs:
        _sim_column(simulated, sim)
        _same_dimension(simulated, sim, reference, ref)
    return (x_sim, x_ref), pairs, skipped


def compare(simulated: Table, reference: Table, x: str = "t", ys: list[str] | None = None, window: str = "",
            outside: int = 0) -> Comparison:
    """Interpolate the simulated curves onto the reference's x points and measure the errors.

    When both files have the same grouping column (e.g. ``setting``), each reference point is compared
    with the simulated curve of its own group (steady operating points of several experiments).
    ``window`` and ``outside``: the time window the tables were cut to and the reference points it left
    out (:func:`apply_window`), for the report and for errors about the simulated range."""
    (x_sim, x_ref), pairs, skipped = resolve(simulated, reference, x, ys)
    x_unit = reference.units[x_ref]
    xr = reference.columns[x_ref]
    missing = np.flatnonzero(np.isnan(xr))
    if missing.size:
        raise reference.error("empty cell: every reference point needs its x", x_ref, int(missing[0]))
    segments = _segments(simulated, reference, x_sim)
    ref_groups = reference.labels if _grouped(simulated, reference) else [None] * len(xr)
    for k in range(len(xr)):
        xs = simulated.columns[x_sim][segments[ref_groups[k]]]
        span = xs[-1] - xs[0]
        if not (xs[0] - EDGE_TOLERANCE * span <= xr[k] <= xs[-1] + EDGE_TOLERANCE * span):
            f = parse_unit(x_unit).factor
            where = f" (group {ref_groups[k]})" if ref_groups[k] is not None else ""
            within = f", in the window {window}" if window else ""
            raise reference.error(f"{x_ref} = {xr[k] / f:g} {x_unit} is outside the simulated range "
                                  f"{xs[0] / f:g} .. {xs[-1] / f:g} {x_unit}{where} ({simulated.file}{within}); "
                                  f"no extrapolation", x_ref, k)

    curves, stats, left_out = [], [], {}
    fx = parse_unit(x_unit).factor
    for sim, ref in pairs:
        ys_si = simulated.columns[sim]
        bad = np.flatnonzero(np.isnan(ys_si))
        if bad.size:
            raise simulated.error("missing value (empty or NaN) in the simulated curve", sim, int(bad[0]))
        unit = reference.units[ref]
        f = parse_unit(unit).factor
        used = np.flatnonzero(~np.isnan(reference.columns[ref]))
        if used.size == 0:
            raise reference.error("no values to compare (every cell is empty)", ref)
        if used.size < len(xr):
            left_out[ref] = len(xr) - used.size
        at_ref = np.empty(used.size)
        for j, k in enumerate(used):
            rows = segments[ref_groups[k]]
            xs = simulated.columns[x_sim][rows]
            at_ref[j] = np.interp(np.clip(xr[k], xs[0], xs[-1]), xs, ys_si[rows])
        labels = [reference.labels[k] for k in used] if reference.labels is not None else None
        curve = CurveData(sim=sim, ref=ref, unit=unit, x_sim=simulated.columns[x_sim] / fx, y_sim=ys_si / f,
                          x_ref=xr[used] / fx, y_ref=reference.columns[ref][used] / f, y_at_ref=at_ref / f,
                          labels=labels)
        curves.append(curve)
        stats.append(_stats(curve, np.arange(used.size), "all"))
        if labels is not None:
            for label, idx in _point_groups(labels, used.size):
                stats.append(_stats(curve, idx, label))
    return Comparison(simulated=simulated.file, reference=reference.file, x_sim=x_sim, x_ref=x_ref, x_unit=x_unit,
                      curves=curves, stats=stats, skipped=skipped, left_out=left_out, window=window, outside=outside)


def _grouped(simulated: Table, reference: Table) -> bool:
    return simulated.group is not None and simulated.group == reference.group


def _segments(simulated: Table, reference: Table, x_sim: str) -> dict:
    """Simulated row indices (sorted by x) per group label, or all rows under the key None."""
    if not _grouped(simulated, reference):
        _check_increasing(simulated, x_sim)
        return {None: np.arange(len(simulated.columns[x_sim]))}
    segments = {}
    for label, rows in simulated.groups.items():
        rows = np.asarray(rows)
        order = rows[np.argsort(simulated.columns[x_sim][rows], kind="stable")]
        _check_increasing(simulated, x_sim, order)
        segments[label] = order
    for k, label in enumerate(reference.labels):
        if label not in segments:
            raise reference.error(f"group {reference.group} = {label} has no simulated points "
                                  f"(simulated groups: {', '.join(map(str, segments))})", reference.group, k)
    return segments


def _stats(curve: CurveData, idx: np.ndarray, group: str) -> CurveStats:
    e = curve.error[idx]
    k = int(np.argmax(np.abs(e)))
    return CurveStats(sim=curve.sim, ref=curve.ref, group=group, unit=curve.unit, n=int(e.size),
                      rmse=math.sqrt(float(np.mean(e**2))), mean=float(np.mean(e)), max_abs=float(abs(e[k])),
                      x_at_max=float(curve.x_ref[idx][k]))


def _check_increasing(table: Table, name: str, rows: np.ndarray | None = None) -> None:
    """The simulated x (over ``rows``, default all) must be strictly increasing; errors name the file row."""
    rows = np.arange(len(table.columns[name])) if rows is None else rows
    x = table.columns[name][rows]
    bad = np.flatnonzero(np.isnan(x))
    if bad.size:
        raise table.error("missing value (empty or NaN) in the simulated x", name, int(rows[bad[0]]))
    if x.size < 2:
        raise table.error("the simulated curve needs at least two points" + (" per group" if len(rows) < len(
            table.columns[name]) else ""), name, int(rows[0]) if len(rows) else None)
    step = np.diff(x)
    bad = np.flatnonzero(step <= 0)
    if bad.size:
        k = int(bad[0]) + 1
        f = parse_unit(table.units[name]).factor
        what = "repeated" if step[k - 1] == 0 else "decreasing"
        later, earlier = distinct(x[k] / f, x[k - 1] / f)
        when = ""
        if name != "t" and _is_time(table, "t"):  # in the file's unit: the columns are in SI (s)
            unit = table.units["t"]
            when = f", at t = {float(table.columns['t'][rows[k]]) / parse_unit(unit).factor:.10g} {unit}"
        raise table.error(f"x must be strictly increasing in the simulated curve: {later} after {earlier} "
                          f"({what}{when})", name, int(rows[k]))


def _is_time(table: Table, name: str) -> bool:
    """Whether ``table`` has a column ``name`` with the dimension of time (in whatever unit: s, ms, min)."""
    unit = table.units.get(name)
    if name not in table.columns or not unit:
        return False
    try:
        return parse_unit(unit).same_dimension(parse_unit("s"))
    except ValueError:
        return False


def distinct(a: float, b: float) -> tuple[str, str]:
    """Two numbers written with the fewest significant digits (at least 6, ``:g`` style) that tell them
    apart, so that an error about their order never reads "50 after 50" when they differ in the eighth
    digit; equal numbers are written as ``:g`` writes them."""
    a, b = float(a), float(b)
    if a == b:
        return f"{a:g}", f"{b:g}"
    for digits in range(6, 18):
        sa, sb = f"{a:.{digits}g}", f"{b:.{digits}g}"
        if sa != sb:
            return sa, sb
    return repr(a), repr(b)


# ---- a time window ---------------------------------------------------------------------------------------
def _s(seconds: float) -> str:
    """A time in s as reports write it (``:g``, and -0 as 0)."""
    return f"{seconds + 0.0:g}"


def window_problem(t_from: float | None, t_to: float | None, start: float | None = None, end: float | None = None,
                   what: str = "") -> str | None:
    """What is wrong with the window ``t_from .. t_to`` (s; None: that end of the run), or None. It must not
    be empty (the one place this is checked: ``vphs diff`` asks before reading any file) and, given the run's
    ``start`` and ``end`` (``what`` names it: a file, a netlist's simulation), lie within the run (to the
    rounding a CSV's 10 digits leave, :data:`EDGE_TOLERANCE`): a window past the end would compare nothing,
    or fewer points than the user asked, silently."""
    if t_from is not None and t_to is not None and t_from >= t_to:
        return f"--t-from {_s(t_from)} s is not before --t-to {_s(t_to)} s"
    if start is None or end is None:
        return None
    slack = EDGE_TOLERANCE * max(end - start, 0.0)
    run = f"{what} ({_s(start)} .. {_s(end)} s)"
    if t_from is not None and not start - slack <= t_from < end:
        side = "before the start" if t_from < start else "at or after the end"
        return f"--t-from {_s(t_from)} s is {side} of {run}"
    if t_to is not None and not start < t_to <= end + slack:
        side = "after the end" if t_to > end else "at or before the start"
        return f"--t-to {_s(t_to)} s is {side} of {run}"
    return None


def apply_window(simulated: Table, reference: Table, x: str, t_from: float | None, t_to: float | None):
    """The simulated curve over the window ``t_from .. t_to`` (s; None: open at that end) and, when the
    comparison's abscissa is the simulated t (a time series), the reference points in the same window.
    Returns (simulated, reference, span, outside): the window as said in reports ("t 0.6 .. 2.5 s") and the
    count of reference points it left out. The window is first checked against the simulated t
    (:func:`window_problem`); a problem is raised as a ValueError with the message alone.

    The windowed curve is the run's own between the window's ends, not the samples that happen to lie in
    it: every column interpolated linearly in t at t_from and at t_to (a sample within
    :data:`EDGE_TOLERANCE` of an end is taken as that end, as it is), then the samples strictly between.
    A reference time inside both the run and the window is so always on the curve, however far apart the
    samples, and gets the value the whole run would give it. With another abscissa (pressure along the
    stroke, ``--x x``) the window means the part of the curve the run traced from t_from to t_to: its ends
    are the x the run had at those times. Keeping instead the samples that bracket the window would add
    points from outside it (the creep of a hold before a lift, where x is not increasing, which is what the
    window is there to leave out). With that abscissa every reference point stays, to be found on that part
    of the curve (one outside it is an error that names the window).

    t must be strictly increasing (an error names the row where it is not). With a grouping column that the
    reference shares (a run per group, compared group by group), each group is windowed on its own, the
    window cut to the group's times; a group with no time in the window is left out."""
    if "t" not in simulated.columns:
        raise ValueError(f"--t-from/--t-to: {simulated.file} has no column 't' to take a window of "
                         f"(columns: {', '.join(simulated.columns)})")
    t = simulated.columns["t"]
    finite = t[~np.isnan(t)]
    if finite.size == 0:
        raise ValueError(f"--t-from/--t-to: {simulated.file}: the column 't' has no values")
    start, end = float(finite.min()), float(finite.max())
    problem = window_problem(t_from, t_to, start, end, f"the simulated curve in {simulated.file}")
    if problem:
        raise ValueError(problem)
    span = f"t {_s(start if t_from is None else t_from)} .. {_s(end if t_to is None else t_to)} s"
    slack = EDGE_TOLERANCE * (end - start)
    lo = start if t_from is None else max(t_from, start)
    hi = end if t_to is None else min(t_to, end)
    segments = list(simulated.groups.values()) if _grouped(simulated, reference) else [np.arange(t.size)]
    sources, ends = [], []  # the row each windowed row takes its place from; (position, row0, row1, t) to interpolate
    for rows in segments:
        _check_time(simulated, rows)
        for source, interpolate in _window_rows(t[rows], lo, hi, slack):
            if interpolate is not None:
                i, tk = interpolate
                ends.append((len(sources), rows[i], rows[i + 1], tk))
                source = _source(simulated, rows[i], rows[i + 1], prefer=rows[source])
            else:
                source = rows[source]
            sources.append(source)
    if len(sources) < 2:
        raise ValueError(f"--t-from/--t-to: no group of the simulated curve in {simulated.file} has two times in "
                         f"the window {span}")
    windowed = simulated.rows(np.array(sources))
    for position, i, j, tk in ends:
        w = (tk - t[i]) / (t[j] - t[i])
        for name, column in windowed.columns.items():
            a, b = simulated.columns[name][i], simulated.columns[name][j]
            column[position] = a + w * (b - a)  # exactly a (or b) where the column is constant
        windowed.columns["t"][position] = tk
    outside = 0
    x_sim, x_ref = split_pair(x)
    if x_sim == "t" and x_ref in reference.columns:
        xr = reference.columns[x_ref]
        width = EDGE_TOLERANCE * (hi - lo)  # as compare() allows at the curve's ends
        below = -math.inf if t_from is None else t_from - width
        above = math.inf if t_to is None else t_to + width
        inside = np.flatnonzero(np.isnan(xr) | ((xr >= below) & (xr <= above)))  # an empty x stays, to be refused
        if inside.size == 0:
            raise ValueError(f"--t-from/--t-to: no reference point of {reference.file} lies in the window {span}")
        if inside.size < xr.size:
            outside = int(xr.size - inside.size)
            reference = reference.rows(inside)
    return windowed, reference, span, outside


def _check_time(table: Table, rows: np.ndarray) -> None:
    """A window needs t strictly increasing over ``rows``; errors name the file row."""
    t = table.columns["t"][rows]
    bad = np.flatnonzero(np.isnan(t))
    if bad.size:
        raise table.error("missing value (empty or NaN): a window (--t-from/--t-to) needs every time",
                          "t", int(rows[bad[0]]))
    step = np.diff(t)
    bad = np.flatnonzero(step <= 0)
    if bad.size:
        k = int(bad[0]) + 1
        f = parse_unit(table.units["t"]).factor
        later, earlier = distinct(t[k] / f, t[k - 1] / f)
        what = "repeated" if step[k - 1] == 0 else "decreasing"
        raise table.error(f"t must be strictly increasing to take a window (--t-from/--t-to): {later} after "
                          f"{earlier} ({what})", "t", int(rows[k]))


def _window_rows(t: np.ndarray, lo: float, hi: float, slack: float):
    """The rows of one segment's window ``lo .. hi`` (t strictly increasing; indices into t): a list of
    (index, None) for a sample kept as it is and (index, (i, t_end)) for an end interpolated between samples
    i and i + 1 (index: the bracketing sample outside the window, whose place the row takes in errors).
    Empty when the segment has no two times in the window."""
    lo, hi = max(lo, float(t[0])), min(hi, float(t[-1]))
    if hi - lo <= slack:
        return []
    out = []
    j = int(np.searchsorted(t, lo - slack))  # the first sample at or after the start (to the slack)
    if t[j] <= lo + slack:
        out.append((j, None))
    else:
        out.append((j - 1, (j - 1, lo)))
    out += [(k, None) for k in np.flatnonzero((t > lo + slack) & (t < hi - slack))]
    i = int(np.searchsorted(t, hi + slack, side="right")) - 1  # the last sample at or before the end
    if t[i] >= hi - slack:
        out.append((i, None))
    else:
        out.append((i + 1, (i, hi)))
    return out


def _source(table: Table, i: int, j: int, prefer: int) -> int:
    """The row an interpolated row takes its place (file line, sample, labels) from: of the two samples
    ``i`` and ``j`` it lies between, one with a missing value, so that an error about it names that row;
    else ``prefer``."""
    for k in (i, j):
        if any(np.isnan(c[k]) for c in table.columns.values()):
            return k
    return prefer


# ---- the simulated side ---------------------------------------------------------------------------------
def is_netlist(path: str | Path) -> bool:
    return Path(path).suffix.lower() in (".yaml", ".yml")


def table_from_result(result) -> Table:
    """A simulation :class:`~blocks.result.Result` as a table: ``t [s]`` and the logged signals (SI inside)."""
    return _signal_table(result.file, result.names, result.display_units, result.t, result.values)


def planned_table(circuit) -> Table:
    """The names and units a circuit will log, without values: to check a comparison before running."""
    outputs = circuit.outputs
    return _signal_table(circuit.flat.file, [o.name for o in outputs], [o.display_unit for o in outputs],
                         np.empty(0), np.empty((0, len(outputs))))


def _signal_table(file, names, display_units, t, values) -> Table:
    columns = {"t": np.asarray(t, dtype=float)}
    units = {"t": "s"}
    for k, name in enumerate(names):
        columns[name] = np.asarray(values[:, k], dtype=float)
        units[name] = display_units[k]
    return Table(file=str(file), columns=columns, units=units, positions={n: i for i, n in enumerate(columns, start=1)})
