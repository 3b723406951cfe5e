"""``vphs diff``: a simulated curve against reference points (blocks/compare.py, blocks/datafile.py).

Expected statistics are worked out by hand in each test from the points written there (linear
interpolation of the simulated polyline, error = simulated - reference, in the reference's units); the
netlist case checks the drive line against points taken from the golden traces of the independent
hand-written model (tests/golden), with the golden test's tolerances.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

import cli
from blocks.compare import compare
from blocks.datafile import DataFileError, read_table

ROOT = Path(__file__).resolve().parents[2]
DRIVE_LINE = ROOT / "netlists" / "examples" / "drive_line.yaml"
GOLDEN = ROOT / "tests" / "golden" / "drive_line_1l.csv"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

# simulated y = t^2 sampled at t = 0..4: the linear interpolation is NOT t^2 between samples
SIM_SQUARE = "t [s],y [bar]\n0,0\n1,1\n2,4\n3,9\n4,16\n"
# at t = 0.5, 1.25, 2, 3.5 the polyline gives 0.5, 1.75, 4, 12.5; errors -0.5, 0, +1, -1.5
REF_SQUARE = "# hand-made reference\nt [s],y [bar]\n0.5,1.0\n1.25,1.75\n2,3.0\n3.5,14.0\n"


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def run(capsys, *argv) -> tuple[int, str, str]:
    code = cli.main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def read_rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


# ---------------------------------------------------------------- statistics by hand
def test_known_curve_against_known_points(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", SIM_SQUARE)
    ref = write(tmp_path / "ref.csv", REF_SQUARE)
    out = tmp_path / "table.csv"
    code, stdout, stderr = run(capsys, "diff", sim, ref, "-o", out)
    assert code == 0, stderr
    errors = [-0.5, 0.0, 1.0, -1.5]
    (row,) = read_rows(out)  # written with 10 significant digits: compared to rel 1e-9
    assert row["curve"] == "y" and row["unit"] == "bar" and row["n"] == "4" and row["group"] == "all"
    assert float(row["rmse"]) == pytest.approx(math.sqrt(sum(e * e for e in errors) / 4), rel=1e-9)  # sqrt(0.875)
    assert float(row["mean_error"]) == pytest.approx(-0.25, rel=1e-9)
    assert float(row["max_abs_error"]) == pytest.approx(1.5, rel=1e-9)
    assert float(row["x_at_max"]) == pytest.approx(3.5, rel=1e-9)
    assert row["x"] == "t" and row["x_unit"] == "s"
    # the same numbers on stdout, in the reference's unit
    line = next(l for l in stdout.splitlines() if l.startswith("y "))
    assert line.split() == ["y", "bar", "4", f"{math.sqrt(0.875):.4g}", "-0.25", "1.5", "3.5"]


def test_python_api_gives_the_interpolated_points(tmp_path):
    comparison = compare(read_table(write(tmp_path / "s.csv", SIM_SQUARE)),
                         read_table(write(tmp_path / "r.csv", REF_SQUARE)))
    (curve,) = comparison.curves
    assert np.allclose(curve.y_at_ref, [0.5, 1.75, 4.0, 12.5], rtol=0, atol=1e-12)
    assert np.allclose(curve.error, [-0.5, 0.0, 1.0, -1.5], rtol=0, atol=1e-12)


def test_reference_points_at_the_ends_of_the_simulated_range(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", SIM_SQUARE)
    ref = write(tmp_path / "ref.csv", "t [s],y [bar]\n0,1\n4,15\n")  # errors -1, +1
    out = tmp_path / "t.csv"
    code, _, stderr = run(capsys, "diff", sim, ref, "-o", out)
    assert code == 0, stderr
    (row,) = read_rows(out)
    assert float(row["rmse"]) == pytest.approx(1.0) and float(row["mean_error"]) == pytest.approx(0.0, abs=1e-12)
    assert float(row["x_at_max"]) == 0.0  # a tie: the first point


def test_empty_reference_cells_are_left_out(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", "t [s],a [bar],b [bar]\n0,0,0\n2,2,20\n")
    ref = write(tmp_path / "ref.csv", "t [s],a [bar],b [bar]\n0.5,1.5,\n1,,13\n1.5,1.0,14\n")
    out = tmp_path / "t.csv"
    code, stdout, stderr = run(capsys, "diff", sim, ref, "-o", out)
    assert code == 0, stderr
    # the table says how many rows each curve left out (review: "n = 1" and no word of the dropped row)
    assert stdout.splitlines()[-2:] == ["1 row with an empty cell in a left out",
                                        "1 row with an empty cell in b left out"], stdout
    rows = {r["curve"]: r for r in read_rows(out)}
    # a: t = 0.5, 1.5 -> sim 0.5, 1.5; errors -1, +0.5
    assert rows["a"]["n"] == "2" and float(rows["a"]["rmse"]) == pytest.approx(math.sqrt((1 + 0.25) / 2))
    # b: t = 1, 1.5 -> sim 10, 15; errors -3, +1
    assert rows["b"]["n"] == "2" and float(rows["b"]["max_abs_error"]) == pytest.approx(3.0)
    assert float(rows["b"]["x_at_max"]) == pytest.approx(1.0)


def test_groups_get_rows_of_their_own(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", "Q [l/min],p [bar]\n0,10\n100,30\n")  # p = 10 + 0.2 Q
    ref = write(tmp_path / "ref.csv", "setting,Q [l/min],p [bar]\n"
                                      "1,10,13\n1,50,20\n2,20,14\n2,80,25\n")  # errors -1, 0 | 0, +1
    out = tmp_path / "t.csv"
    code, stdout, stderr = run(capsys, "diff", sim, ref, "--x", "Q", "-o", out)
    assert code == 0, stderr
    rows = {r["group"]: r for r in read_rows(out)}
    assert set(rows) == {"all", "1", "2"}
    assert rows["all"]["n"] == "4" and float(rows["all"]["rmse"]) == pytest.approx(math.sqrt(2 / 4))
    assert float(rows["1"]["mean_error"]) == pytest.approx(-0.5) and float(rows["1"]["x_at_max"]) == 10
    assert float(rows["2"]["mean_error"]) == pytest.approx(0.5) and float(rows["2"]["x_at_max"]) == 80
    assert rows["all"]["x"] == "Q" and rows["all"]["x_unit"] == "l/min"
    assert "group" in stdout.splitlines()[1]


def test_a_reference_column_that_lost_its_unit_is_not_taken_for_groups(tmp_path, capsys):
    """A user review: 'x' written without its unit became the grouping column, split p into a group per x
    value and was itself never compared, with no word."""
    sim = write(tmp_path / "sim.csv", "t [s],x [mm],p [bar]\n0,0,10\n1,100,30\n")
    ref = write(tmp_path / "ref.csv", "t [s],x,p [bar]\n0.5,50,20\n0.8,80,26\n")
    code, stdout, stderr = run(capsys, "diff", sim, ref)
    assert code == 2 and stdout == "" and len(stderr.strip().splitlines()) == 1
    assert "ref.csv:1:2: column 'x': has no unit, so it only labels groups of points, yet the simulation has a " \
           "signal 'x': to compare it, write its unit ('x [mm]')" in stderr


# ---------------------------------------------------------------- units
def test_units_are_converted_into_the_references(tmp_path, capsys):
    # simulated in bar and l/min against a reference in Pa, m^3/s and ms
    sim = write(tmp_path / "sim.csv", "t [s],p [bar],Q [l/min]\n0,100,60\n1,200,120\n")
    # at t = 500 ms: p 150 bar = 1.5e7 Pa (ref 1.4e7: error +1e6 Pa); Q 90 l/min = 1.5e-3 m^3/s (ref 1.6e-3)
    ref = write(tmp_path / "ref.csv", "t [ms],p [Pa],Q [m^3/s]\n500,1.4e7,1.6e-3\n")
    out = tmp_path / "t.csv"
    code, _, stderr = run(capsys, "diff", sim, ref, "-o", out)
    assert code == 0, stderr
    rows = {r["curve"]: r for r in read_rows(out)}
    assert rows["p"]["unit"] == "Pa" and float(rows["p"]["mean_error"]) == pytest.approx(1.0e6, rel=1e-9)
    assert rows["Q"]["unit"] == "m^3/s" and float(rows["Q"]["mean_error"]) == pytest.approx(-1.0e-4, rel=1e-9)
    assert float(rows["p"]["x_at_max"]) == pytest.approx(500.0) and rows["p"]["x_unit"] == "ms"


def test_units_the_other_way_and_renamed_curves(tmp_path, capsys):
    # simulated in SI, reference in bar and l/min, names mapped with SIM=REF
    sim = write(tmp_path / "sim.csv", "t [s],pA [Pa],qA [m^3/s]\n0,0,0\n2,4e6,2e-3\n")
    # at t = 1: 2e6 Pa = 20 bar (ref 21: error -1 bar); 1e-3 m^3/s = 60 l/min (ref 57: error +3 l/min)
    ref = write(tmp_path / "ref.csv", "time [s],p1 [bar],Q [l/min]\n1,21,57\n")
    out = tmp_path / "t.csv"
    code, stdout, stderr = run(capsys, "diff", sim, ref, "--x", "t=time", "--y", "pA=p1", "--y", "qA=Q", "-o", out)
    assert code == 0, stderr
    rows = {r["curve"]: r for r in read_rows(out)}
    assert float(rows["pA=p1"]["mean_error"]) == pytest.approx(-1.0, rel=1e-9)
    assert float(rows["qA=Q"]["mean_error"]) == pytest.approx(3.0, rel=1e-9)
    assert rows["qA=Q"]["simulated"] == "qA" and rows["qA=Q"]["reference"] == "Q"


def test_default_matching_skips_unsimulated_columns(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", SIM_SQUARE)
    ref = write(tmp_path / "ref.csv", "t [s],y [bar],z [bar]\n1,1,5\n")
    code, stdout, stderr = run(capsys, "diff", sim, ref)
    assert code == 0, stderr
    assert "not compared" in stderr and "z" in stderr
    assert [l.split()[0] for l in stdout.splitlines()[2:]] == ["y"]


# ---------------------------------------------------------------- a netlist as SIMULATED
@pytest.fixture(scope="module")
def drive_line_reference(tmp_path_factory):
    """Every 25th golden point (t = 0, 0.25, ..., 3 s) in other units: x in m, pA in MPa, speed in rad/s."""
    with open(GOLDEN) as handle:
        rows = list(csv.reader(l for l in handle if not l.startswith("#")))
    assert rows[0] == ["t [s]", "x [mm]", "pA [bar]", "pB [bar]", "speed [rad/s]"]
    data = np.array(rows[1:], dtype=float)[::25]
    assert data[-1, 0] == pytest.approx(3.0)
    path = tmp_path_factory.mktemp("ref") / "drive_line_points.csv"
    lines = ["# from tests/golden/drive_line_1l.csv, every 25th row", "t [s],x [m],pA [MPa],speed [rad/s]"]
    lines += [f"{t:.17g},{x / 1e3:.17g},{p / 10:.17g},{w:.17g}" for t, x, p, _, w in data]
    path.write_text("\n".join(lines) + "\n")
    return path, data


TOLERANCE = {"x": (0.005e-3, "m"), "pA": (0.002, "MPa"), "speed": (0.01, "rad/s")}  # as tests/golden


def test_netlist_against_golden_points(tmp_path, capsys, drive_line_reference):
    ref, data = drive_line_reference
    out = tmp_path / "t.csv"
    code, stdout, stderr = run(capsys, "diff", DRIVE_LINE, ref, "-o", out, "-q")
    assert code == 0, stderr
    rows = {r["curve"]: r for r in read_rows(out)}
    assert set(rows) == {"x", "pA", "speed"}  # matched by name; the netlist logs speed in rpm
    for name, (tol, unit) in TOLERANCE.items():
        assert rows[name]["unit"] == unit and rows[name]["n"] == str(len(data))
        assert float(rows[name]["max_abs_error"]) < tol, (name, rows[name])
        assert float(rows[name]["rmse"]) <= float(rows[name]["max_abs_error"])

    # the same statistics computed here from the circuit's own result, interpolated independently. The CLI
    # always runs in slices (with a progress callback), which steps slightly differently from one call
    # without (~1e-5 mm in x): run it the same way so that the numbers must agree to the last digits
    from blocks.circuit import Circuit

    result = Circuit.from_file(DRIVE_LINE).simulate(progress=lambda fraction, seconds: None)
    golden = {"x": data[:, 1] / 1e3, "pA": data[:, 2] / 10, "speed": data[:, 4]}
    for name, (_, unit) in TOLERANCE.items():
        e = np.interp(data[:, 0], result.t, result.in_unit(name, unit)) - golden[name]
        assert float(rows[name]["rmse"]) == pytest.approx(np.sqrt(np.mean(e**2)), rel=1e-6, abs=1e-15)
        assert float(rows[name]["max_abs_error"]) == pytest.approx(np.max(np.abs(e)), rel=1e-6, abs=1e-15)


def test_netlist_diff_sees_a_one_percent_change(tmp_path, capsys, drive_line_reference):
    """The comparison can fail: 1 % more motor displacement moves some curve beyond the golden tolerance."""
    ref, _ = drive_line_reference
    out = tmp_path / "t.csv"
    code, _, stderr = run(capsys, "diff", DRIVE_LINE, ref, "-o", out, "-q", "--set", "motors.D=60.6 cm^3/rev")
    assert code == 0, stderr
    rows = {r["curve"]: r for r in read_rows(out)}
    assert any(float(rows[n]["max_abs_error"]) > tol for n, (tol, _) in TOLERANCE.items()), rows


# ---------------------------------------------------------------- the plot
def test_plot_is_written(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", "t [s],a [bar],b [l/min]\n0,0,0\n1,1,10\n2,4,20\n")
    ref = write(tmp_path / "ref.csv", "run,t [s],a [bar],b [l/min]\nA,0.5,0.4,5\nA,1.5,2.6,16\nB,1,1.2,9\n")
    png = tmp_path / "plots" / "overlay.png"
    code, _, stderr = run(capsys, "diff", sim, ref, "--plot", png)
    assert code == 0, stderr
    data = png.read_bytes()
    assert data[:8] == PNG_SIGNATURE and len(data) > 20_000
    assert not [p for p in png.parent.iterdir() if p.name.startswith(".")], "a temporary file was left behind"


# ---------------------------------------------------------------- bad input: exit 2, located, nothing written
BAD_CASES = {
    # name: (simulated text or None for SIM_SQUARE, reference text, extra args, expected location, expected words)
    "missing reference file": (None, None, [], "{ref}: file not found", []),
    "missing reference column": (None, REF_SQUARE, ["--y", "nope"], "{ref}:2: no column 'nope'", []),
    "missing x column": (None, REF_SQUARE, ["--x", "time"], "{ref}:2: no column 'time'", []),
    "missing simulated column": (None, REF_SQUARE, ["--y", "q=y"], "{sim}:1: no simulated column 'q'", []),
    "unknown unit": (None, "t [s],y [barr]\n1,2\n", [], "{ref}:1:2: column 'y [barr]'", ["unknown unit 'barr'", "bar"]),
    "not a number": (None, "# c\nt [s],y [bar]\n1,2\n2,abc\n", [], "{ref}:4:2: column 'y [bar]'",
                     ["'abc' is not a number"]),
    "nan is not a number": (None, "t [s],y [bar]\nnan,2\n", [], "{ref}:2:1: column 't [s]'", ["'nan' is not a number"]),
    "sim not a number": ("t [s],y [bar]\n0,0\n1,x1\n", REF_SQUARE, [], "{sim}:3:2: column 'y [bar]'", ["'x1'"]),
    "unsorted simulated x": ("t [s],y [bar]\n0,0\n2,1\n1,2\n3,3\n", "t [s],y [bar]\n1,1\n",
                             [], "{sim}:4:1: column 't [s]'", ["strictly increasing", "decreasing"]),
    "repeated simulated x": ("# run\nt [s],y [bar]\n0,0\n1,1\n1,2\n3,3\n", "t [s],y [bar]\n1,1\n",
                             [], "{sim}:5:1: column 't [s]'", ["strictly increasing", "repeated"]),
    "dimension mismatch": (None, "t [s],y [l/min]\n1,2\n", [], "{ref}:1:2: column 'y [l/min]'",
                           ["does not match", "{sim}"]),
    "x dimension mismatch": (None, "t [bar],y [bar]\n1,2\n", [], "{ref}:1:1: column 't [bar]'", ["does not match"]),
    "x outside simulated range": (None, "# c\nt [s],y [bar]\n1,1\n4.5,2\n", [], "{ref}:4:1: column 't [s]'",
                                  ["outside the simulated range", "no extrapolation"]),
    "empty x cell": (None, "t [s],y [bar]\n,1\n", [], "{ref}:2:1: column 't [s]'", ["empty"]),
    "second column without unit": (None, "setting,t [s],y,z [bar]\n1,1,1,1\n", [], "{ref}:1:3:", ["'y' has no unit"]),
    "wrong number of cells": (None, "t [s],y [bar]\n1,1\n2\n", [], "{ref}:3:", ["1 cells, the header has 2"]),
    "duplicate column": (None, "t [s],y [bar],y [Pa]\n1,1,1\n", [], "{ref}:1:3:", ["appears twice"]),
    "header only comments": (None, "# nothing\n\n", [], "{ref}: no header line", []),
    "no data rows": (None, "t [s],y [bar]\n", [], "{ref}:1: no data rows", []),
    "no matching curve": (None, "t [s],w [bar]\n1,1\n", [], "{ref}:1: no reference column matches", ["--y"]),
    "grouping column as curve": (None, "run,t [s],y [bar]\na,1,1\n", ["--y", "run"], "{ref}:1:1: column 'run'",
                                 ["grouping column"]),
    "empty unit": (None, "t [s],y []\n1,1\n", [], "{ref}:1:2:", ["empty unit"]),
    "semicolons": (None, "t [s];y [bar]\n1;1\n", [], "{ref}:1:1:", ["separated by ';'", "comma-separated"]),
    "tabs": (None, "t [s]\ty [bar]\n1\t1\n", [], "{ref}:1:1:", ["separated by tabs", "comma-separated"]),
}


@pytest.mark.parametrize("case", list(BAD_CASES), ids=list(BAD_CASES))
def test_bad_input_is_one_located_line_and_exit_2(tmp_path, capsys, case):
    sim_text, ref_text, extra, where, words = BAD_CASES[case]
    sim = write(tmp_path / "sim.csv", sim_text or SIM_SQUARE)
    ref = tmp_path / "ref.csv"
    if ref_text is not None:
        write(ref, ref_text)
    out, png = tmp_path / "table.csv", tmp_path / "overlay.png"
    write(out, "previous good table\n")
    code, stdout, stderr = run(capsys, "diff", sim, ref, "-o", out, "--plot", png, *extra)
    assert code == 2, (stdout, stderr)
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    names = {"ref": ref, "sim": sim}
    assert lines[0].startswith("vphs: " + where.format(**names)), lines[0]
    for word in words:
        assert word.format(**names) in lines[0], (word, lines[0])
    assert out.read_text() == "previous good table\n", "an earlier output was overwritten"
    assert not png.exists()
    expected_files = ["sim.csv", "table.csv"] + (["ref.csv"] if ref_text else [])
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(expected_files), "a file was left behind"


def test_missing_simulated_file_and_netlist(tmp_path, capsys):
    ref = write(tmp_path / "ref.csv", REF_SQUARE)
    code, _, stderr = run(capsys, "diff", tmp_path / "gone.csv", ref)
    assert code == 2 and stderr.strip() == f"vphs: {tmp_path / 'gone.csv'}: file not found"
    code, _, stderr = run(capsys, "diff", tmp_path / "gone.yaml", ref)
    assert code == 2 and str(tmp_path / "gone.yaml") in stderr and "not found" in stderr


def test_bad_arguments(tmp_path, capsys):
    sim = write(tmp_path / "sim.csv", SIM_SQUARE)
    ref = write(tmp_path / "ref.csv", REF_SQUARE)
    code, _, stderr = run(capsys, "diff", sim, ref, "--set", "a=1")
    assert code == 2 and "--set applies only when SIMULATED is a netlist" in stderr
    code, _, stderr = run(capsys, "diff", sim, ref, "-o", tmp_path)
    assert code == 2 and "is a folder" in stderr
    code, _, stderr = run(capsys, "diff", sim, ref, "--y", "=y")
    assert code == 2 and "'=y'" in stderr


@pytest.mark.parametrize("option, target, words", [
    ("-o", "afile/t.csv", ["cannot write", "afile", "not a writable folder"]),
    ("--plot", "afile/d.png", ["cannot write", "afile", "not a writable folder"]),
    ("--plot", "d.txt", ["--plot '{target}': give a file ending in .png, .pdf, .svg"]),
    ("--plot", "d.jpg", ["--plot '{target}': give a file ending in .png, .pdf, .svg"]),
])
def test_output_paths_checked_before_the_comparison(tmp_path, capsys, monkeypatch, option, target, words):
    """The same check as vphs run, before any file is read. Review: a path under a file failed after the
    comparison ("internal error: FileExistsError", exit 1), .txt with "internal error: ValueError", and
    .jpg was written although vphs run refuses it."""
    import blocks.compare

    def refuse(*args, **kwargs):
        raise AssertionError("the comparison ran before the output paths were checked")

    monkeypatch.setattr(blocks.compare, "compare", refuse)
    sim = write(tmp_path / "sim.csv", SIM_SQUARE)
    ref = write(tmp_path / "ref.csv", REF_SQUARE)
    write(tmp_path / "afile", "keep\n")
    target = tmp_path / target
    code, stdout, stderr = run(capsys, "diff", sim, ref, option, target)
    assert code == 2 and len(stderr.strip().splitlines()) == 1 and "internal error" not in stderr, stderr
    for word in words:
        assert word.format(target=target) in stderr, (word, stderr)
    assert stdout == "" and sorted(p.name for p in tmp_path.iterdir()) == ["afile", "ref.csv", "sim.csv"]
    assert (tmp_path / "afile").read_text() == "keep\n"


@pytest.mark.parametrize("ref_text, extra, where, words", [
    (REF_SQUARE, ["--y", "pA=nope"], "{ref}:2: no column 'nope'", []),
    (REF_SQUARE, ["--y", "nope=y"], "{net}: no simulated column 'nope'", ["pA"]),
    ("t [s],pA [l/min]\n1,1\n", [], "{ref}:1:2: column 'pA [l/min]'", ["does not match", "pA [bar]"]),
])
def test_netlist_names_and_units_checked_before_the_run(tmp_path, capsys, monkeypatch, ref_text, extra, where,
                                                        words):
    """Misnamed columns and mismatched units fail at once, before the netlist is compiled and run."""
    from blocks.circuit import Circuit

    def refuse(*args, **kwargs):
        raise AssertionError("the netlist was compiled or run before the names were checked")

    monkeypatch.setattr(Circuit, "compile", refuse)
    monkeypatch.setattr(Circuit, "simulate", refuse)
    ref = write(tmp_path / "ref.csv", ref_text)
    code, _, stderr = run(capsys, "diff", DRIVE_LINE, ref, *extra)
    names = {"ref": ref, "net": DRIVE_LINE}
    assert code == 2 and stderr.startswith("vphs: " + where.format(**names)), stderr
    assert all(w in stderr for w in words), stderr


# ---------------------------------------------------------------- the reader on its own
def test_read_table_units_groups_and_lines(tmp_path):
    path = write(tmp_path / "d.csv", "\ufeff# comment\nsetting, p1 [bar] ,Q [l/min],k [-]\n\n# more\n"
                                     "a,1,60,2\nb,2.5,,3\na,3,120,4\n")
    table = read_table(path)
    assert table.units == {"p1": "bar", "Q": "l/min", "k": "1"}
    assert np.allclose(table.columns["p1"], [1e5, 2.5e5, 3e5])
    assert np.allclose(table.columns["Q"][[0, 2]], [1e-3, 2e-3]) and np.isnan(table.columns["Q"][1])
    assert np.allclose(table.in_unit("Q", "l/min")[[0, 2]], [60, 120])
    assert table.group == "setting" and table.labels == ["a", "b", "a"]
    assert {k: v.tolist() for k, v in table.groups.items()} == {"a": [0, 2], "b": [1]}
    assert table.header_line == 2 and table.lines == [5, 6, 7]
    with pytest.raises(DataFileError) as info:
        raise table.error("bad", "Q", 2)
    assert str(info.value) == f"{path}:7:3: column 'Q [l/min]': bad"


def test_shared_measurement_file_reads(tmp_path):
    """The thesis's multistep measurements (a grouping column and units) read as they are."""
    path = ROOT.parent / "shared" / "data" / "mcv_vf250_multistep.csv"
    if not path.exists():
        pytest.skip("shared data not present")
    table = read_table(path)
    assert table.group == "setting" and set(table.units) == {"p1", "p2", "p3", "Q"}
    assert np.all(np.isfinite(table.columns["Q"])) and table.columns["Q"].max() < 0.01  # m^3/s, not l/min


