"""Gaps found by mutation testing blocks/optimise/complex.py (session 27).

Each test checks a rule the module docstring or docs/netlist-reference.md states (the settings refused,
the defaults max_evaluations 500 and max_retractions 30, "a tie counts as worst", the stops "s <= tol_x"
and "spread <= tol_f") on a complex small enough to follow by hand.
"""

import numpy as np
import pytest

from test_complex import BOX, A, B, C, Scripted  # the hand-followed complex and its scripted costs

from blocks.optimise.complex import ComplexSettings, complex_minimise


class EverWorse:
    """Every new point costs more than all before it: it is always the worst, so the k - 1 others never move
    and neither stop (spread in parameters or in cost) can be reached; only the budget ends the run."""

    def __init__(self):
        self.calls, self.info = 0, []

    def __call__(self, points, info):
        self.info += list(info)
        out = [float(self.calls + i) for i in range(len(points))]
        self.calls += len(points)
        return out




def bowl(points, info):
    """A quadratic bowl; an empty batch is a bug of the caller (it would loop for ever), so it raises."""
    if not points:
        raise RuntimeError("evaluate() asked for no points")
    return [float(np.sum(np.asarray(p) ** 2)) for p in points]


@pytest.mark.parametrize("bad", [dict(alpha=0.0), dict(alpha=-1.3), dict(n0=0.0), dict(rfak=-0.1),
                                 dict(gamma=-0.1), dict(candidates=0), dict(max_retractions=-1)])
def test_each_bad_setting_is_refused_on_its_own(bad):
    """check_settings: 'alpha and n0 must be positive; rfak, gamma and max_retractions >= 0; candidates >= 1'.
    Each setting out of its range is refused by itself, the others being the defaults."""
    with pytest.raises(ValueError, match="alpha and n0 must be positive"):
        complex_minimise(bowl, [-1.0, -1.0], [1.0, 1.0], ComplexSettings(**bad))


@pytest.mark.parametrize("edge", [dict(max_retractions=0), dict(rfak=0.0), dict(gamma=0.0), dict(candidates=1),
                                  dict(alpha=0.5), dict(alpha=1.0), dict(n0=0.5), dict(n0=1.0)])
def test_settings_on_the_edge_of_their_range_are_accepted(edge):
    """'rfak, gamma and max_retractions >= 0; candidates >= 1': the edge values themselves run; 'alpha and n0
    must be positive': any positive value runs, 1 and below included."""
    r = complex_minimise(bowl, [-1.0, -1.0], [1.0, 1.0], ComplexSettings(max_evaluations=20, **edge), seed=1)
    assert r.evaluations <= 20


def test_no_free_parameter_is_refused():
    """n = 0 (no bounds at all): 'the Complex method needs at least one free parameter'."""
    with pytest.raises(ValueError, match="at least one free parameter"):
        complex_minimise(bowl, [], [])


@pytest.mark.parametrize("n", [1, 2, 3])
def test_a_complex_of_n_plus_one_points_is_the_smallest_accepted(n):
    """The complex needs at least n + 1 points (docs: 'at least n + 1'): k = n + 1 runs (for n = 1 that is
    two points), k = n is refused."""
    lower, upper = [-1.0] * n, [1.0] * n
    r = complex_minimise(bowl, lower, upper, ComplexSettings(points=n + 1, max_evaluations=30), seed=2)
    assert r.extra["points"] == n + 1
    with pytest.raises(ValueError, match="n \\+ 1"):
        complex_minimise(bowl, lower, upper, ComplexSettings(points=n, max_evaluations=30), seed=2)


def test_default_budget_is_500_evaluations():
    """docs/netlist-reference.md: complex max_evaluations 500. A cost that never lets the complex converge
    is evaluated exactly 500 times with the default settings."""
    f = EverWorse()
    r = complex_minimise(f, [0.0, 0.0], [1.0, 1.0], seed=0)
    assert r.reason == "budget"
    assert r.evaluations == 500 and f.calls == 500


