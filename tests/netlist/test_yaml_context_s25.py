"""A YAML syntax error says where the construct it broke starts, not only where the parser gave up (review 25:
'tank: {type: tank' with its brace missing was reported at the next line, 20:6, and PyYAML's "while parsing a
flow mapping ... line 19" was dropped)."""

from __future__ import annotations

import pytest

import cli

HEAD = "components:\n  relief: {type: relief_valve}\n"

CASES = {
    "unclosed brace": (HEAD + "  tank:    {type: tank\n  dcv: {type: valve_4_3}\n", "4:6",
                       "invalid YAML: expected ',' or '}', but got ':' (while parsing a flow mapping that starts at "
                       "line 3, column 12; is its closing brace missing?)"),
    "unclosed bracket": (HEAD + "nets:\n  T: [tank.port, relief.b\n  P: [relief.a]\n", "5:4",
                         "invalid YAML: expected ',' or ']', but got ':' (while parsing a flow sequence that starts "
                         "at line 4, column 6; is its closing bracket missing?)"),
    "unclosed quote": (HEAD + 'parameters:\n  p: "180 bar\n', "5:1",
                       "invalid YAML: found unexpected end of stream (while scanning a quoted scalar that starts at "
                       "line 4, column 6; is its closing quote missing?)"),
    # on the construct's own line a missing ',' is as likely as a missing brace (review 25, finding 4)
    "comma missing in a mapping": (HEAD + "  c: {type: constant params: {value: 1}}\n", "3:28",
                                   "invalid YAML: expected ',' or '}', but got ':' (while parsing a flow mapping "
                                   "that starts at line 3, column 6; is a ',' or its closing brace missing?)"),
    "comma missing in a sequence": (HEAD + "nets:\n  T: [tank.port, {a: b}  relief.b: c]\n", "4:26",
                                    "invalid YAML: expected ',' or ']', but got '<scalar>' (while parsing a flow "
                                    "sequence that starts at line 4, column 6; is a ',' or its closing bracket "
                                    "missing?)"),
    # a quoted scalar's context comes only with the end of the stream: the quote is unclosed even on its line
    "unclosed quote on the last line": (HEAD + 'parameters:\n  p: "180 bar', "4:14",
                                        "invalid YAML: found unexpected end of stream (while scanning a quoted "
                                        "scalar that starts at line 4, column 6; is its closing quote missing?)"),
    "no context": (HEAD + "parameters: a: b\n", "3:14", "invalid YAML: mapping values are not allowed here"),
}


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_the_start_of_the_broken_construct_is_named(tmp_path, capsys, case):
    text, where, message = CASES[case]
    path = tmp_path / "n.yaml"
    path.write_text(text)
    assert cli.main(["validate", str(path)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line == f"vphs: {path}:{where}: {message}", line
