"""Shared helpers for the netlist tests: load a netlist as far as a circuit without compiling it, locate a
needle in a fixture's text, run the CLI in a subprocess.

Loading builds the circuit with ``compile=False``: the generated module is only checked to be valid Python,
not written, imported or handed to numba (compiling a new structure costs seconds).
"""

from __future__ import annotations

import inspect
import os
import re
import subprocess
import sys
from contextlib import contextmanager
from pathlib import Path
from unittest import mock

from blocks.errors import VphsError

HERE = Path(__file__).resolve().parent
CASES = HERE / "cases"
ROOT = HERE.parents[1]
EXAMPLES = ROOT / "netlists" / "examples"

# "<file>:<line>:<column>: message", line and column optional
LOCATED = re.compile(r"^(?P<file>.+?)(?::(?P<line>\d+)(?::(?P<col>\d+))?)?: (?P<message>\S.*)$")


def load(path):
    """flatten + Circuit (without compiling: ``compile=False``, as ``vphs validate`` does) + vectors; the
    generated source is checked to be valid Python. Returns the circuit."""
    from blocks.circuit import Circuit
    from blocks.netlist.flatten import flatten

    circuit = Circuit(flatten(str(path)), compile=False)
    compile(circuit.source, f"<generated for {path}>", "exec")  # the generator wrote valid Python
    circuit.vectors()
    return circuit


def load_error(path) -> VphsError:
    """The VphsError that loading ``path`` raises (fails the test if it loads or raises anything else)."""
    try:
        load(path)
    except VphsError as exc:
        return exc
    except Exception as exc:  # noqa: BLE001  (any other exception is a bug: the CLI calls it "internal error")
        raise AssertionError(f"{path}: {type(exc).__name__}: {exc} (expected a VphsError)") from exc
    raise AssertionError(f"{path} loaded without error; expected a VphsError")


def position(text: str, needle: str, nth: int = 0, offset: int = 0) -> tuple[int, int]:
    """1-based (line, column) of the ``nth`` occurrence of ``needle`` in ``text``, plus ``offset`` chars.

    A first line ``description: ...`` (which says what is wrong with a fixture) is not searched.
    """
    start = text.find("\n") if text.startswith("description:") else -1
    for _ in range(nth + 1):
        start = text.find(needle, start + 1)
        assert start >= 0, f"needle {needle!r} (occurrence {nth}) not in the fixture"
    start += offset
    line = text.count("\n", 0, start) + 1
    col = start - (text.rfind("\n", 0, start) + 1) + 1
    return line, col


def split_message(message: str) -> tuple[str, int | None, int | None, str]:
    """(file, line, column, what) of a one-line error; AssertionError if it is not in that form."""
    assert "\n" not in message, f"error message spans several lines: {message!r}"
    m = LOCATED.match(message)
    assert m, f"error message not in the form '<file>[:line[:col]]: what': {message!r}"
    line = int(m["line"]) if m["line"] else None
    col = int(m["col"]) if m["col"] else None
    return m["file"], line, col, m["message"]


def cli_env(cache_dir: Path) -> dict:
    env = dict(os.environ)
    env.pop("VPHS_DEBUG", None)
    env["VPHS_CACHE_DIR"] = str(cache_dir)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def run_cli(args: list[str], cache_dir: Path, cwd: Path | None = None, timeout: float = 300):
    """``python -m cli ARGS`` in a fresh process; returns the CompletedProcess (text mode)."""
    return subprocess.run([sys.executable, "-m", "cli", *args], cwd=str(cwd or ROOT), env=cli_env(cache_dir),
                          capture_output=True, text=True, timeout=timeout)