def test_default_max_retractions_is_30_moves_per_iteration():
    """docs: max_retractions 30 (module docstring: at most 30 moves per iteration). A design that stays the
    worst is reflected (n_rep 0) and retracted with n_rep 1..30; the 32nd request of the iteration is the
    next iteration's reflection."""
    f = EverWorse()
    complex_minimise(f, *BOX, ComplexSettings(max_evaluations=3 + 31 + 1), initial=[A, B, C])
    first = f.info[3:34]
    assert [i["n_rep"] for i in first] == list(range(31))
    assert all(i["iteration"] == 1 for i in first)
    assert f.info[34] == {"step": "reflection", "iteration": 2, "n_rep": 0}


def test_a_tie_with_the_worst_of_the_others_counts_as_worst():
    """Module docstring step 3: 'f(y_new) >= max_{i != j} f_i (a tie counts as worst)'. Costs A 1, B 2,
    C 10: a reflection costing exactly 2 (B's cost) is retracted; one costing 1.999 is accepted."""
    f = Scripted([1.0, 2.0, 10.0, 2.0, 0.5])
    complex_minimise(f, *BOX, ComplexSettings(max_evaluations=5), initial=[A, B, C])
    assert f.info[4] == {"step": "retraction", "iteration": 1, "n_rep": 1}
    f = Scripted([1.0, 2.0, 10.0, 1.999, 0.5])
    complex_minimise(f, *BOX, ComplexSettings(max_evaluations=5), initial=[A, B, C])
    assert f.info[4] == {"step": "reflection", "iteration": 2, "n_rep": 0}


def test_a_complex_of_one_point_repeated_has_converged_in_parameters_at_tol_x_zero():
    """Stop rule 7: 's <= tol_x'. Three copies of one point have spread s = 0, which is <= tol_x = 0: the
    run stops before the first iteration, after the initial evaluations only."""
    f = Scripted([1.0, 2.0, 3.0])
    r = complex_minimise(f, *BOX, ComplexSettings(tol_x=0.0, tol_f=0.0), initial=[A, A, A])
    assert r.reason == "parameters converged" and r.evaluations == 3 and r.iterations == 0


def test_equal_costs_have_converged_in_cost_at_tol_f_zero():
    """Stop rule 7: '(f_max - f_min) / |f_min| <= tol_f'. Three distinct points of equal cost 5 have spread
    0, which is <= tol_f = 0: the run stops after the initial evaluations only."""
    f = Scripted([5.0, 5.0, 5.0])
    r = complex_minimise(f, *BOX, ComplexSettings(tol_x=0.0, tol_f=0.0), initial=[A, B, C])
    assert r.reason == "cost converged" and r.evaluations == 3 and r.iterations == 0


@pytest.mark.parametrize("n, k", [(1, 3), (2, 4), (3, 6)])
def test_default_size_of_the_complex_is_max_2n_3(n, k):
    """Module docstring step 1 and docs: k = max(2n, 3) unless set: 3 points for n = 1, 4 for n = 2, 6 for
    n = 3; the initial population is one batch of k points."""
    f = Scripted([float(i) for i in range(k)])
    r = complex_minimise(f, [-1.0] * n, [1.0] * n, ComplexSettings(max_evaluations=k), seed=3)
    assert r.extra["points"] == k and len(f.points) == k


