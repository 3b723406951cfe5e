"""A misspelt unit at the start of an expression (``"10 barr + p_c"``) is said as the misspelt unit, as it is
anywhere else in an expression. Before, the value was read as a quantity whose unit was 'barr + p_c', and
the message was "cannot read '+ p_c' in unit 'barr + p_c'" (left alone by session 24's first fix of unit
hints). A quantity alone with its unit misspelt, and a sum that is wrong for another reason, say what they
said before.
"""

from __future__ import annotations

import pytest

from test_unspaced_unit_s24 import MISSPELT, said


@pytest.mark.parametrize("p_set, message", [
    ("10 barr + p_c", MISSPELT),
    ("10 barr+p_c", MISSPELT),
    ("2*10 barr + p_c", MISSPELT),
    ("10 barr", MISSPELT),  # a quantity alone: as before
    ("10 bar +", "p_set: cannot read '+' in unit 'bar +'"),  # as before: no unit is misspelt
    ("10 m/ss + p_c", "p_set: unknown unit 'ss' (did you mean s?)"),
])
def test_a_misspelt_unit_at_the_start_of_an_expression(tmp_path, capsys, p_set, message):
    assert said(tmp_path, capsys, p_set) == message
