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
- A second Ctrl-C while an interrupted calibration's output folder was being put back stopped that half-way:
  part of the unfinished run's files left beside none of the previous run's (hidden in .previous); and a
  second one while a set of result files was being given up left their staged (half-written) files in the
  folder. Both clean-ups now run to their end before the interrupt is taken (blocks.interrupt.deferred).
"""

from __future__ import annotations

import os
import re
import signal
from pathlib import Path

import pytest
import yaml

import cli
from blocks import interrupt, result
from blocks.calibrate import output
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


# ---------------------------------------------------------------- a second Ctrl-C during the clean-up
def tree(folder: Path) -> dict[str, str]:
    """Every file under ``folder`` (hidden ones too) by relative path, with its text."""
    return {str(p.relative_to(folder)): p.read_text() for p in sorted(folder.rglob("*")) if p.is_file()}


def ctrl_c_again(monkeypatch, owner, name: str, after=None) -> list:
    """``owner.name`` replaced by a call that first receives a Ctrl-C (a real SIGINT, as a terminal sends
    it), the first time it is called: the user pressing Ctrl-C again while the clean-up runs. ``after``: the
    Ctrl-C comes instead just after the first call whose arguments ``after`` accepts."""
    real, calls, sent = getattr(owner, name), [], []

    def ctrl_c() -> None:
        if not sent:
            sent.append(True)
            os.kill(os.getpid(), signal.SIGINT)

    def again(*args, **kwargs):
        if after is None:
            ctrl_c()
        calls.append(args)
        done = real(*args, **kwargs)
        if after is not None and after(*args):
            ctrl_c()
        return done

    monkeypatch.setattr(owner, name, again)
    return calls


def test_a_second_ctrl_c_while_an_interrupted_run_is_undone_leaves_the_previous_output_whole(tmp_path,
                                                                                             monkeypatch):
    out = tmp_path / "out"
    (out / "round1").mkdir(parents=True)
    (out / "round1" / "augmented.yaml").write_text("previous round 1\n")
    (out / "report.md").write_text("previous report\n")
    (out / "notes.txt").write_text("the user's\n")
    before = tree(out)
    calls = ctrl_c_again(monkeypatch, output, "_remove")
    with pytest.raises(KeyboardInterrupt):
        with interrupt.handling(), output.replacing(out):
            for k in (1, 2, 3):
                (out / f"round{k}").mkdir()
                (out / f"round{k}" / "augmented.yaml").write_text(f"unfinished round {k}\n")
            raise KeyboardInterrupt  # the first Ctrl-C, mid-run
    assert tree(out) == before and sorted(p.name for p in out.iterdir()) == ["notes.txt", "report.md", "round1"]
    assert len(calls) == 3  # the run's three rounds deleted, the second Ctrl-C taken after


def test_a_second_ctrl_c_while_staged_results_are_given_up_leaves_no_half_written_file(tmp_path, monkeypatch):
    (tmp_path / "report.md").write_text("previous\n")

    def interrupted(tmp):
        tmp.write_text("half a plo")
        raise KeyboardInterrupt  # the first Ctrl-C, while the second file is written

    calls = ctrl_c_again(monkeypatch, Path, "unlink")
    with pytest.raises(KeyboardInterrupt):
        with interrupt.handling():
            result.write_together((tmp_path / "report.md", lambda tmp: tmp.write_text("new\n")),
                                  (tmp_path / "fit.png", interrupted))
    assert tree(tmp_path) == {"report.md": "previous\n"}
    assert len(calls) == 2  # both staged files removed, the second Ctrl-C taken after


def test_a_ctrl_c_just_as_the_previous_output_is_set_aside_puts_it_back(tmp_path, monkeypatch):
    """Interrupted after the last rename of moving aside (.previous.partial -> .previous), before the run."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.md").write_text("previous report\n")
    ctrl_c_again(monkeypatch, Path, "rename", after=lambda path, target: Path(target).name == output.PREVIOUS)
    with pytest.raises(KeyboardInterrupt):
        with interrupt.handling(), output.replacing(out):
            pytest.fail("the run started")
    assert tree(out) == {"report.md": "previous report\n"}