def test_cost_spread_is_absolute_when_the_best_cost_is_zero_and_relative_to_its_size_otherwise():
    """Stop rule 7: (f_max - f_min) / |f_min| <= tol_f, or f_max - f_min <= tol_f if f_min = 0. By hand:
    costs 0, 1e-6, 2e-6: absolute spread 2e-6 <= 1e-5, converged. Costs -1, -0.5, -0.2: relative spread
    0.8 / |-1| = 0.8 > 1e-5, not converged (an iteration is made). Costs 1e6, 1e6 + 1, 1e6 + 5: relative
    spread 5e-6 <= 1e-5, converged although the absolute spread is 5."""
    settings = ComplexSettings(tol_x=0.0, tol_f=1e-5, max_evaluations=4)
    r = complex_minimise(Scripted([0.0, 1e-6, 2e-6]), *BOX, settings, initial=[A, B, C])
    assert r.reason == "cost converged" and r.iterations == 0
    r = complex_minimise(Scripted([-1.0, -0.5, -0.2, -2.0]), *BOX, settings, initial=[A, B, C])
    assert r.iterations == 1 and r.reason == "budget"
    r = complex_minimise(Scripted([1e6, 1e6 + 1.0, 1e6 + 5.0]), *BOX, settings, initial=[A, B, C])
    assert r.reason == "cost converged" and r.iterations == 0


def test_forgetting_raises_the_costs_by_their_spread_not_their_sum():
    """Step 6: f_i <- f_i + (max f - min f) * K_f, K_f = 1 - (alpha/2)^(gamma/k). By hand with costs A 100,
    B 101, C 110, gamma 1, k 3: K_f = 1 - 0.65^(1/3) = 0.133761, B ages to 101 + 10 * 0.133761 = 102.338. C is
    the worst and is reflected; a reflection costing 105 is still >= B's aged cost, so it is retracted.
    (Aged by the sum of the costs instead, B would be 129.1 and 105 accepted.)"""
    f = Scripted([100.0, 101.0, 110.0, 105.0, 50.0])
    complex_minimise(f, *BOX, ComplexSettings(max_evaluations=5, gamma=1.0, tol_x=0.0, tol_f=0.0),
                     initial=[A, B, C])
    assert f.info[4] == {"step": "retraction", "iteration": 1, "n_rep": 1}
    # a reflection just under B's aged cost by hand (102.33) is accepted: the next request is a new reflection
    f = Scripted([100.0, 101.0, 110.0, 102.33, 50.0])
    complex_minimise(f, *BOX, ComplexSettings(max_evaluations=5, gamma=1.0, tol_x=0.0, tol_f=0.0),
                     initial=[A, B, C])
    assert f.info[4] == {"step": "reflection", "iteration": 2, "n_rep": 0}


def test_a_batch_never_goes_past_max_retractions_or_the_budget():
    """Parallel evaluation: 'the first c of that sequence are evaluated at once' -- but the sequence of an
    iteration is the reflection and at most max_retractions retractions, and 'a batch never asks for more
    than the budget has left'. With c = 2 or 4 and max_retractions 2, a design that stays the worst gets n_rep
    0, 1, 2 and then the next iteration's reflection, as with c = 1; with a budget of 5 after 3 initial
    points, only 2 more points are asked for. (c = 2 takes the iteration in two batches, 2 + 1.)"""
    for c in (1, 2, 4):
        f = EverWorse()
        complex_minimise(f, *BOX, ComplexSettings(max_evaluations=7, max_retractions=2, candidates=c),
                         initial=[A, B, C])
        assert [(i["iteration"], i["n_rep"]) for i in f.info[3:7]] == [(1, 0), (1, 1), (1, 2), (2, 0)]
    f = EverWorse()
    r = complex_minimise(f, *BOX, ComplexSettings(max_evaluations=5, candidates=4), initial=[A, B, C])
    assert f.calls == 5 and r.evaluations == 5 and r.extra["discarded"] == 0


def test_the_initial_population_is_asked_for_before_the_first_iteration_and_is_no_retraction():
    """The initial points precede iteration 1 (iterations are numbered from 1, as result.iterations counts
    them) and none has yet been the worst (n_rep, the times in a row a design has been the worst, is 0):
    each gets {"step": "initial", "iteration": 0, "n_rep": 0}, the convention of every other method's
    points outside an iteration (blocks.optimise.runner, scipy_methods)."""
    f = EverWorse()
    complex_minimise(f, [-1.0, -1.0], [1.0, 1.0], ComplexSettings(max_evaluations=4), seed=4)
    assert f.info == [{"step": "initial", "iteration": 0, "n_rep": 0}] * 4
