"""`vphs linearise` says what the run to its operating point warned of, as `vphs run` does: before, those
warnings (a vapour cavity, a fixed step too long) were dropped and the model was linearised silently.

The circuit: tests/circuits/netlists/flow_pulse.yaml at a fixed step of 2 tau (tau = V/(beta*G) = 0.125 s),
which tests/circuits/test_fixed_step_check.py shows is off its closed form and warned of by `vphs run`.
"""

from __future__ import annotations

from pathlib import Path

import yaml

import cli

FLOW_PULSE = Path(__file__).parent / "netlists" / "flow_pulse.yaml"


def _netlist(tmp_path: Path, fixed_step: str) -> Path:
    spec = yaml.safe_load(FLOW_PULSE.read_text())
    spec["parameters"].update({"t_p": "0.5 s", "w": "100 s"})
    spec["simulation"] = {"t_end": "2 s", "dt_out": "10 ms", "solver": "fixed", "fixed_step": fixed_step}
    path = tmp_path / "pulse.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def test_the_run_to_the_point_warns_as_vphs_run_does(tmp_path, capsys):
    code = cli.main(["linearise", str(_netlist(tmp_path, "0.25 s")), "--at", "1.5 s", "-q"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "linearised about the state at t = 1.5 s of the run" in out
    lines = [line for line in err.splitlines() if "fixed_step" in line]
    assert len(lines) == 1
    assert lines[0].startswith("vphs: warning: the run to the operating point: simulation.fixed_step 0.25 s may "
                               "be too long")


def test_a_run_with_nothing_to_say_says_nothing(tmp_path, capsys):
    code = cli.main(["linearise", str(_netlist(tmp_path, "1 ms")), "--at", "1.5 s", "-q"])
    out, err = capsys.readouterr()
    assert code == 0 and "warning" not in err
