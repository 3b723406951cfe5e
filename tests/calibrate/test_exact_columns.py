"""A data column the netlist reads itself (a recorded command trace on a profile block, ``{csv:, column:}``)
is imposed exactly: the experiment names it, the report says so, and a remaining discrepancy points at it."""

from __future__ import annotations

import shutil
from pathlib import Path
from types import SimpleNamespace

import yaml

from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.run import verdict

EXPERIMENTS = Path(__file__).resolve().parents[2] / "netlists" / "experiments"


def _trace_experiment(tmp_path: Path, data_name: str) -> Path:
    """The drive-line experiment with its command profile reading the columns t and cmd of ``data_name``, and
    the command no longer listed as an input."""
    (tmp_path / "circuits").mkdir()
    (tmp_path / "data").mkdir()
    shutil.copy(EXPERIMENTS / "data" / "drive_line_series.csv", tmp_path / "data" / "drive_line_series.csv")
    shutil.copy(EXPERIMENTS / "data" / "drive_line_series.csv", tmp_path / "data" / "other.csv")
    netlist = yaml.safe_load((EXPERIMENTS / "circuits" / "drive_line_open.yaml").read_text())
    netlist["components"]["cmd"]["params"] = {"times": {"csv": f"../data/{data_name}", "column": "t"},
                                              "values": {"csv": f"../data/{data_name}", "column": "cmd"}}
    (tmp_path / "circuits" / "trace.yaml").write_text(yaml.safe_dump(netlist, sort_keys=False))
    exp = yaml.safe_load((EXPERIMENTS / "drive_line_series.yaml").read_text())
    exp["netlist"] = "circuits/trace.yaml"
    del exp["inputs"]
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(exp, sort_keys=False))
    return tmp_path / "exp.yaml"


def test_a_column_the_netlist_reads_from_the_data_is_named(tmp_path):
    exp = load_experiment(_trace_experiment(tmp_path, "drive_line_series.csv"))
    assert exp.exact_columns == [("cmd", "cmd.values")]  # the sample times (t) are exact in the model anyway


def test_a_column_read_from_another_file_is_not_the_datas(tmp_path):
    assert load_experiment(_trace_experiment(tmp_path, "other.csv")).exact_columns == []


def test_a_remaining_discrepancy_points_at_the_exact_column():
    final = SimpleNamespace(fit=SimpleNamespace(converged=True),
                            lof=SimpleNamespace(significant=lambda: ["chi^2/nu = 2.26 (p = 0)"]))
    cal = SimpleNamespace(rounds=[], final=final, exchanges=[], removals=[], accepted=[],
                          exp=SimpleNamespace(exact_columns=[("cmd", "cmd.values")]))
    lines, unexplained = verdict(cal)
    assert unexplained and lines[0] == "unexplained discrepancy remains: chi^2/nu = 2.26 (p = 0)"
    assert lines[1].startswith("  the netlist imposes the column cmd (cmd.values) exactly as read from the data: "
                               "its measurement noise is not accounted for")
    cal.exp.exact_columns = []
    assert verdict(cal)[0] == ["unexplained discrepancy remains: chi^2/nu = 2.26 (p = 0)"]
