"""Gaps found by mutation testing blocks/datafile.py (session 27).

The reader's errors name the file, the line and the column counted from 1 as a person counts them in an
editor (module docstring of blocks.datafile); ``Table.in_unit`` converts an SI column to any unit of its
dimension. Each test checks against a count or a conversion done by hand.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from blocks.datafile import DataFileError, header_of, read_table


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def test_header_of_names_the_column_counted_from_one(tmp_path):
    """header_of (used for experiment group tables) locates a bad header cell by its 1-based column: the
    third cell of the header line is column 3, as an editor counts it, on line 2 (after a comment)."""
    path = write(tmp_path / "h.csv", "# a comment\nsetting,p1 [bar],Q []\n1,2,3\n")
    with pytest.raises(DataFileError) as info:
        header_of(path)
    err = info.value
    assert (err.file, err.line, err.column) == (str(path), 2, 3)
    assert str(err).startswith(f"{path}:2:3: ")


def test_header_of_returns_each_column_with_its_unit(tmp_path):
    """header_of gives (name, unit) per column, the unit None where the cell has no brackets and '1' for
    '[-]', on the first line that is not a comment (line 3 here)."""
    path = write(tmp_path / "h.csv", "# one\n\n setting , p1 [bar],k [-]\n1,2,3\n")
    assert header_of(path) == (3, [("setting", None), ("p1", "bar"), ("k", "1")])


def test_named_group_header_error_names_the_column_counted_from_one(tmp_path):
    """With the grouping column named by the caller (an experiment file), a bad header cell is still located
    at its 1-based column: the second cell is column 2."""
    path = write(tmp_path / "g.csv", "setting,p1 [furlong],Q [l/min]\na,1,2\n")
    with pytest.raises(DataFileError) as info:
        read_table(path, group="setting")
    assert (info.value.file, info.value.line, info.value.column) == (str(path), 1, 2)


def test_in_unit_converts_to_another_unit_and_defaults_to_the_written_one(tmp_path):
    """in_unit(name, unit) is the SI column divided by the unit's factor: 2.5 bar is 250 kPa and 36.2594 psi
    (1 psi = 6894.757 Pa); without a unit it gives the column in the unit it was written in (2.5 bar)."""
    path = write(tmp_path / "u.csv", "p [bar],Q [l/min]\n2.5,60\n1,30\n")
    table = read_table(path)
    np.testing.assert_allclose(table.in_unit("p", "kPa"), [250.0, 100.0], rtol=1e-12)
    np.testing.assert_allclose(table.in_unit("p", "psi"), [2.5e5 / 6894.757293168, 1e5 / 6894.757293168], rtol=1e-9)
    np.testing.assert_allclose(table.in_unit("Q", "m^3/s"), [1e-3, 5e-4], rtol=1e-12)
    np.testing.assert_allclose(table.in_unit("p"), [2.5, 1.0], rtol=1e-12)
    np.testing.assert_allclose(table.in_unit("Q"), [60.0, 30.0], rtol=1e-12)
