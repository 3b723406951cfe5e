"""A netlist value the expression parser refuses is said in plain words (session 22's user review): a decimal
comma ("150,5 bar") read as 'Tuple' is not allowed, and every other refused construct was named by the
parser's node type ('Subscript', 'BinOp', 'IfExp'...). Now a decimal comma is named as such with the number
to write, in a netlist and through ``--set`` alike, and each refused construct as it is written."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from blocks.circuit import Circuit
from blocks.expressions import ExpressionError, parse_expression
from blocks.units import UnitError
from netlist_helpers import load_error, position, split_message

NETLIST = """
parameters:
  p_c: "160 bar"
components:
  src:  {type: pressure_source, params: {p: VALUE}}
  tank: {type: tank}
  q:    {type: flow_source, params: {q: "1 l/min"}}
nets:
  T: [tank.port, q.a]
  P: [src.port, q.b]
simulation: {t_end: "0.1 s", dt_out: "10 ms"}
"""

# every class of Python's syntax tree: none may name what is wrong in a message
NODE_NAMES = {name for name, obj in vars(ast).items() if isinstance(obj, type) and issubclass(obj, ast.AST)
              and name[0].isupper()}  # "keyword", "arguments": English words too


def netlist(tmp_path: Path, value: str) -> Path:
    path = tmp_path / "net.yaml"
    path.write_text(NETLIST.replace("VALUE", value))
    return path


@pytest.mark.parametrize("value, expected", [
    ('"150,5 bar"', "src.p: ',' is not a decimal point in '150,5 bar' (write 150.5)"),
    ('"p_c + 0,5 bar"', "src.p: ',' is not a decimal point in 'p_c + 0,5 bar' (write 0.5)"),
    ('"1,000 bar"', "src.p: ',' is not a decimal point in '1,000 bar' (write 1.000, or 1000 without a thousands "
                    "separator)"),
])
def test_a_decimal_comma_is_named_with_the_number_to_write(tmp_path, value, expected):
    path = netlist(tmp_path, value)
    file, line, _, what = split_message(str(load_error(path)))
    assert what == expected
    assert file == str(path) and line == position(path.read_text(), value)[0]


def test_a_decimal_comma_given_with_set_says_the_same(tmp_path):
    table = Circuit.from_file(netlist(tmp_path, '"150 bar"'), compile=False).flat.parameters
    with pytest.raises(UnitError) as caught:
        table.value_si("src.p", "150,5 bar")
    assert str(caught.value) == "',' is not a decimal point in '150,5 bar' (write 150.5)"


def test_a_comma_between_a_functions_arguments_is_no_decimal_comma(tmp_path):
    values = Circuit.from_file(netlist(tmp_path, '"max(150,5 bar)"'), compile=False).vectors().values
    assert values["src.p"] == pytest.approx(5e5)


@pytest.mark.parametrize("text, expected", [
    ("1, 2", "a comma outside a function's parentheses is not allowed in expression '1, 2' (a value is one "
             "number; a comma only separates a function's arguments)"),
    ("a[0]", "indexing with '[ ]' is not allowed in expression 'a[0]'"),
    ("2^3", "'^' is not allowed in expression '2^3' (write ** for a power, as in x**2)"),
    ("7//2", "'//' is not allowed in expression '7//2' (write floor(a/b))"),
    ("a if b else c", "'if ... else' is not allowed in expression 'a if b else c'"),
    ("a < b", "a comparison is not allowed in expression 'a < b'"),
    ("...", "only real numbers are allowed in '...', not ..."),
    ("a.b(1)", "unknown function 'a.b' in 'a.b(1)' (allowed: abs, acos, asin, atan, atan2, ceil, cos, degrees, exp, "
               "floor, hypot, log, log10, max, min, radians, sin, sqrt, tan, tanh)"),
    ("max(3)", "'max(3)': max() takes 2 or more arguments, not 1"),
    ("sqrt(1, 2)", "'sqrt(1, 2)': sqrt() takes 1 argument, not 2"),
    ("atan2(1)", "'atan2(1)': atan2() takes 2 arguments, not 1"),
])
def test_a_refused_construct_is_named_as_written(text, expected):
    assert refusal(text) == expected


def refusal(text: str) -> str:
    """What is wrong with ``text`` as an expression: refused when parsed, or when evaluated (a call's number
    of arguments), with every name it reads 1."""
    with pytest.raises(ExpressionError) as caught:
        expression = parse_expression(text)
        expression.evaluate(dict.fromkeys(expression.names, 1.0))
    return str(caught.value)


@pytest.mark.parametrize("text", [
    "1, 2", "a[0]", "a[1:2]", "[1, 2]", "{1: 2}", "{1}", "{**a}", "a < b", "a == b", "a and b", "a or b", "not a",
    "~a", "a if b else c", "lambda: 1", "[x for x in y]", "{x for x in y}", "{x: 1 for x in y}", "(x for x in y)",
    "f'{a}'", "2^3", "7//2", "a@b", "a|b", "a&b", "a<<2", "a>>2", "(a:=1)", "max(*a)", "'s'", "True", "None",
    "...", "b'x'", "1j", "a.b(1)", "max(3)", "min()", "log(1, 2, 3)", "hypot()", "max(1, k=2)", "a._b", "sqrt",
])
def test_no_message_names_a_syntax_tree_node(text):
    message = refusal(text)
    assert not set(re.findall(r"[A-Za-z_]\w*", message)) & NODE_NAMES - set(re.findall(r"[A-Za-z_]\w*", text)), \
        message
