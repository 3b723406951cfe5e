"""Standard errors of a fit (blocks/calibrate/fit.py) against the closed form of linear least squares.

A straight line y = a + b*t through points with unit noise (the residuals are already normalised): the
covariance of (a, b) is (X^T X)^-1, with X = [1, t], inflated by chi^2/nu when that is over 1. A point whose
run fails holds the failure penalty (FAILED_RESIDUAL) in its row, not a residual: it must change neither.
"""

from types import SimpleNamespace

import numpy as np
import pytest

from blocks.calibrate.fit import fit
from blocks.calibrate.model import FAILED_RESIDUAL

T = np.linspace(0.0, 4.0, 9)


class _Line:
    """r = a + b*t - y over the points, and, with ``failing``, one more row whose run always fails."""

    data = SimpleNamespace(kind="time")

    def __init__(self, y: np.ndarray, failing: bool):
        self.y, self.failing = y, failing
        self.n_rows = len(y) + failing
        self.failures = []

    def residuals(self, x, points=None):
        r = x[0] + x[1] * T - self.y
        if self.failing:
            self.failures.append("the solver failed at t = 0.1 s")
            r = np.append(r, FAILED_RESIDUAL)
        return r

    def jacobian(self, x, cols, points, r0):
        J = np.column_stack([np.ones_like(T), T])
        if self.failing:
            J = np.vstack([J, np.zeros(2)])  # no slope where every perturbed run fails too
        return J[:, cols]

    def bounds(self):
        return np.full(2, -1e3), np.full(2, 1e3)

    def steps(self):
        return np.full(2, 1e-6)


def _closed_form_se(y: np.ndarray) -> np.ndarray:
    X = np.column_stack([np.ones_like(T), T])
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    chi2 = float(np.sum((X @ coef - y) ** 2))
    cov = np.linalg.inv(X.T @ X) * max(1.0, chi2 / (len(T) - 2))
    return np.sqrt(np.diag(cov))


@pytest.mark.parametrize("spread", [0.5, 3.0], ids=["within the noise", "a misfit, inflated"])
def test_a_point_whose_run_fails_changes_no_standard_error(spread):
    y = 1.0 + 2.0 * T + spread * np.random.default_rng(4).normal(size=T.size)
    expected = _closed_form_se(y)
    for failing in (False, True):
        res = fit(_Line(y, failing), np.zeros(2), np.array([True, True]))
        assert res.failed_rows == int(failing)
        assert np.allclose(res.se, expected, rtol=1e-6), (failing, res.se, expected)
    assert res.chi2 > FAILED_RESIDUAL ** 2  # the penalty stays in chi^2 (and so in BIC)


def test_the_slope_of_a_failed_row_is_not_read_as_information():
    """A perturbed run that did not fail gives the failed row a slope (r - 1e3)/h of about 1e9: no
    information, but in J^T J it would make both parameters look known to 1e-9."""
    from blocks.calibrate.fit import summarise

    y = 1.0 + 2.0 * T + 0.5 * np.random.default_rng(4).normal(size=T.size)
    X = np.column_stack([np.ones_like(T), T])
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    model = _Line(y, failing=True)
    r = model.residuals(coef)
    J = np.vstack([X, np.full(2, 1e9)])
    res = summarise(model, coef, np.array([True, True]), np.ones(len(r), dtype=bool), r, J)
    assert np.allclose(res.se, _closed_form_se(y), rtol=1e-6)
