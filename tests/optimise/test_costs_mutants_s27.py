"""Gaps found by mutation testing blocks/optimise/costs.py (session 27).

Each test checks a cost term against its definition in the module docstring, computed by hand: the units
of a term's value, the window t_from <= t <= t_to (both ends included), J = int (h/scale)^2 dt for hp_ise,
the high-pass started in steady state at the first sample, its default damping, and a ragged grid being
interpolated onto a uniform one.
"""

import numpy as np
import pytest

from blocks.optimise.costs import Term, evaluate_term, highpass


def test_value_unit_is_the_unit_for_max_abs_and_its_square_times_seconds_for_integrals():
    """max_abs is in the error's unit; ise and hp_ise integrate its square over time: (unit)^2*s. Without a
    unit the error is a plain number, '1'."""
    assert Term("m", "max_abs", "x", unit="mm").value_unit == "mm"
    assert Term("p", "ise", "x", unit="mm").value_unit == "(mm)^2*s"
    assert Term("v", "hp_ise", "p", unit="bar", wn=10.0).value_unit == "(bar)^2*s"
    assert Term("m", "max_abs", "x").value_unit == "1"
    assert Term("p", "ise", "x").value_unit == "(1)^2*s"


def test_the_window_includes_both_of_its_ends():
    """'over the window t_from <= t <= t_to'. Samples at t = 0, 1, 2, 3 s of a constant error 2: over
    [1, 2] the integral of 2^2 is 4 * 1 s = 4 (both end samples are needed for it), the max is 2; a window
    holding the one sample t = 1 integrates over no time: 0."""
    t = np.array([0.0, 1.0, 2.0, 3.0])
    signals = {"x": np.full(4, 2.0)}
    assert evaluate_term(Term("p", "ise", "x", t_from=1.0, t_to=2.0), t, signals) == pytest.approx(4.0, rel=1e-12)
    assert evaluate_term(Term("m", "max_abs", "x", t_from=3.0, t_to=3.0), t, signals) == 2.0
    assert evaluate_term(Term("p", "ise", "x", t_from=1.0, t_to=1.0), t, signals) == 0.0


def test_hp_ise_divides_the_high_passed_signal_by_the_scale_before_squaring():
    """J = int (h/scale)^2 dt: the same pressure expressed in bar (scale 1e5 Pa) gives 1e10 times less than
    in Pa."""
    t = np.arange(0.0, 1.0 + 1e-12, 1e-3)
    signals = {"p": 20e5 + 1e5 * np.sin(150.0 * t)}
    in_pa = evaluate_term(Term("v", "hp_ise", "p", wn=100.0), t, signals)
    in_bar = evaluate_term(Term("v", "hp_ise", "p", wn=100.0, scale=1e5, unit="bar"), t, signals)
    assert in_pa > 1e8
    assert in_bar == pytest.approx(in_pa / 1e10, rel=1e-12)


def test_the_highpass_starts_in_steady_state_at_the_first_sample():
    """'started in steady state at the first sample': the filter's DC gain H(0) is 0, so its first output
    is 0 whatever the first sample is, even when the signal moves at once (here a ramp from 20 bar)."""
    t = np.arange(0.0, 0.1 + 1e-12, 1e-3)
    u = 20e5 + 1e8 * t  # 20 bar rising at 1000 bar/s
    y = highpass(t, u, 100.0, 0.7071)
    assert abs(y[0]) < 1e-9 * 20e5
    assert np.max(np.abs(y)) > 1.0  # and it is not all zeros: the ramp does pass a little


def test_the_default_damping_is_0_7071():
    """docs: hp_ise zeta default 0.7071. At w = wn, |H(j wn)| = 1/(2 zeta), so |H|^2 = 1/2 at zeta = 1/sqrt(2):
    a sine of amplitude 1e5 Pa over whole periods gives int h^2 dt = |H|^2 * (1e5)^2 / 2 * duration. Checked
    to 1 % (the offline filter is low by about (wn dt)^2/6 in int h^2, module docstring)."""
    wn = 100.0
    period = 2 * np.pi / wn
    t = np.linspace(0.0, 40 * period, 40 * 2000 + 1)
    u = 1e5 * np.sin(wn * t)
    start = 20 * period  # transients long gone
    j = evaluate_term(Term("v", "hp_ise", "p", wn=wn, t_from=start), t, {"p": u})
    assert j == pytest.approx(0.5 * 1e10 / 2 * (t[-1] - start), rel=1e-2)


def test_a_grid_whose_step_changes_is_interpolated_onto_a_uniform_one():
    """'it needs the logged signal at a uniform step (a ragged grid is interpolated onto one)'. A run logged
    at 1 ms from t = 1 s and at 0.5 ms after t = 1.5 s: its high-pass at the samples matches that of the same
    signal logged at 0.5 ms throughout (itself checked against H(jw) in test_costs.py), to 1 % of its peak."""
    def u_of(t):
        return np.sin(60.0 * t) + 0.3 * np.sin(250.0 * t)

    coarse = np.arange(1.0, 1.5, 1e-3)
    fine = np.arange(1.5, 2.0 + 1e-12, 5e-4)
    ragged = np.concatenate([coarse, fine])
    uniform = np.arange(1.0, 2.0 + 1e-12, 5e-4)
    y_uniform = highpass(uniform, u_of(uniform), 100.0, 0.7)
    y_ragged = highpass(ragged, u_of(ragged), 100.0, 0.7)
    expected = np.interp(ragged, uniform, y_uniform)
    np.testing.assert_allclose(y_ragged, expected, atol=1e-2 * np.max(np.abs(y_uniform)))
