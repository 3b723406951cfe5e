"""Fuzzer round s22: standard output that cannot be written (vphs run, validate and every command).

- A reader that left before the command's output was written out (`vphs validate | head -c 0`): with Python's
  usual buffering the one line stayed buffered until the interpreter's exit, whose flush failed outside the
  command's handling: "Exception ignored ... BrokenPipeError" and exit 120. A closed pipe is a quiet exit 0
  wherever the write happens (as `vphs blocks | head` and `-o /dev/stdout | head` were already).
- Standard output on a full device (``> /dev/full``): "internal error: OSError: [Errno 28]" (or, buffered,
  exit 120 and a traceback-like report) where ``-o /dev/full`` says "vphs: /dev/full: No space left on
  device"; now "vphs: standard output: No space left on device", exit 1.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from netlist_helpers import cli_env

ROOT = Path(__file__).resolve().parents[2]
DRIVE = ROOT / "netlists" / "examples" / "drive_line.yaml"


def validate(stdout, cache: Path, buffered: bool) -> subprocess.CompletedProcess:
    """``vphs validate`` of the drive line (no compilation: quick) with its standard output on ``stdout``;
    ``buffered``: as a user's shell runs it (block-buffered into a pipe or file), else PYTHONUNBUFFERED."""
    env = cli_env(cache)
    env.pop("PYTHONUNBUFFERED", None)
    if not buffered:
        env["PYTHONUNBUFFERED"] = "1"
    return subprocess.run([sys.executable, "-m", "cli", "validate", str(DRIVE)], stdout=stdout,
                          stderr=subprocess.PIPE, env=env, cwd=str(ROOT), text=True, timeout=120)


@pytest.mark.parametrize("buffered", [True, False])
def test_a_reader_that_left_before_the_output_was_written_is_a_quiet_exit(tmp_path, buffered):
    """The pipe's read end is closed before vphs starts: the broken pipe does not depend on timing."""
    read, write = os.pipe()
    os.close(read)
    try:
        done = validate(write, tmp_path, buffered)
    finally:
        os.close(write)
    assert (done.returncode, done.stderr) == (0, "")


@pytest.mark.parametrize("buffered", [True, False])
def test_standard_output_on_a_full_device_is_one_line_naming_it(tmp_path, buffered):
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full here")
    with open("/dev/full", "w") as full:
        done = validate(full, tmp_path, buffered)
    assert (done.returncode, done.stderr) == (1, "vphs: standard output: No space left on device\n")
