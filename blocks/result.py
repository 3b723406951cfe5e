"""A simulation result: named signals with units, written as CSV or plotted.

Values are SI inside; each logged signal has a display unit (from the netlist's ``outputs:``) used only
when writing and plotting. Files are written atomically (temporary file, then rename), so an interrupted
or failed run never leaves a half-written CSV or PNG in place of a good one.
"""

from __future__ import annotations

import csv
import io
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from blocks.units import parse_unit

TIME_COLUMN = "t"
"""The name of the results CSV's first column (``t [s]``)."""


def column_name_problem(name: str) -> str | None:
    """Why ``name`` cannot head a column of the results CSV (``name [unit]``), or None if it can.

    The CSV is read back by :func:`blocks.datafile.read_table` (``vphs diff``), which
    takes a header cell's name up to its ``[unit]`` and strips the spaces around it: a logged signal named
    ``t`` would be a second time column, one with brackets would not read as ``name [unit]``, one with
    spaces around it (or nothing but spaces) would read as another name, and one with a comma would be
    split into two columns by a reader that does not honour the CSV's quotes (a spreadsheet's import)."""
    if name == TIME_COLUMN:
        return f"'{TIME_COLUMN}' is the name of the time column"
    if not name.strip():
        return "a column name cannot be empty"
    if name != name.strip():
        return "spaces around a column name are dropped when the CSV is read"
    if "[" in name or "]" in name:
        return "'[' and ']' enclose a column's unit"
    if "," in name:
        return "',' separates the CSV's columns"
    if not name.isprintable():
        return "a column name must be printable characters"
    return None


CSV_ROWS = 4096  # rows formatted and written at a time


