"""``vphs diff --t-from/--t-to`` (a time window of the run) and the monotonicity error's digits (review 25).

A lift after a hold: during the hold the rod creeps back by a few micrometres, so x is not increasing over
the whole run and a comparison against x is refused; the window that leaves the hold out is compared.
Expected numbers are worked out by hand from the points written here.
"""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from test_diff import run, write

ROOT = Path(__file__).resolve().parents[2]
DRIVE_LINE = ROOT / "netlists" / "examples" / "drive_line.yaml"

# hold (x creeps 50 -> 49.99999957 -> 49.9999991) from t = 0 to 0.2, then lift x = 50 + 100 (t - 0.2)... sampled
SIM = ("t [s],x [mm],p [bar]\n"
       "0,50,10\n0.1,49.99999957,10\n0.2,49.9999991,10\n"
       "0.3,60,20\n0.4,70,30\n0.5,80,40\n")
# p along the stroke: at x = 65 the lift gives 25 bar (error +1), at x = 75, 35 bar (error -1)
REF_PX = "x [mm],p [bar]\n65,24\n75,36\n"
# p in time: 0.1 s (hold, 10) and 0.35 s (25), 0.45 s (35); only the last two lie in 0.3 .. 0.5 s
REF_PT = "# in time\nt [s],p [bar]\n0.1,11\n0.35,26\n0.45,35\n"




def test_the_monotonicity_error_tells_the_values_apart_and_says_when(tmp_path, capsys):
    sim, ref = write(tmp_path / "sim.csv", SIM), write(tmp_path / "ref.csv", REF_PX)
    code, _, err = run(capsys, "diff", sim, ref, "--x", "x")
    assert code == 2
    assert err.strip() == (f"vphs: {sim}:3:2: column 'x [mm]': x must be strictly increasing in the simulated "
                           f"curve: 49.9999996 after 50 (decreasing, at t = 0.1 s)"), err


def test_a_window_leaves_the_hold_out(tmp_path, capsys):
    sim, ref = write(tmp_path / "sim.csv", SIM), write(tmp_path / "ref.csv", REF_PX)
    out = tmp_path / "table.csv"
    code, stdout, err = run(capsys, "diff", sim, ref, "--x", "x", "--t-from", "300 ms", "-o", out)
    assert code == 0, err
    assert "compared over t 0.3 .. 0.5 s" in stdout
    (row,) = list(csv.DictReader(open(out)))
    assert row["n"] == "2" and float(row["rmse"]) == pytest.approx(1.0, rel=1e-9)
    assert float(row["mean_error"]) == pytest.approx(0.0, abs=1e-9)


def test_a_window_on_t_takes_only_the_reference_points_in_it(tmp_path, capsys):
    sim, ref = write(tmp_path / "sim.csv", SIM), write(tmp_path / "ref.csv", REF_PT)
    out = tmp_path / "table.csv"
    code, stdout, err = run(capsys, "diff", sim, ref, "--y", "p", "--t-from", "0.3", "--t-to", "0.5 s", "-o", out)
    assert code == 0, err
    assert "compared over t 0.3 .. 0.5 s; 1 reference point outside it left out" in stdout
    (row,) = list(csv.DictReader(open(out)))
    assert row["n"] == "2"  # errors -1 (0.35 s) and 0 (0.45 s)
    assert float(row["mean_error"]) == pytest.approx(-0.5, rel=1e-9)
    assert float(row["max_abs_error"]) == pytest.approx(1.0, rel=1e-9)
    assert float(row["x_at_max"]) == pytest.approx(0.35, rel=1e-9)


def test_a_reference_point_outside_the_window_names_it(tmp_path, capsys):
    sim, ref = write(tmp_path / "sim.csv", SIM), write(tmp_path / "ref.csv", REF_PX)
    code, _, err = run(capsys, "diff", sim, ref, "--x", "x", "--t-from", "0.3", "--t-to", "0.4")
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "outside the simulated range" in err and "in the window t 0.3 .. 0.4 s" in err, err


