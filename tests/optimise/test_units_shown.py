"""The free parameters are shown in the units the job wrote them in (review: bounds in bar reported as
'2.56e+07 m^-1*kg*s^-2', mm^2 as m^2, and a bound error quoting SI values the user never typed).

The expected numbers are the log's SI values divided by the units' factors written here (1 bar = 1e5 Pa,
1 mm^2 = 1e-6 m^2), not anything the code computes."""

import csv
import json
from pathlib import Path

import pytest

import cli
from blocks.optimise.job import load_job
from blocks.optimise.log import read_log
from tests.optimise.jobs import drive_line_job

BAR, MM2 = 1e5, 1e-6
SWEEP = """\
sweep:
  parameters:
    supply.p: ["150 bar", "220 bar"]
    valve.A_max: {min: "60 mm^2", max: "120 mm^2", points: 2}
"""


def write_job(tmp_path, p_bounds='{min: "150 bar", max: "250 bar"}',
              a_bounds='{min: "60 mm^2", max: "250 mm^2"}') -> Path:
    return drive_line_job(tmp_path, "out", {"supply.p": p_bounds, "valve.A_max": a_bounds, "Kp": "{min: 2, max: 20}"},
                          "{method: complex, max_evaluations: 8}", SWEEP)


def test_the_report_the_console_and_best_json_show_bar_and_mm2(tmp_path, capsys):
    path = write_job(tmp_path)
    assert cli.main(["optimise", str(path), "--workers", "1"]) == 0
    err = capsys.readouterr().err
    out = tmp_path / "out"
    _, records = read_log(out)
    best = min(records[1:], key=lambda r: r["cost"])  # records[0]: the netlist's own design
    p, a, kp = (best["parameters"][k] for k in ("supply.p", "valve.A_max", "Kp"))
    report = (out / "report.md").read_text()
    assert f"| supply.p | {p / BAR:.6g} bar | 150 bar | 250 bar | linear | 207 bar |" in report
    assert f"| valve.A_max | {a / MM2:.6g} mm^2 | 60 mm^2 | 250 mm^2 | linear | 125 mm^2 |" in report
    assert f"| Kp | {kp:.6g} | 2 | 20 | linear | 4 |" in report
    assert "| evaluation | step | cost | supply.p [bar] | valve.A_max [mm^2] | Kp |" in report
    first = records[1]["parameters"]  # the first of the path improves on nothing: it is in the history
    assert f"| {first['supply.p'] / BAR:.6g} | {first['valve.A_max'] / MM2:.6g} | {first['Kp']:.6g} |" in report
    assert "Pa" not in report.split("To simulate")[0] and "m^2 " not in report.replace("mm^2", "")
    assert f"supply.p = {p / BAR:.6g} bar, valve.A_max = {a / MM2:.6g} mm^2, Kp = {kp:.6g};" in err
    saved = json.loads((out / "best.json").read_text())
    assert saved["parameters"] == best["parameters"]  # SI, machine-readable, unchanged
    assert saved["units"] == {"supply.p": "Pa", "valve.A_max": "m^2", "Kp": ""}
    assert saved["shown"]["supply.p"] == {"value": pytest.approx(p / BAR, rel=1e-12), "unit": "bar"}
    assert saved["shown"]["valve.A_max"] == {"value": pytest.approx(a / MM2, rel=1e-12), "unit": "mm^2"}


def test_sweep_csv_has_unit_headers_and_values_in_them(tmp_path):
    path = write_job(tmp_path)
    assert cli.main(["sweep", str(path), "--workers", "1", "-q"]) == 0
    folder = tmp_path / "out" / "sweep"
    _, records = read_log(folder)
    with open(folder / "sweep.csv") as handle:
        rows = list(csv.reader(handle))
    assert rows[0][:2] == ["supply.p [bar]", "valve.A_max [mm^2]"]
    assert len(rows) == 1 + len(records) == 5
    for row, record in zip(rows[1:], records):
        assert float(row[0]) == pytest.approx(record["parameters"]["supply.p"] / BAR, rel=1e-9)
        assert float(row[1]) == pytest.approx(record["parameters"]["valve.A_max"] / MM2, rel=1e-9)
    assert {float(r[0]) for r in rows[1:]} == {150.0, 220.0} and {float(r[1]) for r in rows[1:]} == {60.0, 120.0}
    report = (folder / "report.md").read_text()
    assert "| supply.p [bar] | valve.A_max [mm^2] |" in report and "| 220 | 120 |" in report


def test_bare_si_bounds_are_shown_in_the_netlists_unit(tmp_path):
    """valve.A_max given in SI (6e-5 m^2): the netlist writes it "125 mm^2", so mm^2 it is."""
    job = load_job(write_job(tmp_path, a_bounds="{min: 6e-5, max: 2.5e-4}", p_bounds="{min: 1.5e7, max: 2.5e7}"))
    assert job.units["valve.A_max"] == "mm^2" and job.units["supply.p"] == "bar"  # the netlist: "207 bar"
    assert job.units["Kp"] == "" and [p.unit for p in job.free] == ["bar", "mm^2", ""]


def test_a_bound_error_quotes_the_bounds_as_written(tmp_path, capsys):
    path = write_job(tmp_path, a_bounds='{min: "250 mm^2", max: "60 mm^2"}')
    assert cli.main(["optimise", str(path), "--workers", "1", "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    line = 1 + path.read_text().splitlines().index('  valve.A_max: {min: "250 mm^2", max: "60 mm^2"}')
    assert f"{path}:{line}:" in err and "parameters.valve.A_max: max (60 mm^2) must be above min (250 mm^2)" in err


def test_a_netlist_design_outside_the_bounds_is_said_in_their_unit(tmp_path):
    job = load_job(write_job(tmp_path, p_bounds='{min: "210 bar", max: "250 bar"}'))
    assert job.netlist_design_outside() == "supply.p = 207 bar is outside [210 bar, 250 bar]"


def test_a_bound_outside_the_netlists_bounds_is_quoted_as_written(tmp_path, capsys):
    path = write_job(tmp_path, a_bounds='{min: "60 mm^2", max: "2e7 mm^2"}')  # 20 m^2: above A_max's 1 m^2
    assert cli.main(["optimise", str(path), "--workers", "1", "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "parameters.valve.A_max.max: 2e7 mm^2 is outside the netlist's bounds (" in err
