"""A whole-number switch (a parameter declared ``integer``: a lookup table's ``extrapolate`` and
``warn_outside``, 0 or 1) takes whole numbers only. Before, ``extrapolate: 0.52`` was accepted and the
table did whatever the threshold inside the block made of it; an optimiser or a calibration moved such a
switch continuously, and a sweep's range stepped through 0.5."""

from __future__ import annotations

import re

import pytest
import yaml

import cli
from blocks.registry import all_types

NETLIST = """description: a constant through a table
components:
  c: {type: constant, params: {value: 2.5}}
  tab: {type: lookup_1d, params: {x_table: [0, 1, 2], y_table: [0, 10, 20], extrapolate: EXTRAPOLATE}}
nets:
  n: [c.y, tab.u]
  y: [tab.y]
simulation: {t_end: 0.1 s}
"""


def netlist(tmp_path, extrapolate="0"):
    path = tmp_path / "lk.yaml"
    path.write_text(NETLIST.replace("EXTRAPOLATE", extrapolate))
    return path


def refused(capsys, argv, pattern):
    code = cli.main([str(a) for a in argv])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert re.search(pattern, err), err


def test_every_integer_parameter_refuses_a_fraction_and_takes_its_whole_values():
    found = [(cls, p) for cls in all_types().values() for p in cls.params if p.integer]
    assert found
    for cls, p in found:
        assert p.check(0.52) is not None and "whole number" in p.check(0.52), (cls.type_name, p.name)
        for whole in (p.lower, p.upper):
            assert p.check(whole) is None, (cls.type_name, p.name, whole)


def test_a_fraction_in_the_netlist_or_in_set_is_refused_where_it_is_written(tmp_path, capsys):
    refused(capsys, ["run", netlist(tmp_path, "0.52"), "-q"],
            r"lk\.yaml:4:\d+: tab: extrapolate = 0\.52 must be a whole number \(outside the table")
    refused(capsys, ["run", netlist(tmp_path), "-q", "--set", "tab.extrapolate=0.5"],
            r"--set 'tab\.extrapolate=0\.5': extrapolate = 0\.5 must be a whole number")
    assert cli.main(["run", str(netlist(tmp_path)), "-q", "--set", "tab.extrapolate=1",
                     "-o", str(tmp_path / "r.csv")]) == 0


def job(tmp_path, extra: dict):
    spec = {"name": "lk", "netlist": str(netlist(tmp_path)), "output": str(tmp_path / "out"),
            "parameters": {"c.value": {"min": 1, "max": 3}},
            "cost": {"terms": {"y": {"kind": "ise", "signal": "y", "weight": 1}}},
            "algorithm": {"method": "complex", "max_evaluations": 20}}
    for key, value in extra.items():
        spec[key] = {**spec.get(key, {}), **value}
    path = tmp_path / "job.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def test_an_optimiser_does_not_move_a_switch(tmp_path, capsys):
    refused(capsys, ["optimise", job(tmp_path, {"parameters": {"tab.extrapolate": {"min": 0, "max": 1}}}), "-q"],
            r"job\.yaml:\d+:\d+: parameters\.tab\.extrapolate: a whole-number switch \(outside the table: 0 hold "
            r"end value, 1 linear\) cannot be optimised; set it under set: or a load case")
    assert not (tmp_path / "out").exists()


def test_a_sweep_range_through_a_switch_is_refused_and_its_whole_values_run(tmp_path, capsys):
    path = job(tmp_path, {"sweep": {"parameters": {"tab.extrapolate": {"min": 0, "max": 1, "points": 3}}}})
    refused(capsys, ["sweep", path, "-q"],
            r"sweep\.parameters\.tab\.extrapolate: a whole-number switch \(.*\); list its values instead")
    path = job(tmp_path, {"sweep": {"parameters": {"tab.extrapolate": [0, 1]}}})
    assert cli.main(["sweep", str(path), "-q"]) == 0


def test_a_calibration_does_not_fit_a_switch(tmp_path, capsys):
    (tmp_path / "data.csv").write_text("x [1],y [1]\n0.5,5\n1.5,15\n2.5,25\n")
    spec = {"netlist": str(netlist(tmp_path)), "data": "data.csv",
            "inputs": {"x": {"parameter": "c.value", "noise": 0.01}},
            "outputs": {"y": {"signal": "y", "noise": 0.1}},
            "free": {"tab.extrapolate": {"lower": 0, "upper": 1}}}
    path = tmp_path / "exp.yaml"
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    refused(capsys, ["calibrate", path, "-q", "-o", tmp_path / "cal"],
            r"exp\.yaml:\d+:\d+: free\.tab\.extrapolate: a whole-number switch \(outside the table: 0 hold end "
            r"value, 1 linear\) cannot be fitted; set it under overrides")
    assert not (tmp_path / "cal").exists()
