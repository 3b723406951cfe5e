"""The score test of blocks/calibrate/screening.py on linear models, against closed forms written here: the
absorbed fraction 1 - |s_perp|^2 / |s|^2 (s_perp: s minus its least-squares projection on the free
columns), the 99.9 % threshold of "not identifiable", the one-sided p-value (half the chi^2_1 tail) and a
one-sided candidate whose zero is not 0.

Added from a mutation-testing pass (session 26): each test failed on a mutant the existing tests let
through. For a linear model the finite-difference sensitivity is the column itself up to rounding (rel
~1e-12 of its size), so rel 1e-8 is a rounding tolerance."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats as sps

from blocks.calibrate.candidates.base import Place
from blocks.calibrate.fit import FitResult
from blocks.calibrate.screening import screen

from test_screening import LinearModel, ThresholdModel

N = 120
T = np.linspace(0.0, 1.0, N)
FREE = np.column_stack([np.ones(N), T])


def _screen(column, y, zero=0.0, one_sided=False, upper=np.inf):
    """Screen the candidate ``column`` (its parameter at ``zero``) at the least-squares fit of the free columns."""
    A = np.column_stack([FREE, column])
    theta = np.linalg.lstsq(FREE, y - zero * column, rcond=None)[0]
    x = np.array([theta[0], theta[1], zero])
    model = LinearModel(A, y)
    r = model.residuals(x)
    active = np.array([True, True, False])
    base = FitResult(x, active, np.ones(N, bool), r, FREE, float(r @ r), N, 2, np.eye(2), np.full(3, np.nan), 0, "",
                     0, [])
    place = Place("test", "c", "c", "c", "1", zero, zero if one_sided else -np.inf, upper, 1.0, (-1e9, 1e9),
                  one_sided=one_sided)
    (score,), _ = screen(model, x, base, [place], {"c": 2})
    return score, r


def _perp(c):
    return c - FREE @ np.linalg.lstsq(FREE, c, rcond=None)[0]


def _tilted(ratio, scale):
    """A column of norm ``scale`` whose part outside the free columns' span has squared norm ratio * scale^2."""
    q = np.linalg.qr(np.column_stack([FREE, np.sin(7.0 * T)]))[0]
    inside, outside = q[:, 1], q[:, 2]  # unit vectors: in the span, and orthogonal to it
    return scale * (np.sqrt(1.0 - ratio) * inside + np.sqrt(ratio) * outside)


def test_absorbed_fraction_is_one_minus_the_unabsorbed_share_of_the_sensitivity():
    """absorbed = 1 - |s_perp|^2 / |s|^2 for a candidate the free columns absorb in part."""
    c = 0.4 * T + 0.3 * np.sin(5.0 * T)
    y = 1.0 + 2.0 * T + 0.05 * np.random.default_rng(1).normal(size=N)
    score, r = _screen(c, y)
    sp = _perp(c)
    assert score.status == "screened"
    assert score.absorbed == pytest.approx(1.0 - (sp @ sp) / (c @ c), rel=1e-8)
    assert score.T == pytest.approx((sp @ r) ** 2 / (sp @ sp), rel=1e-8)


@pytest.mark.parametrize("ratio, status", [(0.95e-3, "not identifiable"), (1.05e-3, "screened")])
@pytest.mark.parametrize("scale", [1.0, 40.0])
def test_not_identifiable_when_the_free_parameters_absorb_over_99_9_percent(ratio, status, scale):
    """|s_perp|^2 < 1e-3 |s|^2: not identifiable, whatever the sensitivity's size (scale 1 and 40)."""
    c = _tilted(ratio, scale)
    assert (_perp(c) @ _perp(c)) / (c @ c) == pytest.approx(ratio, rel=1e-9)
    y = 1.0 + 2.0 * T + np.random.default_rng(2).normal(size=N)
    score, _ = _screen(c, y)
    assert score.status == status


def test_one_sided_p_value_is_half_the_chi2_1_tail_and_two_sided_the_whole():
    """A one-sided parameter pulled to its allowed side: p = 0.5 * P(chi^2_1 > T); two-sided: P(chi^2_1 > T)."""
    c = T ** 2
    y = 1.0 + 2.0 * T + 3.0 * T ** 2 + np.random.default_rng(3).normal(size=N)  # phi near 3: T near 9 * 0.67
    for one_sided in (True, False):
        score, _ = _screen(c, y, one_sided=one_sided)
        assert score.phi > 0 and score.T > 1
        assert score.p_value == pytest.approx(sps.chi2.sf(score.T, 1) * (0.5 if one_sided else 1.0), rel=1e-12)


def test_a_one_sided_candidate_whose_zero_is_not_0_is_judged_by_its_side_of_the_zero():
    """zero = 1, allowed side above it: data that want 0.6 (below 1, though positive) pull it to the wrong
    sign (T = 0, p = 1); data that want 1.4 are scored, with phi the linearised estimate 1 - g / |s_perp|^2."""
    c = 20.0 * T ** 2  # |s_perp|^2 = 400 * 120 / 180: phi's SE 0.04 at unit noise, T = (0.4)^2 * 267 = 43
    noise = np.random.default_rng(4).normal(size=N)
    below, _ = _screen(c, 1.0 + 2.0 * T + 0.6 * c + noise, zero=1.0, one_sided=True)
    assert below.phi == pytest.approx(0.6, abs=0.2)  # 0.2: 5 standard errors of phi
    assert below.T == 0.0 and below.p_value == 1.0 and "wrong sign" in below.note
    above, r = _screen(c, 1.0 + 2.0 * T + 1.4 * c + noise, zero=1.0, one_sided=True)
    sp = _perp(c)
    assert above.T == pytest.approx((sp @ r) ** 2 / (sp @ sp), rel=1e-8) and above.T > 10
    assert above.phi == pytest.approx(1.0 - (sp @ r) / (sp @ sp), rel=1e-8)


