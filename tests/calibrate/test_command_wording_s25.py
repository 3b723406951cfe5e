"""calibrated.yaml's header and report.md say where a single time series' command comes from: the fitted one
(latent levels or knots) only when an input is fitted. A user review found "The command is the fitted one"
on an experiment that fits no input (the command was the netlist's own profile)."""

from __future__ import annotations

from pathlib import Path

import yaml

import cli

ROOT = Path(__file__).resolve().parents[2]
EXPERIMENTS = ROOT / "netlists" / "experiments"


def run(tmp_path, keep_inputs: bool) -> tuple[str, str]:
    spec = yaml.safe_load((EXPERIMENTS / "drive_line_series.yaml").read_text())
    spec["netlist"] = str(EXPERIMENTS / spec["netlist"])
    spec["data"] = str(EXPERIMENTS / spec["data"])
    if not keep_inputs:
        del spec["inputs"]  # the netlist's own command profile drives the run
    spec["trace"] = {"rounds": 1, "top": 1, "only": ["coulomb_friction"]}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    assert cli.main(["calibrate", str(tmp_path / "exp.yaml"), "-q", "-o", str(tmp_path / "out")]) == 0
    return (tmp_path / "out" / "calibrated.yaml").read_text(), (tmp_path / "out" / "report.md").read_text()


def test_an_experiment_fitting_no_input_says_the_command_is_the_netlists(tmp_path):
    header, report = run(tmp_path, keep_inputs=False)
    assert "The command is the netlist's own (no input is fitted): `vphs run` reproduces the fit" in header
    assert "the fitted one" not in header
    assert "and the netlist's own command (no input is fitted): `vphs run` reproduces the fit" in report
    assert "the fitted command" not in report


def test_an_experiment_with_latent_command_levels_says_the_command_is_fitted(tmp_path):
    header, report = run(tmp_path, keep_inputs=True)
    assert "The command is the fitted one (its latent levels or knots): `vphs run` reproduces the fit" in header
    assert "and the fitted command: `vphs run` reproduces the fit" in report
