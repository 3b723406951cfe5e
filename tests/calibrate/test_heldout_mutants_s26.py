"""The held-out error (blocks/calibrate/heldout.py heldout) of a model whose refit has a closed form: two
output channels, each a constant (an offset fitted by least squares), steady points in three groups, held
out one group at a time. The refit without a group is the mean of the other groups' readings, so every
held-out residual, the per-fold mean, the per-channel chi^2/n and RMSE, and the pooled error are known by
hand.

Added from a mutation-testing pass (session 26): squaring or rooting these reported numbers wrongly was not
seen by the fast held-out tests. Tolerance rel 1e-6: the refit is scipy's least squares to tol 1e-8 on a
problem it solves in one step; its answer agrees with the mean to far better than 1e-6."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from blocks.calibrate.fit import fit
from blocks.calibrate.heldout import heldout

GROUPS = {"A": np.arange(0, 4), "B": np.arange(4, 8), "C": np.arange(8, 12)}
SIGMA = np.array([2.0, 0.5])  # p, q


class _Offsets:
    """Residuals (a - y_p) / sigma_p and (b - y_q) / sigma_q at each of 12 steady points; rows: p then q."""

    def __init__(self, yp, yq):
        self.yp, self.yq = yp, yq
        n = yp.size
        self.n_rows = 2 * n
        self.row_point = np.tile(np.arange(n), 2)
        self.row_channel = np.repeat([0, 1], n)
        self.channels = [SimpleNamespace(name="p", role="output"), SimpleNamespace(name="q", role="output")]
        self.sigma = SIGMA
        self.data = SimpleNamespace(kind="steady", n=n, groups=GROUPS, sources=None)
        self.layout = SimpleNamespace(inputs=[], globals=[SimpleNamespace(name=k, kind="declared", run=None,
                                                                          initial=0.0) for k in "ab"])
        self.failures, self.unsettled = [], []

    def residuals(self, x, points=None):
        return np.concatenate([(x[0] - self.yp) / SIGMA[0], (x[1] - self.yq) / SIGMA[1]])

    def jacobian(self, x, cols, points, r0):
        J = np.zeros((self.n_rows, 2))
        J[: self.yp.size, 0] = 1 / SIGMA[0]
        J[self.yp.size:, 1] = 1 / SIGMA[1]
        return J[:, cols]

    def bounds(self):
        return np.full(2, -1e3), np.full(2, 1e3)

    def steps(self):
        return np.full(2, 1e-6)

    def rows_of_points(self, points):
        sel = np.zeros(self.data.n, dtype=bool)
        sel[np.asarray(points, dtype=int)] = True
        return sel[self.row_point]

    def output_rows(self):
        return np.ones(self.n_rows, dtype=bool)


def test_held_out_errors_of_an_offset_model_by_hand():
    """Each group predicted by the other groups' mean: residual (mean_others - y) / sigma; per fold the mean
    of its squared residuals (both channels), per channel chi^2/n and RMSE = sqrt(mean((r sigma)^2)), pooled
    the mean over all 24 held-out rows (the score equals it: no latent knots)."""
    rng = np.random.default_rng(21)
    yp = 10.0 + SIGMA[0] * rng.normal(size=12) + np.repeat([0.0, 3.0, -2.0], 4)  # groups disagree: errors > 1
    yq = -4.0 + SIGMA[1] * rng.normal(size=12)
    model = _Offsets(yp, yq)
    res = fit(model, np.zeros(2), np.array([True, True]))
    ho = heldout(model, res, SimpleNamespace(scheme="leave_one_group_out", k=5, seed=0))
    rp, rq, folds = np.zeros(12), np.zeros(12), []
    for label, idx in GROUPS.items():
        others = np.setdiff1d(np.arange(12), idx)
        rp[idx] = (yp[others].mean() - yp[idx]) / SIGMA[0]
        rq[idx] = (yq[others].mean() - yq[idx]) / SIGMA[1]
        folds.append((label, 8, np.mean(np.concatenate([rp[idx], rq[idx]]) ** 2)))
    assert ho.scheme == "leave one group out" and ho.n == 24
    for (name, n, err), (label, n_exp, err_exp) in zip(ho.folds, folds):
        assert (name, n) == (label, n_exp) and err == pytest.approx(err_exp, rel=1e-6)
    assert ho.chi2n["p"] == pytest.approx(np.mean(rp ** 2), rel=1e-6)
    assert ho.chi2n["q"] == pytest.approx(np.mean(rq ** 2), rel=1e-6)
    assert ho.rmse["p"] == pytest.approx(np.sqrt(np.mean((rp * SIGMA[0]) ** 2)), rel=1e-6)
    assert ho.rmse["q"] == pytest.approx(np.sqrt(np.mean((rq * SIGMA[1]) ** 2)), rel=1e-6)
    pooled = np.mean(np.concatenate([rp, rq]) ** 2)
    assert ho.error == pytest.approx(pooled, rel=1e-6) and ho.score == pytest.approx(pooled, rel=1e-6)
    assert ho.error > 1.5  # the groups' shifts make the prediction worse than the noise
