"""Fuzzer round s20: a group table's units and rows, a free parameter's step, and SIGTERM (vphs calibrate).

- A ``group_table`` column in kg setting a pressure, or one without a unit, was read in SI (95.4 Pa for a
  crack pressure meant in bar); a data column of the wrong unit was refused already, the table's now is.
- Two rows for one group were taken (the last won, silently); an empty cell set the parameter to NaN.
- ``free: {k: {step: -1}}`` (or 0, or ``true``: 1 in SI) ran the fit.
- SIGTERM killed the process outright, leaving round1/ and experiment_augmented.yaml half-written; it now
  stops the command as Ctrl-C does, for every command (the handling is shared: blocks/interrupt.py), exit 143.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

import cli
from blocks.calibrate.experiment import load_experiment

ROOT = Path(__file__).resolve().parents[2]
RIG = ROOT / "netlists" / "experiments" / "circuits" / "relief_rig.yaml"

SPEC = {
    "netlist": str(RIG),
    "data": "data.csv",
    "group": "setting",
    "inputs": {"Q": {"parameter": "Q_in", "noise": "0.5 l/min"}},
    "outputs": {"p1": {"signal": "p1", "noise": "0.2 bar"}},
    "group_table": {"file": "crack.csv", "columns": {"crack": "p_set"}},
    "free": {"k_s": {"initial": "50 bar", "lower": "5 bar", "upper": "500 bar"}},
}
DATA = "setting,Q [l/min],p1 [bar]\n1,20,40\n1,40,50\n2,20,45\n2,40,55\n"
CRACK = "setting,crack [bar]\n1,30\n2,45\n"


def files(tmp_path, crack: str = CRACK, **free) -> Path:
    (tmp_path / "data.csv").write_text(DATA)
    (tmp_path / "crack.csv").write_text(crack)
    spec = yaml.safe_load(yaml.safe_dump(SPEC))
    spec["free"]["k_s"].update(free)
    path = tmp_path / "exp.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def calibrate(tmp_path, capsys, path: Path) -> tuple[int, str]:
    code = cli.main(["calibrate", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    return code, err


def refused(tmp_path, capsys, path: Path, pattern: str) -> str:
    code, err = calibrate(tmp_path, capsys, path)
    assert code == 2 and len(err.splitlines()) == 1 and "internal error" not in err and "Traceback" not in err, err
    assert re.fullmatch(pattern, err), err
    assert not (tmp_path / "out").exists()
    return err


def test_a_group_table_in_bar_sets_each_group(tmp_path):
    exp = load_experiment(files(tmp_path))
    assert exp.groups == {"1": {"p_set": pytest.approx(30e5)}, "2": {"p_set": pytest.approx(45e5)}}


def test_a_group_table_column_of_another_dimension_is_refused(tmp_path, capsys):
    path = files(tmp_path, crack="setting,crack [kg]\n1,30\n2,45\n")
    refused(tmp_path, capsys, path, rf"vphs: {re.escape(str(tmp_path / 'crack.csv'))}:1:2: column 'crack \[kg\]': "
            r"a mass, but it sets p_set \(group_table\.columns\.crack in exp\.yaml\), a pressure \(Pa\)")


def test_a_group_table_column_without_a_unit_is_refused_with_the_unit_to_write(tmp_path, capsys):
    path = files(tmp_path, crack="setting,crack\n1,30\n2,45\n")
    refused(tmp_path, capsys, path, rf"vphs: {re.escape(str(tmp_path / 'crack.csv'))}:1:2: column 'crack' has no "
            r"unit, but it sets p_set \(group_table\.columns\.crack in exp\.yaml\), a pressure \(Pa\): write "
            r"'crack \[bar\]'")


def test_unmapped_columns_of_a_group_table_keep_their_freedom(tmp_path):
    """Only the mapped columns set parameters; others (a ratio, a note) go without a unit as before."""
    exp = load_experiment(files(tmp_path, crack="setting,ratio,note,crack [bar]\n1,2.8,std,30\n2,2.8,+1 turn,45\n"))
    assert exp.groups["2"] == {"p_set": pytest.approx(45e5)}


def test_two_rows_for_one_group_are_refused_naming_both(tmp_path, capsys):
    path = files(tmp_path, crack="setting,crack [bar]\n1,30\n2,45\n1,300\n")
    refused(tmp_path, capsys, path, rf"vphs: {re.escape(str(tmp_path / 'crack.csv'))}:4:1: column 'setting': group "
            r"'1' has 2 rows \(lines 2 and 4\); a group table gives one row per group, else which values the group "
            r"takes is ambiguous")


def test_an_empty_cell_of_a_group_table_is_refused(tmp_path, capsys):
    path = files(tmp_path, crack="setting,crack [bar]\n1,30\n2,\n")
    refused(tmp_path, capsys, path, rf"vphs: {re.escape(str(tmp_path / 'crack.csv'))}:3:2: column 'crack \[bar\]': "
            r"no value for group '2' \(an empty cell\); it sets p_set")


@pytest.mark.parametrize("step, pattern", [
    (-1, r"free\.k_s\.step: -1 is not a positive step; give the finite-difference step of k_s as a size above 0"),
    (0, r"free\.k_s\.step: 0 is not a positive step; .*"),
    ("-0.5 bar", r"free\.k_s\.step: -0\.5 bar is not a positive step; .*"),
    (float("inf"), r"k_s: inf is not a finite number"),
    (True, r"free\.k_s\.step: true is not a number"),
])
def test_a_step_that_is_not_a_positive_size_is_refused(tmp_path, capsys, step, pattern):
    path = files(tmp_path, step=step)
    line = next(k for k, text in enumerate(path.read_text().splitlines(), start=1) if text.strip().startswith("step:"))
    refused(tmp_path, capsys, path, rf"vphs: {re.escape(str(path))}:{line}:\d+: {pattern}")


def test_a_positive_step_is_kept(tmp_path):
    assert load_experiment(files(tmp_path, step="0.5 bar")).free[0].step == pytest.approx(0.5e5)
