"""The held-out score: the Gaussian log score of a held-out block's outputs under the spread that its
recorded command's knots leave (blocks/calibrate/heldout.py).

The algebra against the dense form (that the score is the error itself where the inputs are known is in
tests/calibrate/test_heldout_convergence.py, on steady points); and on
the drive line's example data (a recorded command, noise 0.005 on levels of 0.1 to 0.2), that the right
model's held-out residuals are wider than the noise, and that whitened by S = I + J_k C_k J_k^T they are
the noise's width again: the propagated spread is of the right size, neither ignored nor inflated."""

from __future__ import annotations

import numpy as np
import pytest

from blocks.calibrate.heldout import gaussian_deviance, heldout
from blocks.calibrate.run import calibrate
from tests.calibrate.test_recorded_traces import _trace_experiment


def test_the_woodbury_form_is_the_dense_one():
    rng = np.random.default_rng(3)
    r, A = rng.normal(size=40), rng.normal(size=(40, 5))
    S = np.eye(40) + A @ A.T
    quadratic, log_det = gaussian_deviance(r, A)
    assert quadratic == pytest.approx(r @ np.linalg.solve(S, r), rel=1e-10)
    assert log_det == pytest.approx(np.linalg.slogdet(S)[1], rel=1e-10)
    assert gaussian_deviance(r, np.zeros((40, 0))) == (pytest.approx(r @ r), 0.0)


def test_a_wider_spread_lowers_the_quadratic_and_charges_the_determinant():
    rng = np.random.default_rng(4)
    r, A = rng.normal(size=30), rng.normal(size=(30, 2))
    narrow, wide = gaussian_deviance(r, 0.5 * A), gaussian_deviance(r, 2.0 * A)
    assert wide[0] < narrow[0] and wide[1] > narrow[1]


@pytest.fixture(scope="module")
def recorded_friction(tmp_path_factory):
    """The example data (Coulomb friction 3 N*m planted) fitted with that friction: the right model."""
    tmp = tmp_path_factory.mktemp("recorded")
    exp = _trace_experiment(tmp, "drive_line_series.csv", latent=True,
                            trace={"rounds": 1, "only": ["coulomb_friction"]})
    cal = calibrate(exp, tmp / "out", with_heldout=False)
    assert [a[0] for a in cal.accepted] == ["coulomb_friction@shaft"]  # the premise
    return cal


def test_the_right_models_held_out_residuals_whiten_to_the_noise(recorded_friction):
    final = recorded_friction.final
    ho = heldout(final.model, final.fit, recorded_friction.exp.spec.heldout)
    n = ho.n
    assert ho.knots > 0
    # the premise: predicted from the recording, the right model misses by more than the noise
    assert ho.error > 1.0 + 5.0 * np.sqrt(2.0 / n), ho.error
    # whitened by the knots' propagated spread, chi^2/n of the noise again (its SD is sqrt(2/n))
    assert abs(ho.whitened - 1.0) < 4.0 * np.sqrt(2.0 / n), (ho.whitened, ho.error)
    assert ho.score > ho.whitened  # ln det S > 0 whenever a knot reaches the block
