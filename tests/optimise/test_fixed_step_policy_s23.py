"""Where the fixed solver's doubled-step check runs in jobs and calibrations (blocks/solve/step_check.py).

The check repeats a run at twice the step: half a run more. An optimisation's evaluations and a calibration's
fits skip it (thousands of runs); the design an optimisation reports, the points of a sweep and the final model
of a calibration are checked, and a step too long is said there.

The circuit: tests/circuits/netlists/flow_pulse.yaml, a volume V drained by a laminar leak G taking a flow
step q at t_p; tau = V/(beta*G) = 0.125 s. A fixed step of 2 tau is off the closed form and is warned of
(tests/circuits/test_fixed_step_check.py); a step of tau/125 is not.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

import blocks.solve.step_check as step_check
from blocks.optimise.job import load_job
from blocks.optimise.report import warnings
from blocks.optimise.runner import run_optimise, run_sweep

FLOW_PULSE = Path(__file__).resolve().parents[1] / "circuits" / "netlists" / "flow_pulse.yaml"
BETA, V, G, Q = 8e8, 1e-3, 1e-11, 10.0 / 60000
TAU = V / (BETA * G)
TOO_LONG = "simulation.fixed_step 0.25 s may be too long"


def _netlist(tmp_path: Path, fixed_step: float) -> Path:
    spec = yaml.safe_load(FLOW_PULSE.read_text())
    spec["parameters"].update({"t_p": "0.5 s", "w": "100 s"})  # a step of q at 0.5 s, held to the end
    spec["simulation"] = {"t_end": "2 s", "dt_out": "10 ms", "solver": "fixed", "fixed_step": f"{fixed_step} s"}
    path = tmp_path / "pulse.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def _job(tmp_path: Path, fixed_step: float, body: str) -> Path:
    path = tmp_path / "job.yaml"
    path.write_text(f"""\
name: pulse
netlist: {_netlist(tmp_path, fixed_step)}
output: {tmp_path / "out"}
seed: 1
cost:
  terms:
    peak: {{kind: max_abs, signal: pA, unit: bar}}
{body}""")
    return path


OPTIMISE = """\
parameters:
  q: {min: "5 l/min", max: "15 l/min"}
algorithm: {method: complex, max_evaluations: 8, candidates: 1}
"""
SWEEP = """\
sweep:
  parameters:
    q: ["5 l/min", "10 l/min", "15 l/min"]
"""


@pytest.fixture
def checks(monkeypatch):
    """The number of doubled-step checks run."""
    calls = []
    original = step_check.doubled_step_warning

    def counted(*args):
        calls.append(1)
        return original(*args)

    monkeypatch.setattr(step_check, "doubled_step_warning", counted)
    return calls


def test_an_optimisation_checks_only_the_design_it_reports_and_says_its_step_is_too_long(tmp_path, checks):
    summary = run_optimise(load_job(_job(tmp_path, 2 * TAU, OPTIMISE)), workers=1, quiet=True)
    assert summary.evaluated >= 5 and len(checks) == 1  # the best, run again by the report; no evaluation
    assert all(not r.get("warnings") for r in summary.records)
    said = [w for w in warnings(summary) if TOO_LONG in w]
    assert len(said) == 1 and said[0].startswith("the best design, run again with its step checked: ")
    assert f"**Warning:** The best design, run again with its step checked: {TOO_LONG}" in summary.report.read_text()


def test_an_optimisation_with_a_short_enough_step_says_nothing_of_it(tmp_path, checks):
    summary = run_optimise(load_job(_job(tmp_path, TAU / 125, OPTIMISE)), workers=1, quiet=True)
    assert len(checks) == 1 and summary.step_checks == []
    assert not any("fixed_step" in w for w in warnings(summary))


def test_a_sweep_checks_every_point_and_lists_them_in_its_report(tmp_path, checks):
    summary = run_sweep(load_job(_job(tmp_path, 2 * TAU, SWEEP)), workers=1, quiet=True)
    assert len(checks) == 3
    assert all(TOO_LONG in r["warnings"][0] for r in summary.records)
    assert "3 of 3 points ran with warnings (the report's Warnings section lists them)" in warnings(summary)
    report = summary.report.read_text()
    assert "## Warnings (3 points)" in report
    assert report.count(TOO_LONG) == 3 and "(q = 10 l/min)" in report


def test_a_calibration_checks_its_final_model_once_and_says_so_in_the_verdict(tmp_path, checks):
    from blocks.calibrate.run import calibrate

    netlist = _netlist(tmp_path, 2 * TAU)
    t = np.arange(0.0, 2.0 + 1e-9, 0.01)
    p = np.where(t < 0.5, 0.0, Q / G * (1.0 - np.exp(-np.clip(t - 0.5, 0.0, None) / TAU)))
    noisy = p / 1e5 + 0.05 * np.random.default_rng(3).normal(size=t.size)
    (tmp_path / "data.csv").write_text("t [s],pA [bar]\n" + "".join(f"{a:.4f},{b:.5f}\n" for a, b in zip(t, noisy)))
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump({
        "netlist": str(netlist), "data": "data.csv", "outputs": {"pA": {"signal": "pA", "noise": "0.05 bar"}},
        "free": {"leak.G": {"initial": "1.2e-11 m^3/(s*Pa)", "lower": "1e-12 m^3/(s*Pa)",
                            "upper": "1e-10 m^3/(s*Pa)"}},
        "trace": {"rounds": 1, "only": ["sensor_offset"]}}, sort_keys=False))
    cal = calibrate(tmp_path / "exp.yaml", tmp_path / "out", with_heldout=False)
    assert cal.simulations > 10 and len(checks) == 1  # the fits' runs unchecked, the final model checked
    said = [line for line in cal.verdict if TOO_LONG in line]
    assert len(said) == 1 and said[0].startswith("the final model's run warns: simulation.fixed_step")
