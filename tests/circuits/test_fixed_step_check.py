"""The fixed solver against a closed form: its doubled-step check (blocks/solve/step_check.py), its steps
ending on an input's jumps, and its grid kept across the run's slices (blocks/solve/run.py).

tests/circuits/netlists/flow_pulse.yaml with the pulse longer than the run: a volume V drained by a laminar
leak G takes a flow step q at t_p, p = (q/G)*(1 - exp(-(t - t_p)/tau)), tau = V/(beta*G) = 0.125 s. A fixed
step far shorter than tau gives that curve, and nothing is said; a step of 2 tau is off it (the L-stable
method still runs to the right end value, so the run does not fail), and the warning must say so.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit

NETLIST = Path(__file__).parent / "netlists" / "flow_pulse.yaml"
ROOT = Path(__file__).resolve().parents[2]
BETA, V, G, Q = 8e8, 1e-3, 1e-11, 10.0 / 60000
TAU = V / (BETA * G)
STEP_AT = {"t_p": 0.5, "w": 100.0}  # a step of q at 0.5 s, held to the end


def _run(fixed_step: float, check: bool = True, t_p: float = 0.5):
    circuit = Circuit.from_file(NETLIST)
    settings = circuit.settings.with_(solver="fixed", fixed_step=fixed_step, t_end=2.0, fixed_step_check=check)
    result = circuit.simulate({**STEP_AT, "t_p": t_p}, settings=settings)
    p = result.values[:, result.names.index("pA")]
    rise = np.clip(result.t - t_p, 0.0, None)
    expected = np.where(result.t < t_p, 0.0, Q / G * (1.0 - np.exp(-rise / TAU)))
    return result, np.max(np.abs(p - expected)) / (Q / G)


def test_a_step_short_against_the_time_constant_is_right_and_not_warned():
    result, error = _run(TAU / 125)
    assert error < 1e-9
    assert not result.warnings


def test_a_step_of_twice_the_time_constant_is_off_and_warned():
    result, error = _run(2 * TAU)
    assert error > 5e-3  # the run ends at the right pressure, with status 0
    assert len(result.warnings) == 1
    assert "simulation.fixed_step 0.25 s may be too long" in result.warnings[0]
    assert "'pA' moves by" in result.warnings[0]


def test_a_fixed_step_ends_on_an_input_jump_between_its_grid_points():
    # 0.3 ms into a 1 ms step: smeared over that step, it was 2e-3 of q/G off
    result, error = _run(TAU / 125, t_p=0.5003)
    assert error < 1e-9
    assert result.stats["steps"] == 2001  # the 2000 of the grid and the one the jump splits


def test_the_check_can_be_turned_off():
    result, error = _run(2 * TAU, check=False)
    assert error > 5e-3 and not result.warnings


def test_the_variable_step_solver_is_not_checked_twice():
    circuit = Circuit.from_file(NETLIST)
    result = circuit.simulate(STEP_AT, settings=circuit.settings.with_(fixed_step=2 * TAU, t_end=2.0))
    assert not result.warnings


@pytest.mark.parametrize("option, message", [
    ("1 mm", "vphs: --fixed-step '1 mm': wrong unit 'mm'"),
    ("inf", "vphs: --fixed-step 'inf': not a finite time"),
    ("-1 ms", "vphs: simulation.fixed_step (with --solver/--t-end/--fixed-step): must be positive"),
])
def test_a_bad_fixed_step_option_is_one_line_and_exit_2(option, message):
    done = subprocess.run([sys.executable, "-m", "cli", "run", str(NETLIST), "--solver", "fixed",
                           "--fixed-step", option, "-q"], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 2
    assert done.stderr.startswith(message) and done.stderr.count("\n") == 1


def test_the_fixed_step_option_sets_the_step(tmp_path):
    out = tmp_path / "p.csv"
    done = subprocess.run([sys.executable, "-m", "cli", "run", str(NETLIST), "--solver", "fixed",
                           "--fixed-step", "0.25 s", "--t-end", "2 s", "--set", "t_p=0.5 s", "--set", "w=100 s",
                           "-o", str(out)], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0
    assert "vphs: warning: simulation.fixed_step 0.25 s may be too long" in done.stderr
    assert "steps 8," in done.stderr  # 2 s at 0.25 s
