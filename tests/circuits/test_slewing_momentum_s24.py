"""The LGA's slewing inertia follows the arm's pose, coupled to the jib and the telescope by Lagrange's
equations (block `lga_slewing_load`, vphs_blocks/lga_slewing_load.py; thesis eqs. 2.46-2.53).

Tier 1, the block alone: J_S's slopes against central differences of lga_geometry's J_S; the shaft's torque
-dJ_shaft/dt*w and the pulls 1/2*dJ_S/dq*W^2 on the rods. Tier 2, the arm's mechanics alone
(tests/circuits/netlists/slewing_momentum.yaml, whose description gives the set-up): the angular momentum
(J_S/n^2 + J_rotor)*w is conserved with everything free; the kinetic energy with the telescope held, and
with the jib held; with the coupling off (k_vel = 0), neither is.
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
N, J_ROTOR = 353.3, 0.002  # as in parts/slewing_arm.yaml


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
def test_the_block_stores_j_s_and_applies_the_lagrange_terms(theta, d2):
    w, k1, v1, v2, d2_0 = 61.7, -0.45, 0.05, 0.1, 0.05
    args = dict(shaft=w, jib_rod=v1, tel_rod=v2, theta1=theta, k1=k1, x2=d2 - d2_0, n_tot=N, d2_0=d2_0)
    tau, f_jib, f_tel, inertia = call(LgaSlewingLoad.derivatives, **args)
    h = 1e-6  # along the motion: theta1 turns at k1*v1, d2 grows at v2
    rate = (j_s(theta + k1 * v1 * h, d2 + v2 * h) - j_s(theta - k1 * v1 * h, d2 - v2 * h)) / (2 * h)
    big_w2 = (w / N) ** 2
    assert inertia == pytest.approx(j_s(theta, d2) / N**2, rel=1e-12)
    assert tau == pytest.approx(-rate * w / N**2, rel=1e-6)
    assert f_tel == pytest.approx(0.5 * (j_s(theta, d2 + h) - j_s(theta, d2 - h)) / (2 * h) * big_w2, rel=1e-6)
    assert f_jib == pytest.approx(0.5 * (j_s(theta + h, d2) - j_s(theta - h, d2)) / (2 * h) * big_w2 * k1, rel=1e-6)
    assert call(LgaSlewingLoad.outputs, **args)[0] == pytest.approx(j_s(theta, d2), rel=1e-12)
    assert call(LgaSlewingLoad.derivatives, **args, k_vel=0.0)[:3] == (0.0, 0.0, 0.0)


@lru_cache(maxsize=None)
def run():
    return Circuit.from_file(NETLIST).simulate()


def momentum(r, which):
    return (r[f"J_{which}"] / N**2 + J_ROTOR) * r[f"w_{which}"]


def shaft_energy(r, which):
    return 0.5 * (r[f"J_{which}"] / N**2 + J_ROTOR) * r[f"w_{which}"] ** 2


def test_the_pose_moves_and_j_s_follows_it():
    r = run()
    expected = np.array([j_s(a, b) for a, b in zip(r["theta1"], r["d2"])])
    assert np.allclose(r["J_free"], expected, rtol=1e-12)
    assert expected.max() > 1.3 * expected[0]  # the arm does reach out


def test_a_free_arm_keeps_its_angular_momentum():
    r = run()
    L = momentum(r, "free")
    assert np.abs(L / L[0] - 1.0).max() < 1e-7
    assert r["w_free"][-1] < 0.8 * r["w_free"][0]  # reaching out, it slowed down


def test_with_the_telescope_held_the_energy_is_kept():
    r = run()
    energy = 0.5 * r["m_jib"] * r["v_jib"] ** 2 + shaft_energy(r, "jib")
    assert np.abs(energy / energy[0] - 1.0).max() < 1e-7
    assert np.ptp(r["v_jib"]) > 0.05 * abs(r["v_jib"][0])  # energy did move between the axes


def test_with_the_jib_held_the_energy_is_kept():
    r = run()
    m_tel = lga.THESIS["m2"] + lga.THESIS["m3"]
    energy = 0.5 * m_tel * r["v_tel"] ** 2 + shaft_energy(r, "tel")
    assert np.abs(energy / energy[0] - 1.0).max() < 1e-7
    assert r["v_tel"][-1] > 1.05 * r["v_tel"][0]  # the slewing's pull sped the telescope up


def test_without_the_coupling_neither_is_kept():
    """k_vel = 0 (J_S follows the pose, the thesis's J_sm*dw/dt = tau): the shaft keeps its speed, so the
    momentum grows with J_S, far beyond the tolerance the checks above hold."""
    r = run()
    assert np.allclose(r["w_thesis"], r["w_thesis"][0], rtol=1e-9)
    L = momentum(r, "thesis")
    assert L[-1] / L[0] - 1.0 > 0.2
