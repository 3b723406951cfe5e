"""``--set`` takes an expression over the netlist's parameters (fault s24-1), as a job's ``set:`` does:
``vphs run NETLIST --set Kvp=Kv/4``, ``--set "p_c=p_crack + 10 bar"``. It is evaluated once, before the
run, with the netlist's values and the plain --set values in their place (in any order); its own name
reads the netlist's value. One that reads another --set expression, or (linearise) an --input, is refused
in one line, exit 2: it would not follow it. Every command that takes --set (run, diff, linearise) reads it
alike. It used to say "'Kv/4' is not '<number> <unit>'".
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import cli

NETLIST = """\
description: a second-order system of gain k, from rest at 1 under a unit input
parameters:
  k: 1.0
  w0: "5 rad/s"
  z0: 0.35
components:
  one: {type: constant, params: {value: 1.0}}
  sys: {type: second_order, params: {k: k, wn: "2*w0", zeta: z0}, initial: {x: 0.0}}
nets:
  u: [one.y, sys.u]
outputs:
  y: sys.y
simulation: {t_end: "0.5 s", dt_out: "10 ms"}
"""


@pytest.fixture(scope="module")
def netlist(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("set_s24") / "system.yaml"
    path.write_text(NETLIST)
    return path


def run(netlist: Path, capsys, *sets: str) -> str:
    """The CSV ``vphs run`` writes with these ``--set`` values (exit 0)."""
    args = ["run", str(netlist), "-q"] + [a for s in sets for a in ("--set", s)]
    code = cli.main(args)
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def refused(capsys, args: list[str]) -> str:
    """The one line a command refuses ``args`` with (exit 2, no traceback)."""
    code = cli.main(args)
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("expressions, numbers", [
    (["sys.wn=2*w0 + 1 rad/s", "w0=4 rad/s"], ["sys.wn=9 rad/s", "w0=4 rad/s"]),  # the plain --set value of w0
    (["w0=4 rad/s", "sys.wn=2*w0 + 1 rad/s"], ["sys.wn=9 rad/s", "w0=4 rad/s"]),  # in any order
    (["sys.zeta=2*sys.zeta"], ["sys.zeta=0.7"]),  # its own name: the netlist's value
    (["sys.zeta=z0*2", "sys.k=k + 0.5"], ["sys.zeta=0.7", "sys.k=1.5"]),
    (["sys.wn=(w0/2)*3"], ["sys.wn=7.5 rad/s"]),
    # sys.wn is held at 8 rad/s: that the netlist's 2*w0 reads w0, given by an expression, does not count
    (["w0=2*w0", "sys.wn=8", "sys.k=sys.wn/(8 rad/s)"], ["w0=10 rad/s", "sys.wn=8", "sys.k=1"]),
])
def test_run_with_an_expression_is_the_run_with_its_value(netlist, capsys, expressions, numbers):
    assert run(netlist, capsys, *expressions) == run(netlist, capsys, *numbers)


def test_plain_numbers_and_quantities_are_read_as_before(netlist, capsys):
    assert run(netlist, capsys, "w0=4 rad/s") == run(netlist, capsys, "w0=4") == run(netlist, capsys, "sys.wn=8")


@pytest.mark.parametrize("setting, message", [
    ("sys.wn=2*w00", "unknown parameter 'w00' in --set 'sys.wn=2*w00' (did you mean w0?)"),
    ("sys.wn=w0*2 s", "--set 'sys.wn=w0*2 s': wrong unit: 'w0*2 s' is in rad, but sys.wn is in s^-1*rad"),
    ("sys.wn=2*w0 + 1 bar", "--set 'sys.wn=2*w0 + 1 bar': wrong unit: '2*w0 + 1 bar' adds "),
    ("sys.wn=2*(w0", "--set 'sys.wn=2*(w0': '2*(w0' is neither a '<number> <unit>' value nor a valid expression"),
    ("sys.wn=w0 + 1 rad/ss", "--set 'sys.wn=w0 + 1 rad/ss': unknown unit 'ss' (did you mean s"),
    ("sys.zeta=-z0", "--set 'sys.zeta=-z0': zeta = -0.35 is below its lower bound 0"),
])
def test_a_bad_expression_is_one_line_naming_the_option(netlist, capsys, setting, message):
    err = refused(capsys, ["run", str(netlist), "-q", "--set", setting])
    assert err.startswith(f"vphs: {message}"), err


def test_an_expression_reading_another_set_expression_is_refused(netlist, capsys):
    """Which value it would read, the netlist's or the other expression's, is not clear: refused, as in a
    job's set:. Through the netlist's expressions too (sys.wn is 2*w0 there)."""
    for sets, read in ((["w0=4 rad/s*k", "sys.zeta=z0*w0/(5 rad/s)"], "w0"),
                       (["w0=2*w0", "sys.k=sys.wn/(10 rad/s)"], "w0"),
                       (["sys.k=2*k", "k=sys.k"], "k")):
        err = refused(capsys, ["run", str(netlist), "-q"] + [a for s in sets for a in ("--set", s)])
        assert re.fullmatch(rf"vphs: --set '[^']+': '[^']+' reads {re.escape(read)}, which is given by an expression "
                            r"in --set too: an expression here is evaluated once, with the netlist's values; write "
                            r"it in the netlist", err), err


def test_linearise_takes_expressions_and_refuses_one_reading_an_input(netlist, capsys):
    def modes(*sets: str, inputs=("k",)) -> str:
        args = ["linearise", str(netlist), "-q"] + [a for s in sets for a in ("--set", s)]
        assert cli.main(args + [a for i in inputs for a in ("--input", i)]) == 0
        return capsys.readouterr().out

    assert modes("sys.zeta=z0*2") == modes("sys.zeta=0.7")
    err = refused(capsys, ["linearise", str(netlist), "-q", "--set", "sys.k=2*k", "--input", "k"])
    assert err == ("vphs: --set 'sys.k=2*k': '2*k' reads k, which --input k perturbs (the response would leave it "
                   "out): an expression here is evaluated once, with the netlist's values; write it in the netlist")


def test_diff_takes_expressions_as_run_does(netlist, capsys, tmp_path):
    reference = tmp_path / "ref.csv"
    reference.write_text("t [s],y [SI]\n0.1,0.2\n0.3,0.8\n")

    def table(setting: str) -> str:
        assert cli.main(["diff", str(netlist), str(reference), "-q", "--set", setting]) == 0
        return capsys.readouterr().out

    assert table("sys.wn=2*w0 + 1 rad/s") == table("sys.wn=11 rad/s")
    err = refused(capsys, ["diff", str(netlist), str(reference), "-q", "--set", "sys.wn=2*w00"])
    assert err.startswith("vphs: unknown parameter 'w00' in --set 'sys.wn=2*w00'"), err


def test_values_checked_together_are_checked_with_the_expressions_values(capsys):
    """The relief's p_open must stay above its p_set: a plain p_set above the netlist's p_open is right when
    an expression moves p_open with it, and refused, naming both, when the expression does not lift it."""
    power_unit = Path(__file__).resolve().parents[2] / "netlists" / "components" / "power_unit.yaml"
    args = ["validate", str(power_unit)]
    assert cli.main(args) == 0
    capsys.readouterr()
    linearise = ["linearise", str(power_unit), "-q", "--at", "0 s", "--set", "relief.p_set=200 bar"]
    assert cli.main(linearise + ["--set", "relief.p_open=relief.p_set + 10 bar"]) == 0
    capsys.readouterr()
    err = refused(capsys, linearise + ["--set", "relief.p_open=relief.p_set - 20 bar"])
    assert err.startswith("vphs: --set 'relief.p_set=200 bar', --set 'relief.p_open=relief.p_set - 20 bar': "
                          "relief: p_open = "), err
