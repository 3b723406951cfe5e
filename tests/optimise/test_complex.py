"""The Complex method (thesis section 4.5): steps by hand, analytic optima, bounds, determinism, batching."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from blocks.optimise.complex import (ComplexSettings, complex_minimise, epsilon, forgetting_factor, reflect, retract)


class Scripted:
    """An evaluate() that records what it is asked and answers costs from a script, in order."""

    def __init__(self, costs):
        self.costs, self.points, self.info = list(costs), [], []

    def __call__(self, points, info):
        self.points += [np.array(p, float) for p in points]
        self.info += list(info)
        return [self.costs.pop(0) for _ in points]


# Complex A, B, C in the box [-10, 10]^2, costs 1, 2, 10: C is the worst, A the best.
A, B, C = (1.0, 1.0), (3.0, 1.0), (2.0, 4.0)
BOX = ([-10.0, -10.0], [10.0, 10.0])


def test_epsilon_eq_4_6_by_hand():
    assert epsilon(4, 1) == 1.0  # the first move is Box's: half-way to the centroid
    assert epsilon(4, 2) == pytest.approx(0.7565932872, rel=1e-9)  # (4/5)^(5/4) = exp(1.25 ln 0.8)
    assert epsilon(5, 3) == pytest.approx(0.6243394106, rel=1e-9)  # (5/7)^(7/5)
    values = [epsilon(4, n) for n in range(1, 60)]
    assert all(a > b for a, b in zip(values, values[1:])) and values[-1] < 1e-6  # toward the best design


def test_reflection_and_retractions_match_eqs_4_4_to_4_6_by_hand():
    # costs: the initial three, then the reflection (20: still worst), the first retraction (15: still
    # worst), the second (1.5: better than B's 2, accepted); then B is the worst and is reflected.
    f = Scripted([1.0, 2.0, 10.0, 20.0, 15.0, 1.5, 0.5])
    r = complex_minimise(f, *BOX, ComplexSettings(max_evaluations=7), initial=[A, B, C])
    # eq. 4.3: centroid of A and B = (2, 1); eq. 4.4: 1.3*((2, 1) - (2, 4)) + (2, 1) = (2, -2.9)
    np.testing.assert_allclose(f.points[3], [2.0, -2.9], rtol=0, atol=1e-12)
    # still worst, n_rep = 1, eps = 1: 0.5*((2, -2.9) + (2, 1)) = (2, -0.95)
    np.testing.assert_allclose(f.points[4], [2.0, -0.95], rtol=0, atol=1e-12)
    # n_rep = 2, eps = 0.7565932872: 0.5*((2, -0.95) + eps*(2, 1) + (1 - eps)*(1, 1))
    #   x = 0.5*(2 + 1.5131865744 + 0.2434067128) = 1.8782966436,  y = 0.5*(-0.95 + 1) = 0.025
    np.testing.assert_allclose(f.points[5], [1.8782966436, 0.025], rtol=0, atol=1e-9)
    assert [i["step"] for i in f.info[3:6]] == ["reflection", "retraction", "retraction"]
    assert [i["n_rep"] for i in f.info[3:6]] == [0, 1, 2]
    # next iteration: B (cost 2) is the worst; centroid of A and (1.8782966436, 0.025) = (1.4391483218, 0.5125);
    # reflection 1.3*((1.4391483218, 0.5125) - (3, 1)) + (1.4391483218, 0.5125) = (-0.5899588599, -0.12125)
    np.testing.assert_allclose(f.points[6], [-0.5899588599, -0.12125], rtol=0, atol=1e-9)
    assert f.info[6] == {"step": "reflection", "iteration": 2, "n_rep": 0}
    assert r.evaluations == 7 and r.reason == "budget"
    assert r.f == 0.5 and np.allclose(r.x, f.points[6])


def test_step_functions_are_the_equations():
    yc, yj, yb = np.array([2.0, 1.0]), np.array([2.0, 4.0]), np.array([1.0, 1.0])
    np.testing.assert_allclose(reflect(yc, yj), [2.0, -2.9])
    np.testing.assert_allclose(retract(np.array([2.0, -2.9]), yc, yb, 1.0), [2.0, -0.95])
    np.testing.assert_allclose(retract(np.array([2.0, -0.95]), yc, yb, 0.0), [1.5, 0.025])  # eps = 0: toward the best


def test_a_reflection_outside_the_box_is_clipped_onto_the_bound():
    f = Scripted([1.0, 2.0, 10.0, 0.0])
    complex_minimise(f, [0.0, 0.0], [10.0, 10.0], ComplexSettings(max_evaluations=4), initial=[A, B, C])
    np.testing.assert_allclose(f.points[3], [2.0, 0.0])  # (2, -2.9) clipped onto y = 0


def test_forgetting_factor_by_hand_and_its_effect():
    # K_f = 1 - (1.3/2)^(0.3/4) = 1 - exp(0.075*ln 0.65) = 0.0317923679
    assert forgetting_factor(1.3, 0.3, 4) == pytest.approx(0.0317923679, rel=1e-8)
    assert forgetting_factor(1.3, 0.0, 4) == 0.0
    # a reflection costing 2.1 is worse than B (2): without forgetting it is retracted
    f = Scripted([1.0, 2.0, 10.0, 2.1, 0.5])
    complex_minimise(f, *BOX, ComplexSettings(max_evaluations=5), initial=[A, B, C])
    assert f.info[4]["step"] == "retraction"
    # with gamma = 1 (k = 3): K_f = 1 - 0.65^(1/3) = 0.1337; the aged B is 2 + 9*0.1337 = 3.2 > 2.1: accepted,
    # and the next request is the reflection of the new worst point
    f = Scripted([1.0, 2.0, 10.0, 2.1, 0.5])
    complex_minimise(f, *BOX, ComplexSettings(max_evaluations=5, gamma=1.0), initial=[A, B, C])
    assert f.info[4] == {"step": "reflection", "iteration": 2, "n_rep": 0}


def test_randomisation_moves_the_reflection_within_its_stated_amplitude():
    # spread s = max((3-1)/20, (4-1)/20) = 0.15; rfak 0.5: |shift| <= 0.5*20*0.15*0.5 = 0.75 per coordinate
    shifts = []
    for seed in range(20):
        f = Scripted([1.0, 2.0, 10.0, 0.0])
        complex_minimise(f, *BOX, ComplexSettings(max_evaluations=4, rfak=0.5), seed=seed, initial=[A, B, C])
        shifts.append(f.points[3] - np.array([2.0, -2.9]))
    shifts = np.array(shifts)
    assert np.all(np.abs(shifts) <= 0.75 + 1e-12)
    assert np.abs(shifts).max() > 0.3  # it does move (20 draws)


def bowl(points, info):
    return [float(np.sum((p - np.array([1.0, -2.0, 0.5])) ** 2)) for p in points]


def rosenbrock(points, info):
    return [float((1 - p[0]) ** 2 + 100 * (p[1] - p[0] ** 2) ** 2) for p in points]


@pytest.mark.parametrize("seed", range(10))
def test_converges_on_a_quadratic_bowl(seed):
    r = complex_minimise(bowl, [-5] * 3, [5] * 3, ComplexSettings(max_evaluations=3000, tol_x=1e-7, tol_f=0), seed)
    assert r.reason == "parameters converged"
    np.testing.assert_allclose(r.x, [1.0, -2.0, 0.5], atol=1e-4)


@pytest.mark.parametrize("seed", range(10))
def test_converges_on_rosenbrock(seed):
    r = complex_minimise(rosenbrock, [-2, -2], [2, 2], ComplexSettings(max_evaluations=3000, tol_x=1e-7, tol_f=0), seed)
    assert r.reason == "parameters converged"
    np.testing.assert_allclose(r.x, [1.0, 1.0], atol=1e-4)


@pytest.mark.parametrize("seed", range(5))
def test_complex_rf_converges_on_rosenbrock(seed):
    s = ComplexSettings(max_evaluations=3000, tol_x=1e-7, tol_f=0, rfak=0.3, gamma=0.3)
    r = complex_minimise(rosenbrock, [-2, -2], [2, 2], s, seed)
    np.testing.assert_allclose(r.x, [1.0, 1.0], atol=1e-3)


def test_budget_is_a_hard_stop_on_the_path():
    """The budget counts the path's evaluations, so it stops every batching at the same point of the path;
    the discarded candidates come on top."""
    counted, used, results = [], [], []

    def f(points, info):
        counted.extend(points)
        return rosenbrock(points, info)

    for c in (1, 3):
        counted.clear(), used.clear()
        s = ComplexSettings(max_evaluations=57, tol_x=0, tol_f=0, candidates=c)
        r = complex_minimise(f, [-2, -2], [2, 2], s, 1, on_path=used.append)
        assert r.evaluations == sum(used) == 57 and r.reason == "budget"
        assert len(counted) == 57 + r.extra["discarded"]
        results.append(r)
    assert results[1].extra["discarded"] > 0
    np.testing.assert_array_equal(results[0].extra["complex"], results[1].extra["complex"])
    assert results[0].iterations == results[1].iterations and results[0].f == results[1].f


def test_stops_on_cost_spread():
    def raised_bowl(points, info):  # minimum 10: the relative spread (f_max - f_min)/|f_min| is meaningful
        return [c + 10.0 for c in bowl(points, info)]

    r = complex_minimise(raised_bowl, [-5] * 3, [5] * 3, ComplexSettings(max_evaluations=5000, tol_x=0, tol_f=1e-3), 2)
    assert r.reason == "cost converged"
    costs = r.extra["costs"]
    assert (costs.max() - costs.min()) / costs.min() <= 1e-3
    assert (costs.max() - costs.min()) / costs.min() > 1e-5  # it stopped there, not much later
    assert r.evaluations < 400


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.integers(1, 4), rfak=st.sampled_from([0.0, 0.5, 2.0]),
       gamma=st.sampled_from([0.0, 0.5]), lows=st.lists(st.floats(-1e3, 1e3), min_size=4, max_size=4),
       widths=st.lists(st.floats(1e-3, 1e3), min_size=4, max_size=4))
def test_bounds_are_never_violated(seed, n, rfak, gamma, lows, widths):
    lower = np.array(lows[:n])
    upper = lower + np.array(widths[:n])
    target = upper + 10.0 * (upper - lower)  # the optimum outside the box pulls the complex onto its bounds
    seen = []

    def f(points, info):
        seen.extend(points)
        return [float(np.sum((p - target) ** 2)) for p in points]

    complex_minimise(f, lower, upper, ComplexSettings(max_evaluations=150, rfak=rfak, gamma=gamma), seed)
    seen = np.array(seen)
    assert np.all(seen >= lower) and np.all(seen <= upper)


def test_reproducible_from_the_seed():
    runs = []
    for seed in (5, 5, 6):
        pts = []

        def f(points, info):
            pts.extend(np.array(p) for p in points)
            return rosenbrock(points, info)

        complex_minimise(f, [-2, -2], [2, 2], ComplexSettings(max_evaluations=80, rfak=0.2, gamma=0.2), seed)
        runs.append(np.array(pts))
    np.testing.assert_array_equal(runs[0], runs[1])
    assert not np.array_equal(runs[0][:4], runs[2][:4])


@pytest.mark.parametrize("rfak", [0.0, 0.2])
def test_several_candidates_at_once_follow_the_same_path(rfak):
    """Complex-RFP task prediction: the batch's extra retractions are discarded unless needed; the path
    of the complex (and so the result) is that of the one-at-a-time method, only evaluations differ."""
    results, sequences = [], []
    for c in (1, 2, 4):
        asked = []

        def f(points, info):
            asked.extend(tuple(p) for p in points)
            return rosenbrock(points, info)

        s = ComplexSettings(max_evaluations=100_000, tol_x=1e-6, tol_f=0, rfak=rfak, candidates=c)
        results.append(complex_minimise(f, [-2, -2], [2, 2], s, seed=3))
        sequences.append(asked)
    one = results[0]
    for r, asked in zip(results[1:], sequences[1:]):
        np.testing.assert_array_equal(r.extra["complex"], one.extra["complex"])
        assert r.iterations == one.iterations and r.f == one.f
        assert r.evaluations == one.evaluations and r.extra["discarded"] > 0
        it = iter(asked)  # the one-at-a-time points are a subsequence of the batched ones
        assert all(p in it for p in sequences[0])
    assert results[2].extra["discarded"] > results[1].extra["discarded"] > 0


def test_bad_settings_are_refused():
    with pytest.raises(ValueError, match="n \\+ 1"):
        complex_minimise(bowl, [0] * 3, [1] * 3, ComplexSettings(points=3))
    with pytest.raises(ValueError, match="fewer than"):
        complex_minimise(bowl, [0] * 3, [1] * 3, ComplexSettings(max_evaluations=5))
    with pytest.raises(ValueError, match="upper bound"):
        complex_minimise(bowl, [0, 1, 0], [1, 1, 1])
