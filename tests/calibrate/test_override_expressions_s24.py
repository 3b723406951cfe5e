"""An experiment's ``overrides:`` and per-group values take expressions over the netlist's parameters (fault
s24-2), as a job's ``set:`` and ``--set`` do: evaluated once, when the experiment is loaded, with the netlist's
values and the section's plain values in their place (a group's: the overrides' and its own). One that reads
what the calibration changes (a free parameter, an input's parameter set point by point), another expression
of its section, or for ``overrides:`` a parameter a group sets, would not follow it and is refused, in one line
located at its key, exit 2, as a bad name or unit in it is. They used to be refused as "not '<number> <unit>'".
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

import cli
from blocks.calibrate.experiment import load_experiment

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "netlists" / "experiments" / "relief_rig_steady.yaml"
DATA = "setting,Q [l/min],p1 [bar],p2 [bar],p3 [bar]\n1,20,40,0.3,39\n2,40,50,0.5,48\n3,20,45,0.3,44\n"
GROUPS = '  "1": {p_set: "30 bar"}\n  "2": {p_set: "45 bar"}\n  "3": {p_set: "60 bar"}\n'


def experiment(tmp_path: Path, groups: str, overrides: str = "", netlist: Path | None = None) -> Path:
    """The shipped relief-rig experiment (netlist: p_set 45 bar, relief.A_max 60 mm^2; free k_s, A_ret and
    R_meter; Q_in set per point) on a small data file, with these ``groups:`` lines and ``overrides:`` (and
    another ``netlist``)."""
    text = SHIPPED.read_text().replace("netlist: circuits/relief_rig.yaml",
                                       f"netlist: {netlist or SHIPPED.parent / 'circuits' / 'relief_rig.yaml'}")
    text = text.replace("data: data/relief_rig_steady.csv", "data: data.csv")
    assert GROUPS in text
    text = text.replace(GROUPS, groups + (f"overrides: {overrides}\n" if overrides else ""))
    (tmp_path / "data.csv").write_text(DATA)
    path = tmp_path / "exp.yaml"
    path.write_text(text)
    return path


def test_group_values_may_be_expressions(tmp_path):
    """Its own name reads the netlist's value (p_set 45 bar); a group's plain value and the overrides are
    read in their place (ret.Cd 0.6 in group 1; relief.A_max 50 mm^2, itself an expression, everywhere)."""
    groups = ('  "1": {p_set: "p_set - 15 bar", ret.Cd: 0.6, relief.zeta: "ret.Cd + 0.1"}\n'
              '  "2": {p_set: "30 bar*relief.A_max/(50 mm^2)"}\n  "3": {p_set: "p_set + 15 bar"}\n')
    exp = load_experiment(experiment(tmp_path, groups, '{relief.A_max: "relief.A_max - 10 mm^2"}'))
    assert exp.overrides == pytest.approx({"relief.A_max": 50e-6})
    assert exp.groups == {"1": pytest.approx({"p_set": 30e5, "ret.Cd": 0.6, "relief.zeta": 0.7}),
                          "2": pytest.approx({"p_set": 30e5}), "3": pytest.approx({"p_set": 60e5})}


def refused(tmp_path, capsys, path: Path) -> tuple[int, str]:
    """(line, message) of the one line ``vphs calibrate`` refuses ``path`` with (exit 2), in ``path``."""
    code = cli.main(["calibrate", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    m = re.fullmatch(rf"vphs: {re.escape(str(path))}:(\d+):\d+: (.*)", err)
    assert m, err
    assert not (tmp_path / "out").exists()
    return int(m[1]), m[2]


ONCE = ": an expression here is evaluated once, with the netlist's values; write it in the netlist"


@pytest.mark.parametrize("group, overrides, message", [
    ('{p_set: "2*k_s"}', "", "groups.2.p_set: '2*k_s' reads k_s, which the calibration fits (free.k_s)" + ONCE),
    ('{p_set: "Q_in*1 bar*s/l"}', "", "groups.2.p_set: 'Q_in*1 bar*s/l' reads Q_in, which inputs.Q sets point by "
                                      "point" + ONCE),
    ('{relief.zeta: 0.9, ret.Cd: "relief.zeta - 0.2", relief.wn: "300 Hz*ret.Cd"}', "",
     "groups.2.relief.wn: '300 Hz*ret.Cd' reads ret.Cd, which is given by an expression in groups.2 too" + ONCE),
    ('{p_set: "p_sett + 1 bar"}', "", "unknown parameter 'p_sett' in groups.2.p_set (did you mean p_set, relief.p_set?)"),
    ('{p_set: "p_set*2 m"}', "", "groups.2.p_set: wrong unit: 'p_set*2 m' is in kg*s^-2, but p_set is in "
                                 "m^-1*kg*s^-2"),
    ('{p_set: "p_set + 10 barr"}', "", "groups.2.p_set: unknown unit 'barr' (did you mean bar, mbar?)"),
    ('{p_set: "45 bar"}', '{relief.A_max: "p_set*1 mm^2/bar"}',
     "overrides.relief.A_max: 'p_set*1 mm^2/bar' reads p_set, which groups.1 sets" + ONCE),
])
def test_a_bad_expression_is_one_line_at_its_key(tmp_path, capsys, group, overrides, message):
    groups = GROUPS.replace('  "2": {p_set: "45 bar"}', f'  "2": {group}')
    path = experiment(tmp_path, groups, overrides)
    line, said = refused(tmp_path, capsys, path)
    key = "overrides:" if overrides else '  "2":'
    assert line == path.read_text()[:path.read_text().index(key)].count("\n") + 1, said
    assert said == message, said


def test_a_value_the_netlist_cannot_take_is_the_groups_error(tmp_path, capsys):
    path = experiment(tmp_path, GROUPS.replace('"45 bar"', '"-p_set"'))
    line, said = refused(tmp_path, capsys, path)
    assert said.startswith("groups: with the values of group 2 the netlist cannot be evaluated: ") and \
        "p_set = -4.5e+06 Pa is below its lower bound 0 Pa" in said, said


def test_values_checked_together_are_checked_with_the_expressions_values(tmp_path):
    """A saturation's lower must stay below its upper: a group's plain upper below the netlist's lower is
    right when an expression moves the lower with it (it was refused before the expression was evaluated)."""
    doc = yaml.safe_load((SHIPPED.parent / "circuits" / "relief_rig.yaml").read_text())
    doc["parameters"].update(lo=-1.0, hi=1.0)
    doc["components"].update(c={"type": "constant", "params": {"value": 0.0}},
                             sat={"type": "saturation", "params": {"lower": "lo", "upper": "hi"}})
    doc["nets"]["s"] = ["c.y", "sat.u"]
    netlist = tmp_path / "rig.yaml"
    netlist.write_text(yaml.safe_dump(doc, sort_keys=False))
    groups = GROUPS.replace('{p_set: "45 bar"}', '{hi: -2, lo: "hi - 1"}')
    exp = load_experiment(experiment(tmp_path, groups, '{sat.upper: -5, sat.lower: "2*sat.upper"}', netlist))
    assert exp.groups["2"] == pytest.approx({"hi": -2.0, "lo": -3.0})
    assert exp.overrides == pytest.approx({"sat.upper": -5.0, "sat.lower": -10.0})
