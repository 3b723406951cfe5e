"""A job's ``set:`` and load-case values take the netlist's expression syntax (fault s23-2): an expression
over the netlist's parameters, with units written inside it, evaluated against the netlist's values (with the
job's own plain values), as ``parameters:`` in a netlist does. A bad expression is one located line, exit 2.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import cli
from blocks.errors import NetlistError
from blocks.optimise.job import load_job

NETLIST = """\
description: a second-order system of gain k, from rest at 1 under a unit input (the known-optimum test's)
parameters:
  k: 1.0
  w0: "5 rad/s"
  z0: 0.35
components:
  one: {type: constant, params: {value: 1.0}}
  sys: {type: second_order, params: {k: k, wn: "2*w0", zeta: z0}, initial: {x: 1.0}}
nets:
  u: [one.y, sys.u]
outputs:
  y: sys.y
  r: one.y
simulation: {t_end: "1 s", dt_out: "10 ms"}
"""


def job(tmp_path: Path, name: str, settings: str, cases: str = "") -> Path:
    """A sweep of k over two values with ``settings`` as its set: (flow style) and ``cases`` its load_cases."""
    netlist = tmp_path / "system.yaml"
    netlist.write_text(NETLIST)
    text = (f"netlist: {netlist}\noutput: {tmp_path / name}\nset: {settings}\n"
            + (f"load_cases: {cases}\n" if cases else "")
            + "cost: {terms: {e: {kind: ise, signal: y, reference: r}}}\n"
            + "sweep: {parameters: {k: [0.5, 2]}}\n")
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    return path


EXPRESSION = '{sys.wn: "2*w0 + 1 rad/s", w0: "4 rad/s", sys.zeta: "z0*2"}'


def test_an_expression_in_set_is_the_value_it_evaluates_to(tmp_path):
    """Against the netlist's values with the job's plain ones in their place: w0 = 4 rad/s (the job's,
    not the netlist's 5 rad/s), so sys.wn = 2*4 + 1 = 9 rad/s, and sys.zeta = 2*0.35 (the netlist's z0)."""
    fixed = load_job(job(tmp_path, "expr", EXPRESSION)).fixed
    assert fixed == pytest.approx({"sys.wn": 9.0, "w0": 4.0, "sys.zeta": 0.7})


def test_a_job_with_an_expression_in_set_gives_what_its_number_gives(tmp_path):
    numbers = '{sys.wn: "9 rad/s", w0: "4 rad/s", sys.zeta: 0.7}'
    for name, settings in (("expr", EXPRESSION), ("numbers", numbers)):
        assert cli.main(["sweep", str(job(tmp_path, name, settings)), "--workers", "1", "-q"]) == 0
    assert (tmp_path / "expr" / "sweep" / "sweep.csv").read_text() == \
        (tmp_path / "numbers" / "sweep" / "sweep.csv").read_text()


def test_an_expression_in_a_load_case_is_evaluated_with_the_jobs_set(tmp_path):
    loaded = load_job(job(tmp_path, "cases", '{w0: "4 rad/s"}', '{slow: {sys.wn: "w0"}, fast: {sys.wn: "3*w0"}}'))
    assert loaded.cases == [("slow", {"sys.wn": pytest.approx(4.0)}), ("fast", {"sys.wn": pytest.approx(12.0)})]


@pytest.mark.parametrize("settings, pattern", [
    ('{sys.wn: "2*w00"}', r"unknown parameter 'w00' in set\.sys\.wn \(did you mean w0\?\)"),
    ('{sys.wn: "2*w0 + 1 bar"}', r"set\.sys\.wn: wrong unit: '2\*w0 \+ 1 bar' adds .*"),
    ('{sys.wn: "w0*2 s"}', r"set\.sys\.wn: wrong unit: 'w0\*2 s' is in rad, but sys\.wn is in s\^-1\*rad"),
    ('{sys.wn: "2*(w0"}', r"set\.sys\.wn: .*"),
    ('{sys.wn: "k*10 rad/s"}', r"set\.sys\.wn: '.*' reads k, which the job varies: .*"),
])
def test_a_bad_expression_in_set_is_one_located_line(tmp_path, capsys, settings, pattern):
    path = job(tmp_path, "bad", settings)
    assert cli.main(["sweep", str(path), "--workers", "1", "-q"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert re.fullmatch(rf"vphs: {re.escape(str(path))}:3:\d+: " + pattern, err), err
    assert not (tmp_path / "bad").exists()


def test_a_set_expression_reading_what_a_load_case_changes_is_refused(tmp_path):
    """Computed once, it would not follow the case: the netlist is where such an expression belongs."""
    path = job(tmp_path, "bad", '{sys.wn: "2*w0"}', '{a: {w0: "1 rad/s"}, b: {w0: "2 rad/s"}}')
    with pytest.raises(NetlistError) as caught:
        load_job(path)
    assert caught.value.line == 3 and "reads w0, which load case a sets" in str(caught.value), str(caught.value)
