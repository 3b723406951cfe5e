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
    "from after to": (["--t-from", "0.4 s", "--t-to", "0.3 s"], "vphs: --t-from 0.4 s is not before --t-to 0.3 s"),
    "equal": (["--t-from", "0.4", "--t-to", "400 ms"], "vphs: --t-from 0.4 s is not before --t-to 0.4 s"),
    "to after the end": (["--t-to", "1 s"], "vphs: --t-to 1 s is after the end of the simulated curve in {sim} "
                                            "(0 .. 0.5 s)"),
    "from at the end": (["--t-from", "0.5 s"], "vphs: --t-from 0.5 s is at or after the end of the simulated "
                                               "curve in {sim} (0 .. 0.5 s)"),
    "from before the start": (["--t-from", "-1 s"], "vphs: --t-from -1 s is before the start of the simulated "
                                                    "curve in {sim} (0 .. 0.5 s)"),
    "unparsable": (["--t-from", "soon"], "vphs: --t-from 'soon': 'soon' is not '<number> <unit>'"),
    "wrong unit": (["--t-to", "2 bar"], "vphs: --t-to '2 bar': wrong unit 'bar'"),
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


# ---- review 25, findings 3, 5 and 6: the window is the run's own curve between its ends -------------------
SIM_MS = ("t [ms],x [mm],p [bar]\n"  # SIM, its t in ms
          "0,50,10\n100,49.99999957,10\n200,49.9999991,10\n"
          "300,60,20\n400,70,30\n500,80,40\n")


@pytest.mark.parametrize("window", [["--t-from", "0.32"], ["--t-from", "0.32", "--t-to", "0.48"]],
                         ids=["from", "from and to"])
def test_reference_times_between_samples_of_the_window_are_compared(tmp_path, capsys, window):
    # 0.35 s and 0.45 s are inside the run and the window, but only 0.4 s (and 0.5 s) of the samples: p there
    # is the run's interpolation, 25 and 35 bar, against 26 and 35: errors -1 and 0
    sim, ref = write(tmp_path / "sim.csv", SIM_MS), write(tmp_path / "ref.csv", REF_PT)
    out = tmp_path / "table.csv"
    code, stdout, err = run(capsys, "diff", sim, ref, "--y", "p", *window, "-o", out)
    assert code == 0, err
    end = "0.48" if "--t-to" in window else "0.5"
    assert f"compared over t 0.32 .. {end} s; 1 reference point outside it left out" in stdout
    (row,) = list(csv.DictReader(open(out)))
    assert row["n"] == "2"
    assert float(row["rmse"]) == pytest.approx(0.5 ** 0.5, rel=1e-9)
    assert float(row["mean_error"]) == pytest.approx(-0.5, rel=1e-9)
    assert float(row["max_abs_error"]) == pytest.approx(1.0, rel=1e-9)
    assert float(row["x_at_max"]) == pytest.approx(0.35, rel=1e-9)


def test_a_window_along_x_ends_where_the_run_was_at_its_ends(tmp_path, capsys):
    # 0.35 .. 0.45 s holds one sample (0.4 s: x 70, p 30); its ends are the run at 0.35 s (x 65, p 25) and
    # 0.45 s (x 75, p 35): p at x = 65 and 75 is 25 and 35 against 24 and 36, errors +1 and -1
    sim, ref = write(tmp_path / "sim.csv", SIM_MS), write(tmp_path / "ref.csv", REF_PX)
    out = tmp_path / "table.csv"
    code, stdout, err = run(capsys, "diff", sim, ref, "--x", "x", "--t-from", "0.35", "--t-to", "450 ms", "-o", out)
    assert code == 0, err
    assert "compared over t 0.35 .. 0.45 s\n" in stdout
    (row,) = list(csv.DictReader(open(out)))
    assert row["n"] == "2" and float(row["rmse"]) == pytest.approx(1.0, rel=1e-9)
    assert float(row["mean_error"]) == pytest.approx(0.0, abs=1e-9)


def test_a_window_along_x_takes_no_point_from_outside_it(tmp_path, capsys):
    # the run at 0.25 s is half way from (0.2 s: x 49.9999991) to (0.3 s: x 60), x = 54.99999955: the curve
    # along x starts there, not at the sample before the window (whose x, 49.9999991, would take in x = 52)
    sim, ref = write(tmp_path / "sim.csv", SIM_MS), write(tmp_path / "ref.csv", "x [mm],p [bar]\n52,12\n")
    code, _, err = run(capsys, "diff", sim, ref, "--x", "x", "--t-from", "0.25")
    assert code == 2
    assert err.strip() == (f"vphs: {ref}:2:1: column 'x [mm]': x = 52 mm is outside the simulated range 55 .. 80 mm "
                           f"({sim}, in the window t 0.25 .. 0.5 s); no extrapolation"), err


