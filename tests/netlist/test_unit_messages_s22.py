"""A misspelt unit after an operator ("10 l/mn", "20 cm^3/revv") in a netlist value was reported as an
unknown parameter 'mn' (session 22's user review): the expression reading of the text (10 l divided by a
parameter mn) won over the quantity reading, while ``--set`` said "unknown unit 'mn'". Where the value is
"<number> <unit>" but for that name, and no parameter has that name, the misspelt unit is said, with its
'did you mean'. A genuine expression with an unknown name still says unknown parameter."""

from __future__ import annotations

from pathlib import Path

import pytest

from netlist_helpers import load, load_error, position, split_message

NETLIST = """
parameters:
  m_load: M_LOAD
  V_line: "0.3 l"
  m_n: 2
components:
  tank: {type: tank}
  pump: {type: flow_source, params: {q: FLOW}}
  ref:  {type: constant, params: {value: VALUE}}
nets:
  T: [tank.port, pump.a]
  P: {ports: [pump.b], volume: V_line, initial: "0 bar"}
simulation: {t_end: "0.1 s", dt_out: "10 ms"}
"""


def message(tmp_path: Path, m_load='"1000 kg"', flow='"10 l/min"', value="1", parameters="") -> tuple:
    """(line, column, what) of the error loading the netlist with these values; the place is checked to be
    the value's."""
    text = NETLIST.replace("M_LOAD", m_load).replace("FLOW", flow).replace("VALUE", value)
    text = text.replace("  m_n: 2\n", parameters)
    path = tmp_path / "net.yaml"
    path.write_text(text)
    file, line, col, what = split_message(str(load_error(path)))
    assert file.endswith("net.yaml")
    return (line, col), what, text


@pytest.mark.parametrize("kw, expected", [
    ({"flow": '"10 l/mn"'}, "pump.q: unknown unit 'mn' (did you mean MN, min, N?)"),
    ({"value": '"20 cm^3/revv"'}, "ref.value: unknown unit 'revv' (did you mean rev?)"),
    ({"m_load": '"1000 kg/mn"'}, "m_load: unknown unit 'mn' (did you mean MN, min, N?)"),
])
def test_a_misspelt_unit_after_a_slash_is_said_as_a_unit(tmp_path, kw, expected):
    """As ``--set`` says it: the same words, on the line of the value."""
    (line, _), what, text = message(tmp_path, **kw)
    assert what == expected
    assert line == position(text, next(iter(kw.values())))[0]


def test_a_name_near_both_a_unit_and_a_parameter_names_both(tmp_path):
    """'mn' is near the unit min and the parameter m_n: either may have been meant."""
    _, what, _ = message(tmp_path, flow='"10 l/mn"', parameters="  m_n: 2\n")
    assert what == "pump.q: unknown unit or parameter 'mn' (did you mean the unit MN, min, N or the parameter m_n?)"


def test_a_name_near_no_unit_after_a_quantity_is_an_unknown_unit_or_parameter(tmp_path):
    _, what, _ = message(tmp_path, flow='"10 l/xyzzy"')
    assert what == "pump.q: unknown unit or parameter 'xyzzy'"


@pytest.mark.parametrize("flow, expected", [
    ('"2*V_lin/1 s"', "unknown parameter 'V_lin' in pump.q (did you mean V_line?)"),
    ('"q_nom + 10 l/min"', "unknown parameter 'q_nom' in pump.q"),
    ('"10 l/min/V_lin*V_line"', "unknown parameter 'V_lin' in pump.q (did you mean V_line?)"),
])
def test_an_expression_with_an_unknown_name_still_says_unknown_parameter(tmp_path, flow, expected):
    assert message(tmp_path, flow=flow)[1] == expected


def test_a_parameter_read_after_a_unit_is_still_read(tmp_path):
    """'10 l/min/n' with a parameter n is an expression, as before."""
    text = NETLIST.replace("M_LOAD", '"1 kg"').replace("FLOW", '"10 l/min/n"').replace("VALUE", "1")
    path = tmp_path / "net.yaml"
    path.write_text(text.replace("  m_n: 2\n", "  n: 2\n"))
    assert load(path).vectors().values["pump.q"] == pytest.approx(10e-3 / 60 / 2)
