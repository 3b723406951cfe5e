"""A parameter set for one group both by ``groups:`` and by ``group_table:`` is refused at the group's key.

Before, the table's value silently won over the one written under ``groups:`` (a plain value or an
expression alike), so an engineer who corrected one group's crack setting by hand saw no effect.
"""

from __future__ import annotations

import re

import pytest
import yaml

import cli
from blocks.calibrate.experiment import load_experiment

from test_input_leftovers_s22 import DATA, rig


def experiment(tmp_path, groups: dict) -> object:
    (tmp_path / "data.csv").write_text(DATA)
    (tmp_path / "table.csv").write_text("setting,f\n1,0\n2,0.1\n")
    spec = {"netlist": str(rig(tmp_path, "p_set*(1 + f)")), "data": "data.csv", "group": "setting",
            "inputs": {"Q": {"parameter": "Q_in", "noise": "0.5 l/min"}},
            "outputs": {"p1": {"signal": "p1", "noise": "0.2 bar"}},
            "group_table": {"file": "table.csv", "columns": {"f": "f"}},
            "free": {"k_s": {"initial": "50 bar", "lower": "5 bar", "upper": "500 bar"}}}
    if groups:
        spec["groups"] = groups
    path = tmp_path / "exp.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


@pytest.mark.parametrize("value", [0.2, "0.1 + 0.1"])
def test_a_name_in_groups_and_in_the_group_table_is_refused(tmp_path, capsys, value):
    path = experiment(tmp_path, {2: {"f": value}})
    code = cli.main(["calibrate", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert re.fullmatch(rf"vphs: {re.escape(str(path))}:\d+:\d+: groups\.2\.f is also set by "
                        r"group_table\.columns\.f \(table\.csv\); set it in one of the two, else which value "
                        r"group 2 takes is ambiguous", err), err
    assert not (tmp_path / "out").exists()


def test_other_names_in_groups_beside_the_group_table_are_kept(tmp_path):
    """The check is per name: a group may set what the table does not."""
    path = experiment(tmp_path, {2: {"p_set": "70 bar"}})
    exp = load_experiment(path)
    assert exp.groups["2"]["f"] == pytest.approx(0.1)
    assert exp.groups["2"]["p_set"] == pytest.approx(70e5)
