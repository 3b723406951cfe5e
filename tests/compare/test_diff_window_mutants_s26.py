"""``vphs diff --t-from/--t-to``: reference points lying exactly on the window's ends are compared (the window
is widened by the edge tolerance, 1e-9 of the span, as compare() allows at a curve's ends).

Added from a mutation-testing pass (session 26): narrowing the window by that tolerance instead of widening it
left both end points out unnoticed. Expected numbers worked out by hand from the points written here."""

from __future__ import annotations

import csv
import math

import pytest

from test_diff import run, write

SIM = "t [s],p [bar]\n0,10\n0.1,10\n0.2,10\n0.3,20\n0.4,30\n0.5,40\n0.6,50\n"
# reference at the window's ends and inside it, and one before it: errors 20-21 = -1, 30-30 = 0, 40-38 = +2
REF = "t [s],p [bar]\n0.1,11\n0.3,21\n0.4,30\n0.5,38\n"


def test_reference_points_on_the_window_ends_are_compared(tmp_path, capsys):
    """Window 0.3 .. 0.5 s: the points at 0.3 and 0.5 s are in it (n = 3, RMSE sqrt(5/3), mean 1/3, max 2 at
    0.5 s); only the one at 0.1 s is left out."""
    sim, ref = write(tmp_path / "sim.csv", SIM), write(tmp_path / "ref.csv", REF)
    out = tmp_path / "table.csv"
    code, stdout, err = run(capsys, "diff", sim, ref, "--t-from", "0.3", "--t-to", "0.5", "-o", out)
    assert code == 0, err
    (row,) = list(csv.DictReader(open(out)))
    assert row["n"] == "3"
    assert float(row["rmse"]) == pytest.approx(math.sqrt(5.0 / 3.0), rel=1e-9)
    assert float(row["mean_error"]) == pytest.approx(1.0 / 3.0, rel=1e-9)
    assert float(row["max_abs_error"]) == pytest.approx(2.0, rel=1e-9)

