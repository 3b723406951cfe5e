"""The knots of a latent trace (blocks/calibrate/latent_trace.py), chosen from a noisy recording alone."""

from __future__ import annotations

import numpy as np
import pytest

from blocks.calibrate.latent_trace import choose_knots, knot_values, spline_basis, split_gains

T = np.arange(0.0, 3.4 + 1e-9, 0.002)  # the drive line's samples
CORNERS = [(0.0, 0.0), (0.4, 0.0), (0.402, 0.1), (0.8, 0.1), (1.2, 0.2), (1.6, 0.2), (1.602, 0.0), (2.0, 0.0),
           (2.4, -0.15), (2.6, -0.15), (3.0, 0.0), (3.4, 0.0)]  # steps, ramps and stops, corners on samples


def _command(sigma: float, seed: int) -> np.ndarray:
    times, values = zip(*CORNERS)
    return np.interp(T, times, values) + sigma * np.random.default_rng(seed).normal(size=T.size)


def test_the_gain_of_a_split_is_the_projection_on_its_hat_function():
    rng = np.random.default_rng(3)
    tt = np.concatenate([[0.0], np.sort(rng.uniform(0.0, 1.0, 28)), [1.0]])
    rr = rng.normal(size=tt.size)
    gains = split_gains(tt, rr)
    for s in range(1, tt.size - 1):
        hat = np.interp(tt, [0.0, tt[s], 1.0], [0.0, 1.0, 0.0])
        assert gains[s - 1] == pytest.approx((rr @ hat) ** 2 / (hat @ hat), rel=1e-9)


@pytest.mark.parametrize("seed", range(5))
def test_a_command_of_steps_ramps_and_stops_gets_a_knot_at_each_corner(seed):
    knots = T[choose_knots(T, _command(0.005, seed), 0.005)]
    corners = np.array([t for t, _ in CORNERS])
    nearest = np.min(np.abs(knots[:, None] - corners[None, :]), axis=0)
    assert np.all(nearest <= 0.0201), f"corners without a knot within 10 samples: {corners[nearest > 0.0201]}"
    assert len(knots) <= len(CORNERS) + 3  # at most a few more than the corners


@pytest.mark.parametrize("seed", range(5))
def test_noise_about_a_constant_gets_no_knot_but_the_ends(seed):
    flat = 0.1 + 0.005 * np.random.default_rng(seed).normal(size=T.size)
    assert list(choose_knots(T, flat, 0.005)) == [0, T.size - 1]


def test_the_spline_through_the_knots_follows_the_recording_to_its_noise():
    u = _command(0.005, 7)
    knots = choose_knots(T, u, 0.005)
    r = (u - spline_basis(T, T[knots]) @ knot_values(T, u, knots)) / 0.005
    nu = T.size - len(knots)
    assert abs(r @ r / nu - 1.0) < 4.0 * np.sqrt(2.0 / nu)


def test_a_recording_that_needs_too_many_knots_is_refused():
    wavy = np.sin(2 * np.pi * 3.0 * T) + 0.001 * np.random.default_rng(0).normal(size=T.size)
    with pytest.raises(ValueError, match="more than 8 knots"):
        choose_knots(T, wavy, 0.001, max_knots=8)
