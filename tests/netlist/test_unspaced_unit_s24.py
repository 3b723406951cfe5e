"""A quantity written against its number inside an expression (fault s24-3): ``"p_c+10barr"`` said Python's
"invalid decimal literal", while ``"p_c + 10 barr"`` says the misspelt unit. The unspaced form now says the
same, and that inside an expression a unit follows its number after a space (``"p_c+10bar"`` too, which is
refused as before). No hint where it would be false: ``10*k_unknown`` still names the unknown parameter, and
a number against a parameter's name (a '*' left out) is no unit.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

import cli

ROOT = Path(__file__).resolve().parents[2]
RIG = ROOT / "netlists" / "experiments" / "circuits" / "relief_rig.yaml"
SPACE = "inside an expression a unit follows its number after a space"


def netlist(tmp_path: Path, p_set: str) -> Path:
    """The relief rig with ``p_set`` written as given, beside parameters p_c (30 bar) and pc (a plain 3)."""
    doc = yaml.safe_load(RIG.read_text())
    doc["parameters"].update(p_set=p_set, p_c="30 bar", pc=3)
    path = tmp_path / "rig.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def said(tmp_path, capsys, p_set: str) -> str:
    """The message (after 'file:line:column: ') ``vphs validate`` refuses p_set with: one line, exit 2."""
    path = netlist(tmp_path, p_set)
    code = cli.main(["validate", str(path)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert err.startswith(f"vphs: {path}:"), err
    return err.split(": ", 2)[2]


MISSPELT = "p_set: unknown unit 'barr' (did you mean bar, mbar?)"


@pytest.mark.parametrize("p_set, message", [
    ("p_c + 10 barr", MISSPELT),  # as it was
    ("p_c+10barr", f"{MISSPELT}; and {SPACE} ('10 barr', not '10barr')"),
    ("p_c + 10barr", f"{MISSPELT}; and {SPACE} ('10 barr', not '10barr')"),
    ("p_c*10barr*2", f"{MISSPELT}; and {SPACE} ('10 barr', not '10barr')"),
    ("p_c+10bar", f"p_set: {SPACE} ('10 bar', not '10bar')"),
    ("p_c+1.5e1bar", f"p_set: {SPACE} ('1.5e1 bar', not '1.5e1bar')"),
])
def test_an_unspaced_unit_is_said_as_a_spaced_one_is(tmp_path, capsys, p_set, message):
    assert said(tmp_path, capsys, p_set) == message


@pytest.mark.parametrize("p_set, message", [
    ("10*k_unknown", "unknown parameter 'k_unknown' in p_set"),
    ("p_c+10pc", "p_set: 'p_c+10pc' is neither a '<number> <unit>' value nor a valid expression (invalid decimal "
                 "literal)"),  # pc is a parameter: a '*' left out, not a unit
    ("p_c+10p_c", "p_set: 'p_c+10p_c' is neither a '<number> <unit>' value nor a valid expression (invalid decimal "
                  "literal)"),
    ("p_c+10barr+(", "p_set: 'p_c+10barr+(' is neither a '<number> <unit>' value nor a valid expression ("),
])
def test_no_unit_hint_where_it_would_be_false(tmp_path, capsys, p_set, message):
    assert said(tmp_path, capsys, p_set).startswith(message)


def test_set_says_it_alike(tmp_path, capsys):
    path = netlist(tmp_path, "45 bar")
    assert cli.main(["run", str(path), "-q", "--set", "p_set=p_c+10barr"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"vphs: --set 'p_set=p_c+10barr': unknown unit 'barr' (did you mean bar, mbar?); and {SPACE} " \
                  f"('10 barr', not '10barr')", err
