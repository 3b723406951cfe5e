"""An expression Python only warns about ('1if 2 else 3': "invalid decimal literal") is refused in the one
located line, with no stray '<unknown>:1: SyntaxWarning' on stderr (a fuzz run of the test suite showed it)."""

from __future__ import annotations

import warnings

import pytest

from blocks.expressions import ExpressionError, parse_expression


def test_a_syntax_warning_is_an_expression_error():
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        with pytest.raises(ExpressionError, match=r"invalid decimal literal"):
            parse_expression("1if 2 else 3")
    assert not seen, [str(w.message) for w in seen]


def test_validate_says_one_line(tmp_path):
    """In a fresh process, as a user runs it: stderr is the one located line."""
    import subprocess
    import sys
    from pathlib import Path

    netlist = tmp_path / "n.yaml"
    netlist.write_text('components:\n  c: {type: constant, params: {value: "2*1if 2 else 3"}}\nnets:\n  y: [c.y]\n')
    done = subprocess.run([sys.executable, "-m", "cli", "validate", str(netlist)], capture_output=True, text=True,
                          cwd=Path(__file__).resolve().parents[2], timeout=300)
    err = done.stderr.strip()
    assert done.returncode == 2 and len(err.splitlines()) == 1 and "SyntaxWarning" not in err, err
