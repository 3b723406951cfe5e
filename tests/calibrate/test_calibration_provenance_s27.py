"""A calibration's report names what it was made with (blocks.provenance): report.json's ``environment`` and
the markdown's last line. The versions themselves are checked in tests/optimise/test_optimise_provenance_s27.py."""

import json

import cli
from blocks import provenance
from tests.calibrate.test_calibrate_end_to_end import steady_case


def test_the_calibration_report_says_it(tmp_path):
    exp = steady_case(tmp_path, 0.0, seed=6, only=["leakage"])
    out = tmp_path / "out"
    assert cli.main(["calibrate", str(exp), "-o", str(out), "-q"]) == 0
    assert json.loads((out / "report.json").read_text())["environment"] == provenance.environment()
    assert (out / "report.md").read_text().rstrip().endswith(provenance.environment_line())
