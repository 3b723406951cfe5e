"""The LGA's slewing inertia follows the arm's pose and conserves the angular momentum (block
`lga_slewing_load`, vphs_blocks/lga_slewing_load.py; thesis eqs. 2.46-2.53).

Tier 1, the block alone: J_S and its slopes against lga_geometry's J_S (central differences), and the
torque -dJ_S/dt*w/n^2 it applies. Tier 2, a circuit (tests/circuits/netlists/slewing_momentum.yaml): a
free slewing shaft while the jib rises and the telescope goes out; nothing exerts a moment about the
slewing axis, so J_S(t)*w(t) = J_S(0)*w0 (the closed form w = w0*J_S(0)/J_S(t)); the same arm with the
Lagrange term off keeps w0 and is shown to break it.
"""

from __future__ import annotations

import inspect
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit
from vphs_blocks import lga_geometry as lga
from vphs_blocks.lga_slewing_load import LgaSlewingLoad

NETLIST = Path(__file__).parent / "netlists" / "slewing_momentum.yaml"
G = lga.thesis_geometry()
J4 = lga.disc_inertia(lga.THESIS["m4"], lga.THESIS["R4"], lga.THESIS["r4"])
E = lga.THESIS["e"]
POSES = [(0.785, 0.2), (0.3, 0.5), (1.2, 0.0), (-0.1, 1.0), (1.5, 1.3)]


def j_s(theta, d2):
    return lga.slewing_inertia(theta, d2, E, J4, G)


@pytest.mark.parametrize("theta, d2", POSES)
def test_slopes_are_those_of_j_s(theta, d2):
    h = 1e-6
    d_theta, d_d2 = lga.slewing_inertia_slopes(theta, d2, E, G)
    assert d_theta == pytest.approx((j_s(theta + h, d2) - j_s(theta - h, d2)) / (2 * h), rel=1e-7, abs=1e-4)
    assert d_d2 == pytest.approx((j_s(theta, d2 + h) - j_s(theta, d2 - h)) / (2 * h), rel=1e-7, abs=1e-4)


def call(fn, **given):
    """A block function at the block's default parameters, with ``given`` arguments and parameters."""
    values = {p.name: p.default for p in LgaSlewingLoad.params} | given
    return fn(**{name: values[name] for name in inspect.signature(fn).parameters})


@pytest.mark.parametrize("theta, d2", POSES)
def test_the_block_stores_j_s_over_n_squared_and_applies_minus_dj_dt_w(theta, d2):
    n, w, w1, v2, d2_0 = 353.3, 61.7, -0.2, 0.1, 0.05
    args = dict(shaft=w, theta1=theta, w1=w1, x2=d2 - d2_0, v2=v2, n_tot=n, d2_0=d2_0)
    tau, inertia = call(LgaSlewingLoad.derivatives, **args)
    h = 1e-6  # dJ_S/dt along the motion, by a central difference in time
    rate = (j_s(theta + w1 * h, d2 + v2 * h) - j_s(theta - w1 * h, d2 - v2 * h)) / (2 * h)
    assert inertia == pytest.approx(j_s(theta, d2) / n**2, rel=1e-12)
    assert tau == pytest.approx(-rate * w / n**2, rel=1e-6)
    assert call(LgaSlewingLoad.outputs, **args)[0] == pytest.approx(j_s(theta, d2), rel=1e-12)
    assert call(LgaSlewingLoad.derivatives, **args, k_vel=0.0)[0] == 0.0


@lru_cache(maxsize=None)
def run():
    return Circuit.from_file(NETLIST).simulate()


def test_a_free_slewing_arm_keeps_its_angular_momentum_while_it_reaches_out():
    r = run()
    expected_j = np.array([j_s(a, b) for a, b in zip(r["theta1"], r["d2"])])
    assert np.allclose(r["J"], expected_j, rtol=1e-12)
    assert expected_j[-1] > 1.4 * expected_j[0]  # the arm does reach out: J_S grows by half
    w0 = r["w"][0]
    assert np.allclose(r["w"], w0 * expected_j[0] / expected_j, rtol=1e-7)


def test_without_the_lagrange_term_the_momentum_is_not_kept():
    """k_vel = 0 (J_S follows the pose, dJ/dt*w left out): the shaft keeps its speed, and J_S*w grows with
    J_S, the check above failing by far more than its tolerance."""
    r = run()
    assert np.allclose(r["w_b"], r["w_b"][0], rtol=1e-9)
    momentum = r["J"] * r["w_b"]
    assert momentum[-1] / momentum[0] - 1.0 > 0.4