BAD_WINDOWS = {
    "from after to": (["--t-from", "0.4 s", "--t-to", "0.3 s"], "vphs: --t-from '0.4 s' is not before --t-to '0.3 s'"),
    "equal": (["--t-from", "0.4", "--t-to", "400 ms"], "vphs: --t-from '0.4' is not before --t-to '400 ms'"),
    "to after the end": (["--t-to", "1 s"], "vphs: --t-to 1 s is after the end of the simulated curve in {sim} "
                                            "(0 .. 0.5 s)"),
    "from at the end": (["--t-from", "0.5 s"], "vphs: --t-from 0.5 s is at or after the end of the simulated "
                                               "curve in {sim} (0 .. 0.5 s)"),
    "from before the start": (["--t-from", "-1 s"], "vphs: --t-from -1 s is before the start of the simulated "
                                                    "curve in {sim} (0 .. 0.5 s)"),
    "unparsable": (["--t-from", "soon"], "vphs: --t-from 'soon': 'soon' is not '<number> <unit>'"),
    "wrong unit": (["--t-to", "2 bar"], "vphs: --t-to '2 bar': wrong unit 'bar'"),
    "one sample": (["--t-from", "0.31", "--t-to", "0.39"], "vphs: --t-from/--t-to: the window t 0.31 .. 0.39 s "
                                                           "holds 0 simulated samples (at least two are needed)"),
    "t-end with a CSV": (["--t-end", "1 s"], "vphs: --t-end applies only when SIMULATED is a netlist"),
}


@pytest.mark.parametrize("case", list(BAD_WINDOWS), ids=list(BAD_WINDOWS))
def test_bad_windows_are_one_line_and_exit_2(tmp_path, capsys, case):
    extra, expected = BAD_WINDOWS[case]
    sim, ref = write(tmp_path / "sim.csv", SIM), write(tmp_path / "ref.csv", REF_PX)
    out = write(tmp_path / "table.csv", "previous good table\n")
    code, stdout, err = run(capsys, "diff", sim, ref, "--x", "x", "-o", out, *extra)
    assert code == 2 and stdout == ""
    (line,) = err.strip().splitlines()
    assert line.startswith(expected.format(sim=sim)), line
    assert out.read_text() == "previous good table\n"


def test_a_csv_without_t_has_no_window(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", "x [mm],p [bar]\n60,20\n70,30\n80,40\n")
    ref = write(tmp_path / "ref.csv", REF_PX)
    code, _, err = run(capsys, "diff", sim, ref, "--x", "x", "--t-from", "0.3")
    assert code == 2 and err.strip().startswith(f"vphs: --t-from/--t-to: {sim} has no column 't'"), err


def test_a_netlist_window_is_checked_against_its_run_before_it(tmp_path, capsys, monkeypatch):
    from blocks.circuit import Circuit

    def no_run(*a, **k):
        raise AssertionError("the netlist was run")

    monkeypatch.setattr(Circuit, "simulate", no_run)
    ref = write(tmp_path / "ref.csv", "t [s],speed [rpm]\n0.1,1\n")
    code, _, err = run(capsys, "diff", DRIVE_LINE, ref, "--t-end", "0.2 s", "--t-to", "0.3 s")
    assert code == 2
    assert err.strip() == (f"vphs: --t-to 0.3 s is after the end of the run of {DRIVE_LINE} with --t-end "
                           f"(0 .. 0.2 s)"), err


def test_rows_taken_from_a_run_keep_their_sample_numbers():
    import numpy as np

    from blocks.datafile import Table

    run_table = Table(file="run.yaml", columns={"t": np.arange(5.0), "x": np.arange(5.0)}, units={"t": "s", "x": "m"})
    window = run_table.rows(np.array([2, 3, 4])).rows(np.array([1, 2]))
    assert str(window.error("bad", "x", 0)) == "run.yaml: sample 4: column 'x [m]': bad"
