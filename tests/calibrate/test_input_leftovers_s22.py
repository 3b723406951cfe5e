"""Input leftovers of fuzzer round s22 (vphs calibrate): a group table's column for a parameter of no
declared dimension, a decimal comma beside a grouping column, a repeats: column of text, and a second Ctrl-C
while a calibration's output folder is being restored.

- A ``group_table`` column setting a parameter the netlist gives no dimension (a bare number read inside an
  expression, ``f_s`` in ``p_set*f_s``) was converted with whatever unit it carried and taken in SI: 'f [mm]'
  1000 set f_s = 1 without a word, where ``groups: {1: {f_s: "1000 mm"}}`` is refused. Its unit is now checked
  as that value's is.
- Beside a grouping column, a column without a unit of decimal-comma numbers ("1,5") was kept as labels
  (text, never compared): a ratio meant as 1.5 vanished from the data. It is now the number error it is
  without a grouping column.
- A ``repeats:`` column with a text cell was read as labels beside the grouping column, and the run ended in
  "no column 'point'" while the column was there; the text cell is now the error.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

import cli
from blocks.calibrate.experiment import load_experiment
from blocks.datafile import DataFileError, read_table

ROOT = Path(__file__).resolve().parents[2]
RIG = ROOT / "netlists" / "experiments" / "circuits" / "relief_rig.yaml"

DATA = "setting,Q [l/min],p1 [bar]\n1,20,40\n1,40,50\n2,20,45\n2,40,55\n"


def rig(tmp_path, setting: str) -> Path:
    """The relief rig with the relief's crack setting given by the expression ``setting`` of its parameters
    and a bare number ``f`` (no dimension the netlist gives it: it is read only inside the expression)."""
    text = RIG.read_text()
    text = text.replace('  k_s: "60 bar"', '  f: 0.0\n  k_s: "60 bar"', 1)
    text = text.replace("p_set: p_set, k_s", f'p_set: "{setting}", k_s', 1)
    path = tmp_path / "rig.yaml"
    path.write_text(text)
    return path


def experiment(tmp_path, table: str, setting: str = "p_set*(1 + f)") -> Path:
    (tmp_path / "data.csv").write_text(DATA)
    (tmp_path / "table.csv").write_text(table)
    spec = {"netlist": str(rig(tmp_path, setting)), "data": "data.csv", "group": "setting",
            "inputs": {"Q": {"parameter": "Q_in", "noise": "0.5 l/min"}},
            "outputs": {"p1": {"signal": "p1", "noise": "0.2 bar"}},
            "group_table": {"file": "table.csv", "columns": {"f": "f"}},
            "free": {"k_s": {"initial": "50 bar", "lower": "5 bar", "upper": "500 bar"}}}
    path = tmp_path / "exp.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def refused(tmp_path, capsys, path: Path, pattern: str) -> None:
    code = cli.main(["calibrate", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert re.fullmatch(pattern, err), err
    assert not (tmp_path / "out").exists()


# ---------------------------------------------------------------- a group table's column of no known dimension
def test_a_group_table_column_in_a_unit_its_readers_refuse_is_refused(tmp_path, capsys):
    path = experiment(tmp_path, "setting,f [mm]\n1,0\n2,100\n")
    refused(tmp_path, capsys, path, rf"vphs: {re.escape(str(tmp_path / 'table.csv'))}:1:2: column 'f \[mm\]': "
            r"a length, but it sets f \(group_table\.columns\.f in exp\.yaml\), and with f in m, relief\.p_set: "
            r"wrong unit: .*")


def test_a_group_table_column_without_a_unit_where_its_readers_need_one_is_refused(tmp_path, capsys):
    """In ``p_set + f`` the bare number f is a pressure: a column without a unit would be read as Pa."""
    path = experiment(tmp_path, "setting,f\n1,0\n2,2\n", setting="p_set + f")
    refused(tmp_path, capsys, path, rf"vphs: {re.escape(str(tmp_path / 'table.csv'))}:1:2: column 'f' has no unit, "
            r"but it sets f \(group_table\.columns\.f in exp\.yaml\), and with f a plain number, relief\.p_set: "
            r"wrong unit: .*: write the unit in brackets")


@pytest.mark.parametrize("table, values", [("setting,f\n1,0\n2,0.1\n", (0.0, 0.1)),
                                           ("setting,f [%]\n1,0\n2,10\n", (0.0, 0.1))])
def test_a_group_table_column_its_readers_allow_is_converted_with_its_unit(tmp_path, table, values):
    exp = load_experiment(experiment(tmp_path, table))
    assert [exp.groups[g]["f"] for g in ("1", "2")] == pytest.approx(list(values))


# ---------------------------------------------------------------- a decimal comma beside a grouping column
def test_a_decimal_comma_beside_a_grouping_column_is_not_a_label(tmp_path):
    path = tmp_path / "points.csv"
    path.write_text('setting,ratio,p1 [bar]\n1,2.5,40\n1,"1,5",50\n')
    with pytest.raises(DataFileError) as caught:
        read_table(path, group="setting")
    assert str(caught.value) == (f"{path}:3:2: column 'ratio': '1,5' is not a number (a decimal comma? numbers "
                                 f"are read with a '.')")


def test_a_column_of_labels_beside_a_grouping_column_stays_text(tmp_path):
    """A column with a cell that is text and not a number with a comma is still a column of labels."""
    path = tmp_path / "points.csv"
    path.write_text('setting,note,p1 [bar]\n1,"1,5",40\n1,+1 turn,50\n')
    assert read_table(path, group="setting").text == {"note": ["1,5", "+1 turn"]}


# ---------------------------------------------------------------- a repeats: column of text
REPEATS = {"netlist": str(RIG), "data": "data.csv", "group": "setting", "repeats": "point",
           "inputs": {"Q": {"parameter": "Q_in", "noise": "0.5 l/min"}},
           "outputs": {"p1": {"signal": "p1", "noise": "repeats"}},
           "groups": {"1": {"p_set": "30 bar"}},
           "free": {"k_s": {"initial": "50 bar", "lower": "5 bar", "upper": "500 bar"}}}


@pytest.mark.parametrize("cell, line, pattern", [
    ("b", 4, r"'b' is not a number: the experiment's repeats: column numbers the repeated points \(rows of a "
             r"group with the same number are one operating point set up again\)"),
    ('"2,0"', 4, r"'2,0' is not a number \(a decimal comma\? numbers are read with a '\.'\)"),
])
def test_a_repeats_column_with_a_text_cell_names_that_cell(tmp_path, capsys, cell, line, pattern):
    (tmp_path / "data.csv").write_text(f"setting,point,Q [l/min],p1 [bar]\n1,1,20,40\n1,1,20,40.2\n"
                                       f"1,{cell},40,50\n")
    path = tmp_path / "exp.yaml"
    path.write_text(yaml.safe_dump(REPEATS, sort_keys=False))
    refused(tmp_path, capsys, path, rf"vphs: {re.escape(str(tmp_path / 'data.csv'))}:{line}:2: column 'point': "
            + pattern)
