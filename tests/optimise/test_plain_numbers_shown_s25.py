"""A dimensionless parameter (declared "1" by its block: valve.Cd, spool.zeta) is shown as a plain number
in an optimisation's and a sweep's outputs (review 25: "cbv.R_pilot = 1.5 1", "| 1.5 1 | 1.5 1 | 8 1 |",
a column "cbv.R_pilot [1]" and best.json's unit "1")."""

import csv
import json
import re

import cli
from blocks.optimise.display import shown
from tests.optimise.jobs import drive_line_job

SWEEP = "sweep:\n  parameters:\n    valve.Cd: [0.6, 0.7]\n"


def test_shown_writes_a_plain_number_alone():
    assert shown(1.5, "1") == "1.5" and shown(1.5, "") == "1.5"
    assert shown(2.5e6, "bar") == "25 bar"


def test_reports_console_csv_and_best_json_show_no_unit_1(tmp_path, capsys):
    path = drive_line_job(tmp_path, "out", {"valve.Cd": "{min: 0.6, max: 0.8}", "spool.zeta": "{min: 0.7, max: 1.0}"},
                          "{method: complex, max_evaluations: 6, candidates: 1}", SWEEP)
    assert cli.main(["optimise", str(path), "--workers", "1"]) == 0
    err = capsys.readouterr().err
    report = (tmp_path / "out" / "report.md").read_text()
    assert "| valve.Cd | " in report and "| 0.6 | 0.8 | linear | 0.7 |" in report, report
    assert "| evaluation | step | cost | valve.Cd | spool.zeta |" in report
    assert not re.search(r"\d 1 \|", report) and "[1]" not in report
    best = next(line for line in err.splitlines() if " best cost " in line and " at " in line)
    assert "valve.Cd = " in best and not any(part.strip().endswith(" 1") for part in best.split(","))
    saved = json.loads((tmp_path / "out" / "best.json").read_text())
    assert saved["units"] == {"valve.Cd": "", "spool.zeta": ""}
    assert {v["unit"] for v in saved["shown"].values()} == {""}

    assert cli.main(["sweep", str(path), "--workers", "1", "-q"]) == 0
    folder = tmp_path / "out" / "sweep"
    with open(folder / "sweep.csv", newline="") as handle:
        assert next(csv.reader(handle))[0] == "valve.Cd"
    report = (folder / "report.md").read_text()
    assert "at valve.Cd = 0.6 (evaluation" in report or "at valve.Cd = 0.7 (evaluation" in report, report
    assert "| valve.Cd | pos" in report