@dataclass
class Result:
    file: str
    t: np.ndarray
    names: list[str]
    units: list[str]  # SI
    display_units: list[str]
    values: np.ndarray  # (samples, signals), SI
    states: np.ndarray
    state_names: list[str]
    stats: dict
    seconds: float
    warnings: list[str] = field(default_factory=list)
    step_check: str = ""  # solver fixed: the doubled-step check's line ('' if unsaid or not run), also in warnings
    compile_seconds: float = 0.0  # the shared integrator compiled before this run (not in ``seconds``; 0: ready)

    def __getitem__(self, name: str) -> np.ndarray:
        """A logged signal in SI by name."""
        try:
            return self.values[:, self.names.index(name)]
        except ValueError:
            raise KeyError(f"no logged signal '{name}' (logged: {', '.join(self.names)})") from None

    def in_unit(self, name: str, unit: str | None = None) -> np.ndarray:
        """A logged signal in ``unit`` (its display unit by default)."""
        k = self.names.index(name)
        unit = unit or self.display_units[k]
        return self.values[:, k] / parse_unit(unit).factor

    def state(self, name: str) -> np.ndarray:
        return self.states[:, self.state_names.index(name)]

    def write_csv_into(self, stream) -> None:
        """The CSV into a text ``stream``: a header ``t [s]``, then ``name [unit]`` for each logged signal, and
        the values in those units to 10 significant digits, CSV_ROWS rows at a time (a long run's table is
        never held whole as text)."""
        writer = csv.writer(stream, lineterminator="\n")
        writer.writerow([f"{TIME_COLUMN} [s]"] + [f"{n} [{u}]" for n, u in zip(self.names, self.display_units)])
        factors = np.array([parse_unit(u).factor for u in self.display_units])
        for a in range(0, len(self.t), CSV_ROWS):
            t = self.t[a:a + CSV_ROWS]
            block = np.column_stack([t, self.values[a:a + CSV_ROWS] / factors]) if self.names else t[:, None]
            writer.writerows([f"{v:.10g}" for v in row] for row in block)

    def to_csv_text(self) -> str:
        buffer = io.StringIO()
        self.write_csv_into(buffer)
        return buffer.getvalue()

    def write_csv_file(self, path: Path) -> None:
        """The CSV written straight into the file ``path`` (replaced)."""
        with Path(path).open("w", encoding="utf-8", newline="") as stream:
            self.write_csv_into(stream)

    def write_csv(self, path: str | Path) -> None:
        write_together((Path(path), self.write_csv_file))

    def plot(self, path: str | Path, title: str | None = None, x: str | None = None,
             y: list[str] | None = None) -> None:
        """The logged signals ``y`` (default all) against ``x`` (default t): one panel per unit, signals of
        the same unit together, a shared abscissa. Against a signal the curve is drawn as the run went
        (a pressure against a flow, a force against a position), so a hysteresis shows as a loop."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        shown = [self.names.index(name) for name in (y or self.names) if name != x]
        groups: dict[str, list[int]] = {}
        for k in shown:
            groups.setdefault(self.display_units[k], []).append(k)
        abscissa = self.t if x is None else self.in_unit(x)
        n = max(1, len(groups))
        # constrained layout leaves room for the title above the first panel (tight_layout does not)
        fig, axes = plt.subplots(n, 1, sharex=True, figsize=(9, 2.2 + 1.8 * n), squeeze=False, layout="constrained")
        for ax, (unit, members) in zip(axes[:, 0], groups.items()):
            for k in members:
                ax.plot(abscissa, self.in_unit(self.names[k]), label=self.names[k])
            ax.set_ylabel(f"[{unit}]")
            ax.grid(True, alpha=0.3)
            ax.legend(loc="best", fontsize="small")
        axes[-1, 0].set_xlabel("t [s]" if x is None else f"{x} [{self.display_units[self.names.index(x)]}]")
        fig.suptitle(title or Path(self.file).name)
        try:
            atomic_write_figure(fig, Path(path))
        finally:
            plt.close(fig)


def _umask_mode() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write_text(path: Path, text: str) -> None:
    write_together((Path(path), lambda tmp: tmp.write_text(text, encoding="utf-8")))


def atomic_write_figure(fig, path: Path) -> None:
    write_together((Path(path), lambda tmp: fig.savefig(tmp, dpi=110)))


def write_together(*files) -> None:
    """Write files as one: each ``(path, write)`` pair's ``write(tmp)`` fills a temporary file beside its
    target (of the target's suffix, which matplotlib reads the format from), and only when every one is
    written are they renamed into place, a Ctrl-C during those renames taken after them. An error or an interrupt
    before then leaves every target as it was, and the staged files removed (a second Ctrl-C taken after
    that): a results CSV and its plot are never of two different runs, no half-written file is left beside.

    A target that is a symbolic link is written through: the file it points to is replaced, the link kept.
    A target that exists and is not a regular file (a named pipe, a device), or that names one of the
    process's own streams (/dev/stdout, /proc/self/fd/1, which the shell may have pointed at a file it
    appends to), cannot be replaced by a rename without being destroyed: what was staged for it is
    appended to it instead, after the renames (a pipe that no process reads is an error, not a wait)."""
    from blocks import interrupt

    staged: list[tuple[Path, Path]] = []
    try:
        for path, write in files:
            if special_target(path):
                folder = Path(tempfile.gettempdir())
            else:
                path = Path(os.path.realpath(path))
                path.parent.mkdir(parents=True, exist_ok=True)
                folder = path.parent
            fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=path.suffix or ".tmp")
            os.close(fd)
            staged.append((Path(tmp), path))
            write(Path(tmp))
            os.chmod(tmp, _umask_mode())  # mkstemp makes 0600; a result file is as readable as any other
        if len({os.path.realpath(path) for _, path in staged}) < len(staged):
            raise ValueError("write_together: two of the files are one path")
        with interrupt.deferred():  # a Ctrl-C or SIGTERM taken after the renames
            for tmp, path in staged:
                if not special_target(path):
                    os.replace(tmp, path)
        for tmp, path in staged:
            if special_target(path):
                _append_into(tmp, path)
    except BaseException:
        with interrupt.deferred():  # a second Ctrl-C leaves no staged (half-written) file behind
            for tmp, _ in staged:
                tmp.unlink(missing_ok=True)
        raise


def special_target(path) -> bool:
    """Whether an output ``path`` is written into rather than replaced: it exists (its links followed) and
    names a device or one of the process's streams (under /dev or /proc: /dev/stdout may lead to a file the
    shell appends to), or is neither a regular file nor a folder (a named pipe)."""
    path = Path(path)
    try:
        if not path.exists():
            return False
        return str(path.absolute()).startswith(("/dev/", "/proc/")) or not (path.is_file() or path.is_dir())
    except OSError:  # a symbolic link loop: not a special file (the caller's checks name the loop)
        return False


def _append_into(staged: Path, target: Path) -> None:
    """The staged file's bytes appended to ``target`` (a pipe, a device, a stream), the staged file removed.
    A pipe is opened without waiting: with no process reading it, that is an error (ENXIO)."""
    import errno
    import shutil
    import stat

    try:
        flags = os.O_WRONLY | os.O_APPEND
        if stat.S_ISFIFO(os.stat(target).st_mode):
            flags |= os.O_NONBLOCK
        try:
            fd = os.open(target, flags)
        except OSError as exc:
            if exc.errno == errno.ENXIO:
                raise OSError(errno.ENXIO, "no process reads this pipe", str(target)) from None
            raise
        os.set_blocking(fd, True)
        with open(staged, "rb") as source, os.fdopen(fd, "wb") as sink:
            shutil.copyfileobj(source, sink)
    except OSError as exc:  # a full device: said of the target, not of a nameless write
        raise OSError(exc.errno, exc.strerror, str(target)) from None
    finally:
        staged.unlink(missing_ok=True)
