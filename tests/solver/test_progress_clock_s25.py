"""The progress of a run is timed from its first step, not from the integrator's compilation (review 25: the
first run of a new circuit read "10 % simulated, 5.1 s elapsed, ~45.7 s left" on every line, for a run of
21 ms: numba compiled the shared integrator inside the first slice of the run)."""

from __future__ import annotations

import time
import types
from pathlib import Path

import blocks.solve.run as run
from blocks.circuit import Circuit

DRIVE_LINE = Path(__file__).resolve().parents[2] / "netlists" / "examples" / "drive_line.yaml"
COMPILING = 1.0  # s: the stand-in for numba's compilation, on the integrator's first call


def test_compilation_is_not_on_the_runs_clock(monkeypatch):
    circuit = Circuit.from_file(DRIVE_LINE)
    real = circuit.module.integrate
    calls = []

    def first_call_compiles(*args):
        if not calls:
            time.sleep(COMPILING)
        calls.append(1)
        return real(*args)

    circuit.module = types.SimpleNamespace(integrate=first_call_compiles)
    monkeypatch.setattr(run, "_integrator_ready", lambda: False, raising=False)  # as in a fresh process
    seen = []
    result = circuit.simulate(progress=lambda fraction, seconds: seen.append((fraction, seconds)))
    assert len(seen) == run.PROGRESS_CHUNKS and seen[-1][0] == 1.0
    assert all(seconds < COMPILING / 2 for _, seconds in seen), seen  # the estimate is the run's own
    assert result.seconds < COMPILING / 2
    assert result.compile_seconds >= COMPILING


def test_a_warm_integrator_is_not_called_again(monkeypatch):
    circuit = Circuit.from_file(DRIVE_LINE)
    circuit.simulate()  # the integrator is compiled now, in this process
    assert run._integrator_ready()
    real, calls = circuit.module.integrate, []
    circuit.module = types.SimpleNamespace(integrate=lambda *a: calls.append(1) or real(*a))
    result = circuit.simulate()
    assert result.compile_seconds == 0.0 and len(calls) == run.PROGRESS_CHUNKS
