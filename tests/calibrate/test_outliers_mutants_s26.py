"""The table of the largest residuals (blocks/calibrate/outliers.py largest, verdict_line) against its
definition: |z| sorted, the Bonferroni bound of the rows that ran (failed rows left out), the fitted value
= reading + z * sigma in the channel's display unit, dropped only where the rounding of a huge reading
exceeds 1e-3 sigma, and the verdict naming at most 3 of the residuals beyond the bound.

Added from a mutation-testing pass (session 26): each test failed on a mutant the existing tests let
through."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats as sps

from blocks.calibrate import outliers
from blocks.calibrate.model import FAILED_RESIDUAL


def _stage(measured, z, sigma, unit="bar"):
    n = len(z)
    model = SimpleNamespace(channels=[SimpleNamespace(name="p1", role="output", unit=unit)],
                            row_channel=np.zeros(n, dtype=int), row_point=np.arange(n),
                            measured=np.asarray(measured, float), row_sigma=np.full(n, sigma))
    fit = SimpleNamespace(rows=np.ones(n, bool), r=np.asarray(z, float))
    exp = SimpleNamespace(data_files=None, data="rig.csv", spec=SimpleNamespace(group=None))
    data = SimpleNamespace(table=SimpleNamespace(lines=list(range(3, 3 + n))), n=n, groups={"all": np.arange(n)},
                           kind="steady", labels=None, t=None)
    return exp, data, SimpleNamespace(model=model, fit=fit)


def test_largest_residuals_bound_order_and_fitted_values_in_the_display_unit():
    """12 rows, one failed (its penalty is no residual): the bound is for 11 residuals, Phi^-1(1 - 0.005/11);
    rows sorted by |z| with file:line; measured and fitted (reading + z sigma) in bar."""
    z = np.array([0.3, -5.0, 1.0, 4.2, -0.1, 0.0, 2.0, FAILED_RESIDUAL, -0.7, 0.5, 1.5, -2.5])
    measured = 1e5 * np.arange(20.0, 32.0)
    exp, data, stage = _stage(measured, z, 2e4)
    info = outliers.largest(exp, data, stage, shown=4)
    assert info["residuals"] == 11
    assert info["bound"] == pytest.approx(sps.norm.ppf(1 - 0.005 / 11), rel=1e-12)
    assert [r["z"] for r in info["rows"]] == [-5.0, 4.2, -2.5, 2.0]
    assert 3.3 < info["bound"] < 4.2  # 3.32: -5 and 4.2 beyond it
    assert info["beyond_bound"] == 2 and [r["beyond_bound"] for r in info["rows"]] == [True, True, False, False]
    first = info["rows"][0]
    assert first["where"] == "rig.csv:4" and first["point"] == 1
    assert first["measured"] == pytest.approx(21.0, rel=1e-12)
    assert first["fitted"] == pytest.approx(21.0 - 5.0 * 0.2, rel=1e-12)


def test_the_fitted_value_is_dropped_only_where_a_huge_reading_rounds_it_away():
    """4 eps |reading| against 1e-3 sigma: a reading of 1e12 Pa with sigma 1e5 Pa rounds to 9e-4 Pa, far below
    100 Pa: shown; a reading of 2.3e30 rounds to 2e15 Pa: not shown (the residual itself stays exact)."""
    z = np.array([6.0, 0.1, -0.2, 0.3, 0.1, -0.1])
    for reading, shown in ((1e12, True), (2.3e30, False)):
        exp, data, stage = _stage([reading, 1e6, 1e6, 1e6, 1e6, 1e6], z, 1e5, unit="Pa")
        row = outliers.largest(exp, data, stage)["rows"][0]
        assert row["z"] == 6.0 and (row["fitted"] is not None) == shown
        if shown:
            assert row["fitted"] == pytest.approx(reading + 6.0 * 1e5, rel=1e-15)
    exp, data, stage = _stage([-1e12, 1e6, 1e6, 1e6, 1e6, 1e6], z, 1e5, unit="Pa")  # a negative reading alike
    assert outliers.largest(exp, data, stage)["rows"][0]["fitted"] == pytest.approx(-1e12 + 6e5, rel=1e-15)


def test_the_verdict_names_at_most_three_residuals_beyond_the_bound():
    """Five beyond the bound: three named, 'and 2 more'; one beyond: named alone; none: no line."""
    rows = [{"channel": "p1", "where": f"rig.csv:{k}", "z": 9.0 - k, "beyond_bound": True, "measured": 1.0,
             "fitted": 2.0, "unit": "bar"} for k in range(5)]
    info = {"beyond_bound": 5, "rows": rows, "bound": 3.71, "residuals": 48}
    (line,) = outliers.verdict_line(info)
    assert "rig.csv:0" in line and "rig.csv:2" in line and "rig.csv:3" not in line and "and 2 more" in line
    (line,) = outliers.verdict_line(dict(info, beyond_bound=1, rows=rows[:1]))
    assert line.startswith("gross residual: p1 at rig.csv:0 is 9 sigma off the final fit")
    assert outliers.verdict_line(dict(info, beyond_bound=0)) == []
