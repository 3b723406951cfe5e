"""The score test against its closed form: for a linear model the score statistic T equals the drop of chi^2
that refitting with the candidate brings, and the linearised estimate equals the refitted one."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from blocks.calibrate.candidates.base import Place
from blocks.calibrate.fit import FitResult
from blocks.calibrate.screening import screen


class LinearModel:
    """r(x) = A x - y: columns 0..1 the free parameters, 2.. the candidates."""

    def __init__(self, A, y):
        self.A, self.y = A, y
        self.data = SimpleNamespace(kind="time")
        names = [f"theta{k}" for k in range(A.shape[1])]
        self.layout = SimpleNamespace(names=lambda: names,
                                      globals=[SimpleNamespace(name=n, kind="declared") for n in names])

    def residuals(self, x, points=None):
        return self.A @ x - self.y


def base_fit(model, n_free):
    A = model.A[:, :n_free]
    theta, *_ = np.linalg.lstsq(A, model.y, rcond=None)
    x = np.zeros(model.A.shape[1])
    x[:n_free] = theta
    r = model.residuals(x)
    active = np.zeros(model.A.shape[1], dtype=bool)
    active[:n_free] = True
    rows = np.ones(len(r), dtype=bool)
    return x, FitResult(x, active, rows, r, A, float(r @ r), len(r), n_free, np.eye(n_free),
                        np.full(len(x), np.nan), 0, "", 0, [])


def place(key, one_sided=False, upper=np.inf):
    return Place("test", key, key, key, "1", 0.0, 0.0 if one_sided else -np.inf, upper, 1.0, (-1e9, 1e9),
                 one_sided=one_sided)


def test_score_equals_the_chi2_drop_of_the_refit_for_a_linear_model():
    rng = np.random.default_rng(3)
    n = 200
    t = np.linspace(0, 1, n)
    A = np.column_stack([np.ones(n), t, t ** 2, np.sin(7 * t)])
    y = 1.0 + 2.0 * t + 0.8 * t ** 2 + rng.normal(size=n)  # the t^2 candidate is present, sin(7t) is not
    model = LinearModel(A, y)
    x, base = base_fit(model, 2)
    scores, consistency = screen(model, x, base, [place("quad"), place("sine")], {"quad": 2, "sine": 3})
    assert consistency == 0.0
    for score, col in zip(scores, (2, 3)):
        full = A[:, [0, 1, col]]
        coef, *_ = np.linalg.lstsq(full, y, rcond=None)
        chi2_refit = float(np.sum((full @ coef - y) ** 2))
        assert score.status == "screened"
        assert score.T == pytest.approx(base.chi2 - chi2_refit, rel=1e-9)
        assert score.phi == pytest.approx(coef[2], rel=1e-9)
    assert scores[0].p_value < 1e-3 < scores[1].p_value or scores[1].T < 10


def test_absorbed_candidate_is_not_identifiable_and_names_what_absorbs_it():
    n = 50
    t = np.linspace(0, 1, n)
    A = np.column_stack([np.ones(n), t, 3.0 - 2.0 * t])  # the candidate is a combination of the free columns
    model = LinearModel(A, 1.0 + t)
    x, base = base_fit(model, 2)
    (score,), _ = screen(model, x, base, [place("same")], {"same": 2})
    assert score.status == "not identifiable"
    assert set(score.absorbed_by) == {"theta0", "theta1"} and score.absorbed > 0.999
    # a per-group parameter's copy is named; a latent input (a steady point's true input) is "the latent inputs"
    model.layout.globals = [SimpleNamespace(name="k[a]", kind="declared"), SimpleNamespace(name="Q[3]", kind="latent"),
                            SimpleNamespace(name="theta2", kind="candidate")]
    model.layout.names = lambda: ["k[a]", "Q[3]", "theta2"]
    (score,), _ = screen(model, x, base, [place("same")], {"same": 2})
    assert set(score.absorbed_by) == {"k[a]", "the latent inputs"}


def test_one_sided_candidate_pulled_below_zero_scores_nothing():
    rng = np.random.default_rng(4)
    n = 100
    t = np.linspace(0, 1, n)
    A = np.column_stack([np.ones(n), t ** 2])
    y = 1.0 - 5.0 * t ** 2 + rng.normal(size=n)  # unit noise; the data want a negative loss
    model = LinearModel(A, y)
    x, base = base_fit(model, 1)
    (score,), _ = screen(model, x, base, [place("loss", one_sided=True)], {"loss": 1})
    assert score.T == 0.0 and "wrong sign" in score.note
    (two_sided,), _ = screen(model, x, base, [place("loss2")], {"loss2": 1})
    assert two_sided.T > 100 and two_sided.phi < 0


def test_a_candidate_without_effect_is_reported_as_such():
    n = 20
    A = np.column_stack([np.ones(n), np.zeros(n)])
    model = LinearModel(A, np.ones(n))
    x, base = base_fit(model, 1)
    (score,), _ = screen(model, x, base, [place("none")], {"none": 1})
    assert score.status == "no effect"


class JumpModel(LinearModel):
    """The linear model with a candidate (column 2) whose effect is a jump: 0 below a threshold of its value,
    a fixed change of the residuals above it (a steady point whose solution switches, not a physical effect)."""

    def __init__(self, A, y, threshold, jump):
        super().__init__(A, y)
        self.threshold, self.jump = threshold, jump

    def residuals(self, x, points=None):
        r = self.A[:, :2] @ x[:2] - self.y
        return r + (self.jump if x[2] > self.threshold else 0.0)


def test_a_candidate_whose_change_is_a_jump_is_no_effect_however_it_would_score():
    # an extra volume on a steady rig scored T = 14 this way (user review, session 22)
    rng = np.random.default_rng(5)
    n = 100
    t = np.linspace(0, 1, n)
    A = np.column_stack([np.ones(n), t, np.zeros(n)])
    y = 1.0 + 2.0 * t + rng.normal(size=n)
    x, base = base_fit(LinearModel(A, y), 2)
    r = base.r
    jump = -0.5 * (r - r.mean())  # a change pointing along the residuals: the score would be large
    model = JumpModel(A, y, threshold=0.7, jump=jump)
    (score,), _ = screen(model, x, base, [place("jump")], {"jump": 2})
    assert score.status == "no effect" and "not proportional" in score.note
    # the same change, proportional to the candidate's value, is scored (as its closed form says)
    linear = LinearModel(np.column_stack([A[:, :2], jump]), y)
    (scored,), _ = screen(linear, x, base, [place("linear")], {"linear": 2})
    assert scored.status == "screened" and scored.T > 10


class ThresholdModel(LinearModel):
    """The linear model whose candidate (column 2) acts only from a smallest value on, as a transport delay does
    (below T_min it passes its input through): below ``threshold`` it changes nothing."""

    def __init__(self, A, y, threshold):
        super().__init__(A, y)
        self.threshold = threshold

    def residuals(self, x, points=None):
        x = np.array(x, dtype=float)
        if x[2] < self.threshold:
            x[2] = 0.0
        return self.A @ x - self.y


def test_a_candidate_in_force_only_from_a_smallest_value_is_scored_at_the_larger_step():
    # review, session 22: a strong delay's step ended at 1e-5 s, half of it passed the input through, and the
    # delay was called 'no effect'; at 10 times the step it is first order, and scored as its closed form says
    rng = np.random.default_rng(7)
    n = 200
    t = np.linspace(0, 1, n)
    effect = 2.5 * np.sin(5 * t)
    A = np.column_stack([np.ones(n), t, effect])
    y = 1.0 + 2.0 * t + 0.3 * effect + rng.normal(size=n)
    x, base = base_fit(LinearModel(A, y), 2)
    first = Place("test", "delay", "delay", "delay", "s", 0.0, 0.0, np.inf, 0.4, (0.0, 1e9), one_sided=True)
    (score,), _ = screen(ThresholdModel(A, y, threshold=0.3), x, base, [first], {"delay": 2})
    assert score.status == "screened" and score.step == pytest.approx(4.0)
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    assert score.T == pytest.approx(base.chi2 - float(np.sum((A @ coef - y) ** 2)), rel=1e-9)
    assert score.phi == pytest.approx(coef[2], rel=1e-9)
