"""Fuzzer round s20: a group table's units and rows, a free parameter's step, and SIGTERM (vphs calibrate).

- A ``group_table`` column in kg setting a pressure, or one without a unit, was read in SI (95.4 Pa for a
  crack pressure meant in bar); a data column of the wrong unit was refused already, the table's now is.
- Two rows for one group were taken (the last won, silently); an empty cell set the parameter to NaN.
- ``free: {k: {step: -1}}`` (or 0, or ``true``: 1 in SI) ran the fit.
- SIGTERM killed the process outright, leaving round1/ and experiment_augmented.yaml half-written; it now
  stops the command as Ctrl-C does, for every command (the handling is shared: blocks/interrupt.py), exit 143.
"""

from __future__ import annotations

import os
import re
import signal
from pathlib import Path

import pytest
import yaml

import cli
from blocks import interrupt
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


# ---------------------------------------------------------------- SIGTERM
@pytest.fixture
def sigterm_guard():
    """Without the handling, a SIGTERM sent to the test process would end it: here it raises instead, which the
    command reports as an internal error (exit 1), so the test fails rather than the run dying."""
    class Unhandled(Exception):
        pass

    def unhandled(signum, frame):
        raise Unhandled("SIGTERM not handled by the command")

    previous = signal.signal(signal.SIGTERM, unhandled)
    yield
    signal.signal(signal.SIGTERM, previous)


def _terminated_mid_run(monkeypatch, swallow: bool = False):
    """Replace the fit by one that writes a round's files, then receives SIGTERM (swallowed, as a ctypes
    callback would, if ``swallow``: the command must stop at its next check all the same)."""
    import blocks.calibrate.run as run

    def fit(exp, out, progress=None, warn=None):
        (Path(out) / "round1").mkdir()
        (Path(out) / "round1" / "screening.yaml").write_text("half")
        (Path(out) / "experiment_augmented.yaml").write_text("half")
        try:
            os.kill(os.getpid(), signal.SIGTERM)
        except KeyboardInterrupt:
            if not swallow:
                raise
        interrupt.check()  # as the fit does after each compiled integration
        pytest.fail("the command went on after a SIGTERM")

    monkeypatch.setattr(run, "calibrate", fit)


@pytest.mark.parametrize("swallow", [False, True])
def test_sigterm_stops_calibrate_as_ctrl_c_does(tmp_path, capsys, monkeypatch, sigterm_guard, swallow):
    path = files(tmp_path)
    _terminated_mid_run(monkeypatch, swallow)
    code, err = calibrate(tmp_path, capsys, path)
    assert (code, err) == (143, "vphs: terminated; nothing half-written was left behind")
    assert not (tmp_path / "out").exists()


def test_sigterm_puts_the_previous_output_back(tmp_path, capsys, monkeypatch, sigterm_guard):
    path = files(tmp_path)
    out = tmp_path / "out"
    (out / "round1").mkdir(parents=True)
    (out / "round1" / "screening.yaml").write_text("old")
    (out / "report.md").write_text("old report")
    _terminated_mid_run(monkeypatch)
    code, err = calibrate(tmp_path, capsys, path)
    assert code == 143 and err == "vphs: terminated; nothing half-written was left behind"
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*")) == ["report.md", "round1", "round1/screening.yaml"]
    assert (out / "round1" / "screening.yaml").read_text() == "old"


def test_sigterm_stops_vphs_run_too(tmp_path, capsys, monkeypatch, sigterm_guard):
    """The handling is main()'s, shared by every command: vphs run during compilation, nothing written."""
    from blocks.circuit import Circuit

    def compile_and_stop(self, quiet=True):
        os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(Circuit, "compile", compile_and_stop)
    step = ROOT / "tests" / "circuits" / "netlists" / "second_order_step.yaml"
    code = cli.main(["run", str(step), "-q", "-o", str(tmp_path / "r.csv")])
    assert code == 143 and capsys.readouterr().err.strip() == "vphs: terminated; nothing half-written was left behind"
    assert not (tmp_path / "r.csv").exists()


def test_a_system_error_from_a_terminated_compiled_call_exits_143(tmp_path, capsys, monkeypatch):
    import blocks.solve.run as run

    def terminated_call(*args, **kwargs):
        try:
            raise interrupt.Terminated
        except KeyboardInterrupt as inner:
            raise SystemError("returned a result with an exception set") from inner

    monkeypatch.setattr(run, "_solve_compiled", terminated_call)
    step = ROOT / "tests" / "circuits" / "netlists" / "second_order_step.yaml"
    code = cli.main(["run", str(step), "-q", "-o", str(tmp_path / "r.csv")])
    assert code == 143 and "vphs: terminated; nothing half-written" in capsys.readouterr().err


def test_a_sigterm_ignored_at_the_start_stays_ignored():
    previous = signal.signal(signal.SIGTERM, signal.SIG_IGN)
    try:
        with interrupt.handling():
            assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
        assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGTERM, previous)


def test_sigterm_during_the_renames_of_results_is_taken_after_them(tmp_path, monkeypatch, sigterm_guard):
    """write_together holds a SIGTERM, as it holds Ctrl-C, until every target is in place."""
    from blocks import result

    real = os.replace
    moved = []

    def replace_then_term(src, dst):
        real(src, dst)
        moved.append(dst)
        if len(moved) == 1:
            os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(os, "replace", replace_then_term)
    with interrupt.handling():
        with pytest.raises(interrupt.Terminated):
            result.write_together((tmp_path / "a.csv", lambda tmp: Path(tmp).write_text("a")),
                                  (tmp_path / "b.png", lambda tmp: Path(tmp).write_text("b")))
    assert (tmp_path / "a.csv").read_text() == "a" and (tmp_path / "b.png").read_text() == "b"
