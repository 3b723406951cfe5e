"""pydantic's own wording ("Input should be less than or equal to 50") never reaches a user: every bound,
whole number, choice, list and mapping problem of a netlist, a job or an experiment file is said in the
project's words, in one place (blocks.netlist.yaml_source.in_words) (review 25: heldout.k: 60)."""

from __future__ import annotations

from pathlib import Path

import pytest

import cli

ROOT = Path(__file__).resolve().parents[2]
DRIVE_LINE = ROOT / "netlists" / "opt" / "drive_line.yaml"

NETLIST = f"""\
components:
  tank: {{type: tank}}
simulation: {{t_end: "1 s", SETTING}}
"""

JOB = f"""\
netlist: {DRIVE_LINE}
output: OUT
parameters:
  Kp: {{min: 1, max: 3}}
cost: {{terms: {{pos: {{kind: ise, signal: x, reference: x_ref, unit: mm, weight: WEIGHT}}}}}}
algorithm: {{method: complex, max_evaluations: BUDGET}}
"""

EXPERIMENT = f"""\
netlist: {DRIVE_LINE}
data: data.csv
outputs:
  x: {{signal: x, noise: "1 mm"}}
free:
  Kp: {{initial: 2, lower: 1, upper: 3}}
heldout: {{scheme: kfold, k: K}}
trace: {{rounds: ROUNDS}}
"""

CASES = {
    # name: (kind, text replacements, the line expected after 'vphs: FILE:LINE:COL: ')
    "netlist bound above": ("netlist", {"SETTING": "rtol: 2"}, "simulation.rtol: must be less than 1, got 2"),
    "netlist bound below": ("netlist", {"SETTING": "max_steps: 0"}, "simulation.max_steps: must be greater than 0, got 0"),
    "netlist whole number": ("netlist", {"SETTING": "max_steps: 2.5"},
                             "simulation.max_steps: must be a whole number, got 2.5"),
    "netlist choice": ("netlist", {"SETTING": "solver: ode45"},
                       "simulation.solver: 'ode45' is not known; allowed: 'rodas', 'fixed', 'lsoda', 'bdf' or 'radau'"),
    "job at least": ("job", {"WEIGHT": "-1", "BUDGET": "10"}, "cost.terms.pos.weight: must be at least 0, got -1"),
    "job at least 1": ("job", {"WEIGHT": "1", "BUDGET": "0"}, "algorithm.max_evaluations: must be at least 1, got 0"),
    "job not a whole number": ("job", {"WEIGHT": "1", "BUDGET": "many"},
                               "algorithm.max_evaluations: 'many' is not a whole number"),
    "experiment at most": ("experiment", {"K": "60", "ROUNDS": "1"}, "heldout.k: must be at most 50, got 60"),
    "experiment at least": ("experiment", {"K": "1", "ROUNDS": "1"}, "heldout.k: must be at least 2, got 1"),
    "experiment rounds": ("experiment", {"K": "3", "ROUNDS": "4"}, "trace.rounds: must be at most 3, got 4"),
}


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_bounds_and_types_are_said_in_plain_words(tmp_path, capsys, case):
    kind, replacements, expected = CASES[case]
    text = {"netlist": NETLIST, "job": JOB, "experiment": EXPERIMENT}[kind].replace("OUT", str(tmp_path / "out"))
    for key, value in replacements.items():
        text = text.replace(key, value)
    path = tmp_path / f"{kind}.yaml"
    path.write_text(text)
    (tmp_path / "data.csv").write_text("t [s],x [mm]\n0,0\n1,1\n")
    argv = {"netlist": ["validate", str(path)], "job": ["optimise", str(path), "--workers", "1", "-q"],
            "experiment": ["calibrate", str(path), "-o", str(tmp_path / "cal"), "-q"]}[kind]
    assert cli.main(argv) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"vphs: {path}:") and line.endswith(f": {expected}"), line
    assert "Input should" not in line and "should have" not in line


@pytest.mark.parametrize("error, words", [
    ({"type": "less_than_equal", "ctx": {"le": 50}, "input": 60, "msg": "x"}, "must be at most 50, got 60"),
    ({"type": "greater_than_equal", "ctx": {"ge": 0}, "input": -1.5, "msg": "x"}, "must be at least 0, got -1.5"),
    ({"type": "finite_number", "input": float("inf"), "msg": "x"}, "must be a finite number, got inf"),
    ({"type": "too_short", "ctx": {"min_length": 1, "actual_length": 0}, "input": {}, "msg": "x"},
     "empty: give at least 1 entry"),
    ({"type": "too_long", "ctx": {"max_length": 2, "actual_length": 3}, "input": {}, "msg": "x"},
     "takes at most 2 entries, got 3"),
    ({"type": "list_type", "input": "abc", "msg": "x"}, "expected a list, got the text 'abc'"),
    ({"type": "string_type", "input": 5, "msg": "x"}, "expected text, got the number 5"),
    ({"type": "some_custom_type", "input": 5, "msg": "its own words"}, "its own words"),
])
def test_in_words(error, words):
    from blocks.netlist.yaml_source import in_words

    assert in_words(error) == words
