"""scipy's Nelder-Mead and differential evolution behind the Complex method's interface."""

import numpy as np
import pytest

from blocks.optimise.scipy_methods import DESettings, NelderMeadSettings, differential_evolution, nelder_mead


def bowl(points, info):
    return [float(np.sum((p - np.array([1.0, -2.0, 0.5])) ** 2)) for p in points]


def rosenbrock(points, info):
    return [float((1 - p[0]) ** 2 + 100 * (p[1] - p[0] ** 2) ** 2) for p in points]


class Recorder:
    def __init__(self, f):
        self.f, self.points, self.batches = f, [], []

    def __call__(self, points, info):
        self.points += [np.array(p) for p in points]
        self.batches.append(len(points))
        return self.f(points, info)


@pytest.mark.parametrize("seed", range(3))
def test_nelder_mead_finds_the_bowl_and_rosenbrock(seed):
    r = nelder_mead(bowl, [-5] * 3, [5] * 3, NelderMeadSettings(max_evaluations=2000, xatol=1e-8, fatol=1e-14), seed)
    np.testing.assert_allclose(r.x, [1.0, -2.0, 0.5], atol=1e-5)
    r = nelder_mead(rosenbrock, [-2, -2], [2, 2], NelderMeadSettings(max_evaluations=2000, xatol=1e-8, fatol=1e-14), seed)
    np.testing.assert_allclose(r.x, [1.0, 1.0], atol=1e-5)
    assert r.reason == "converged"


@pytest.mark.parametrize("seed", range(2))
def test_differential_evolution_finds_rosenbrock(seed):
    rec = Recorder(rosenbrock)
    r = differential_evolution(rec, [-2, -2], [2, 2], DESettings(max_evaluations=8000, tol=1e-10), seed)
    np.testing.assert_allclose(r.x, [1.0, 1.0], atol=1e-4)
    assert set(rec.batches[1:]) == {30}  # whole generations (popsize 15 * n 2) go out as one batch


@pytest.mark.parametrize("method,budget", [
    (lambda f: nelder_mead(f, [0, 0], [1, 1], NelderMeadSettings(max_evaluations=40), 1), 40),
    (lambda f: differential_evolution(f, [0, 0], [1, 1], DESettings(max_evaluations=100, popsize=5), 1), 100)])
def test_budgets_and_bounds_are_kept(method, budget):
    far = np.array([9.0, -9.0])

    def pull(points, info):  # optimum outside the box: the search presses against its corner (1, 0)
        return [float(np.sum((p - far) ** 2)) for p in points]

    rec = Recorder(pull)
    r = method(rec)
    pts = np.array(rec.points)
    assert r.evaluations == len(pts) <= budget
    assert np.all(pts >= 0) and np.all(pts <= 1)
    np.testing.assert_allclose(r.x, [1.0, 0.0], atol=0.05)


def test_nelder_mead_budget_is_exact_and_reported():
    rec = Recorder(rosenbrock)
    r = nelder_mead(rec, [-2, -2], [2, 2], NelderMeadSettings(max_evaluations=25, xatol=0, fatol=0), 0)
    assert r.evaluations == len(rec.points) == 25 and r.reason == "budget"


def test_reproducible_from_the_seed():
    for method in (lambda f, s: nelder_mead(f, [-2, -2], [2, 2], NelderMeadSettings(max_evaluations=60), s),
                   lambda f, s: differential_evolution(f, [-2, -2], [2, 2], DESettings(max_evaluations=120, popsize=10), s)):
        a, b, c = Recorder(rosenbrock), Recorder(rosenbrock), Recorder(rosenbrock)
        method(a, 4), method(b, 4), method(c, 5)
        np.testing.assert_array_equal(np.array(a.points), np.array(b.points))
        assert not np.array_equal(np.array(a.points[:3]), np.array(c.points[:3]))