def test_a_weak_candidate_with_a_finite_room_grows_its_step_until_it_moves_the_residuals():
    """A candidate moving no residual by 1e-2 sigma at its first step has its step multiplied by 30 while half
    its room (here 1e6) allows: it is screened, at the closed-form score, with a step far above its first."""
    c = 1e-4 * np.sin(3.0 * T)  # at the first step 1: max change 1e-4 sigma
    y = 1.0 + 2.0 * T + np.random.default_rng(6).normal(size=N)
    score, r = _screen(c, y, one_sided=False, upper=1e6)
    sp = _perp(c)
    assert score.status == "screened" and score.step > 30.0
    assert score.T == pytest.approx((sp @ r) ** 2 / (sp @ sp), rel=1e-6)  # rel 1e-6: differences of r at 1e-2
    assert score.phi == pytest.approx(-(sp @ r) / (sp @ sp), rel=1e-6)  # the sensitivity is d / h, not d * h
    room, _ = _screen(c, y, one_sided=False, upper=100.0)  # 30 times the step would pass half the room (50)
    assert 0 < room.step <= 50.0


def test_the_step_stays_within_half_the_candidates_room():
    """upper - zero = 0.1: the step is at most 0.05, never the first step 1 beyond the candidate's bound."""
    c = 20.0 * np.cos(2.0 * T)
    y = 1.0 + 2.0 * T + np.random.default_rng(7).normal(size=N)
    score, r = _screen(c, y, one_sided=False, upper=0.1)
    assert score.status == "screened" and 0 < score.step <= 0.05
    sp = _perp(c)
    assert score.T == pytest.approx((sp @ r) ** 2 / (sp @ sp), rel=1e-8)
    assert score.phi == pytest.approx(-(sp @ r) / (sp @ sp), rel=1e-8)


def test_the_absorbers_named_are_the_two_largest_contributions():
    """A candidate the free columns reproduce exactly as 3 u1 + 0.6 u2 + 0.001 u3 (u: orthonormal columns,
    so each contribution is its coefficient): not identifiable, absorbed by u1 and u2, the largest first; u3
    (0.03 % of the largest, under the 5 % cut) is not named."""
    from types import SimpleNamespace

    q = np.linalg.qr(np.column_stack([np.ones(N), T, T ** 2]))[0]
    c = 3.0 * q[:, 0] + 0.6 * q[:, 1] + 0.001 * q[:, 2]
    A = np.column_stack([q, c])
    y = np.random.default_rng(8).normal(size=N)
    theta = np.linalg.lstsq(q, y, rcond=None)[0]
    x = np.append(theta, 0.0)
    names = ["u1", "u2", "u3", "cand"]
    model = LinearModel(A, y)
    model.layout = SimpleNamespace(names=lambda: names,
                                   globals=[SimpleNamespace(name=n, kind="declared") for n in names])
    r = model.residuals(x)
    base = FitResult(x, np.array([True, True, True, False]), np.ones(N, bool), r, q, float(r @ r), N, 3, np.eye(3),
                     np.full(4, np.nan), 0, "", 0, [])
    place = Place("test", "cand", "cand", "cand", "1", 0.0, -np.inf, np.inf, 1.0, (-1e9, 1e9), one_sided=False)
    (score,), _ = screen(model, x, base, [place], {"cand": 3})
    assert score.status == "not identifiable"
    assert score.absorbed_by == ["u1", "u2"]


@pytest.mark.parametrize("upper, larger", [(100.0, 5.0), (6.0, 3.0)])
def test_the_larger_step_is_ten_times_the_first_within_half_the_room(upper, larger):
    """First step 0.5, in force from 0.4: half the step (0.25) changes nothing, so the change is not first order
    there; it is tried again at min(10 * 0.5, (upper - zero) / 2) and scored at that step (closed-form T)."""
    c = 2.0 * np.sin(4.0 * T)
    y = 1.0 + 2.0 * T + np.random.default_rng(9).normal(size=N)
    A = np.column_stack([FREE, c])
    theta = np.linalg.lstsq(FREE, y, rcond=None)[0]
    x = np.array([theta[0], theta[1], 0.0])
    model = ThresholdModel(A, y, 0.4)
    r = model.residuals(x)
    base = FitResult(x, np.array([True, True, False]), np.ones(N, bool), r, FREE, float(r @ r), N, 2, np.eye(2),
                     np.full(3, np.nan), 0, "", 0, [])
    place = Place("test", "c", "c", "c", "1", 0.0, -np.inf, upper, 0.5, (-1e9, 1e9), one_sided=False)
    (score,), _ = screen(model, x, base, [place], {"c": 2})
    sp = _perp(c)
    assert score.status == "screened" and score.step == larger
    assert score.T == pytest.approx((sp @ r) ** 2 / (sp @ sp), rel=1e-8)