def test_a_window_between_two_samples_is_the_run_between_them(tmp_path, capsys):
    # no sample in 0.31 .. 0.39 s: the curve is the run from x 61 (p 21) to x 69 (p 29); 65 mm gives 25 bar
    sim, ref = write(tmp_path / "sim.csv", SIM), write(tmp_path / "ref.csv", "x [mm],p [bar]\n65,24\n")
    code, stdout, err = run(capsys, "diff", sim, ref, "--x", "x", "--t-from", "0.31", "--t-to", "0.39")
    assert code == 0, err
    assert stdout.splitlines()[-1].split()[:5] == ["p", "bar", "1", "1", "1"], stdout


def test_a_window_needs_t_increasing_and_says_where_it_is_not(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", "t [s],x [mm],p [bar]\n0,60,20\n0.2,70,30\n0.1,80,40\n")
    ref = write(tmp_path / "ref.csv", REF_PX)
    code, _, err = run(capsys, "diff", sim, ref, "--x", "x", "--t-from", "0.05")
    assert code == 2
    assert err.strip() == (f"vphs: {sim}:4:1: column 't [s]': t must be strictly increasing to take a window "
                           f"(--t-from/--t-to): 0.1 after 0.2 (decreasing)"), err


def test_a_window_of_runs_by_group_cuts_each_run(tmp_path, capsys):
    # two runs (setting A, B), each 0 .. 2 s; from 0.25 s on: A at 0.5 s gives p 5 (against 6: -1), B at
    # 1.5 s gives 30 (against 29: +1); the window is each run's own from 0.25 s
    sim = write(tmp_path / "sim.csv", "setting,t [s],p [bar]\nA,0,0\nA,1,10\nA,2,20\nB,0,0\nB,1,20\nB,2,40\n")
    ref = write(tmp_path / "ref.csv", "setting,t [s],p [bar]\nA,0.5,6\nB,1.5,29\nA,0.1,0\n")
    out = tmp_path / "table.csv"
    code, stdout, err = run(capsys, "diff", sim, ref, "--t-from", "0.25", "-o", out)
    assert code == 0, err
    assert "1 reference point outside it left out" in stdout
    rows = {r["group"]: r for r in csv.DictReader(open(out))}
    assert rows["all"]["n"] == "2" and float(rows["all"]["rmse"]) == pytest.approx(1.0, rel=1e-9)
    assert float(rows["A"]["mean_error"]) == pytest.approx(-1.0, rel=1e-9)
    assert float(rows["B"]["mean_error"]) == pytest.approx(1.0, rel=1e-9)


def test_a_window_from_minus_zero_is_said_from_zero(tmp_path, capsys):
    sim, ref = write(tmp_path / "sim.csv", SIM), write(tmp_path / "ref.csv", REF_PT)
    code, stdout, err = run(capsys, "diff", sim, ref, "--y", "p", "--t-from", "-0")
    assert code == 0, err
    assert "compared over t 0 .. 0.5 s\n" in stdout, stdout


def test_the_monotonicity_error_says_when_in_the_files_unit_of_time(tmp_path, capsys):
    sim, ref = write(tmp_path / "sim.csv", SIM_MS), write(tmp_path / "ref.csv", REF_PX)
    code, _, err = run(capsys, "diff", sim, ref, "--x", "x")
    assert code == 2
    assert err.strip() == (f"vphs: {sim}:3:2: column 'x [mm]': x must be strictly increasing in the simulated "
                           f"curve: 49.9999996 after 50 (decreasing, at t = 100 ms)"), err


def test_an_empty_window_is_refused_in_one_place():
    from blocks.compare import window_problem

    assert window_problem(0.4, 0.3) == "--t-from 0.4 s is not before --t-to 0.3 s"
    assert window_problem(0.4, 0.3, 0.0, 0.5, "a run") == "--t-from 0.4 s is not before --t-to 0.3 s"
    assert window_problem(-0.0, None, 0.1, 0.5, "a run") == "--t-from 0 s is before the start of a run (0.1 .. 0.5 s)"
    assert window_problem(0.2, 0.3) is None
