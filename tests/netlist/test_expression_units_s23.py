"""A misspelt unit inside an expression (fault s23-4): ``m_load: "p_c + 10 barr"`` said only that the text is
neither a value nor a valid expression, and ``"2*10 l/mn"`` that 'mn' is an unknown parameter, where the bare
``"10 barr"`` and ``"10 l/mn"`` say the unit, with its 'did you mean'. The expression's misspelt unit is now
said in the same words, at the value. A name that is no unit and not written as one (``10*k_unknown``) is
still an unknown parameter. The netlist and its helper are test_unit_messages_s22.py's."""

from __future__ import annotations

import pytest

from netlist_helpers import load, position
from test_unit_messages_s22 import NETLIST, message

P_C = '  p_c: "100 bar"\n'  # in place of the netlist's m_n


@pytest.mark.parametrize("kw, expected", [
    ({"m_load": '"p_c + 10 barr"'}, "m_load: unknown unit 'barr' (did you mean bar, mbar?)"),
    ({"m_load": '"2*(p_c - 5 barr)"'}, "m_load: unknown unit 'barr' (did you mean bar, mbar?)"),
    ({"flow": '"2*10 l/mn"'}, "pump.q: unknown unit 'mn' (did you mean MN, min, N?)"),
])
def test_a_misspelt_unit_in_an_expression_is_said_as_the_bare_value_says_it(tmp_path, kw, expected):
    (line, _), what, text = message(tmp_path, parameters=P_C, **kw)
    assert what == expected
    assert line == position(text, next(iter(kw.values())))[0]


def test_the_bare_misspelt_unit_says_the_same(tmp_path):
    assert message(tmp_path, m_load='"10 barr"', parameters=P_C)[1] == \
        "m_load: unknown unit 'barr' (did you mean bar, mbar?)"


@pytest.mark.parametrize("value, expected", [
    ('"p_c + 10*k_unknown"', "unknown parameter 'k_unknown' in m_load"),
    ('"p_c + 10*barr"', "unknown parameter 'barr' in m_load"),  # written as a name, not as a unit
])
def test_an_unknown_name_written_as_a_name_is_still_an_unknown_parameter(tmp_path, value, expected):
    assert message(tmp_path, m_load=value, parameters=P_C)[1] == expected


def test_a_number_beside_a_parameter_is_not_called_a_unit(tmp_path):
    """'10 p_c' (a '*' left out) reads as a quantity in the unit p_c; p_c is a parameter, not a misspelt
    unit: what is wrong is the syntax, as it was said before."""
    what = message(tmp_path, m_load='"p_c + 10 p_c"', parameters=P_C)[1]
    assert what == "m_load: 'p_c + 10 p_c' is neither a '<number> <unit>' value nor a valid expression", what


def test_a_correct_unit_in_an_expression_still_loads(tmp_path):
    text = NETLIST.replace("M_LOAD", '"p_c + 10 bar"').replace("FLOW", '"10 l/min"').replace("VALUE", "1")
    (tmp_path / "net.yaml").write_text(text.replace("  m_n: 2\n", P_C))
    assert load(tmp_path / "net.yaml").vectors().values["m_load"] == pytest.approx(110e5)