def test_grouped_points_are_compared_within_their_own_group(tmp_path):
    """Steady points of several settings: each reference point is interpolated on its own setting's curve.

    Setting a: y = 2x; setting b: y = 10x (simulated); the reference points lie exactly on each, except one
    that is 1 off, so only that group has an error, and ungrouped interpolation would be wrong by ~8x."""
    from blocks.compare import compare
    from blocks.datafile import read_table

    sim = tmp_path / "sim.csv"
    sim.write_text("setting,x [m],y [bar]\na,0,0\na,1,2\na,2,4\nb,0,0\nb,1,10\nb,2,20\n")
    ref = tmp_path / "ref.csv"
    ref.write_text("setting,x [m],y [bar]\na,0.5,1\na,1.5,3\nb,0.5,5\nb,1.5,16\n")
    result = compare(read_table(sim), read_table(ref), x="x", ys=["y"])
    by_group = {s.group: s for s in result.stats}
    assert by_group["a"].max_abs == pytest.approx(0.0, abs=1e-12)
    assert by_group["b"].max_abs == pytest.approx(1.0) and by_group["b"].x_at_max == pytest.approx(1.5)
    assert by_group["all"].rmse == pytest.approx(math.sqrt(1.0 / 4))


def test_a_reference_group_without_simulated_points_is_an_error(tmp_path):
    from blocks.compare import compare
    from blocks.datafile import read_table
    from blocks.errors import VphsError

    sim = tmp_path / "sim.csv"
    sim.write_text("setting,x [m],y [bar]\na,0,0\na,1,2\n")
    ref = tmp_path / "ref.csv"
    ref.write_text("setting,x [m],y [bar]\na,0.5,1\nc,0.5,3\n")
    with pytest.raises(VphsError) as info:
        compare(read_table(sim), read_table(ref), x="x", ys=["y"])
    assert "group setting = c has no simulated points" in str(info.value) and "ref.csv:3" in str(info.value)
