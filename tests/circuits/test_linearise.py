"""The linear model of a circuit (blocks/linearise.py, `vphs linearise`) against closed forms.

tests/circuits/netlists/linear_modes.yaml holds three independent circuits:
- RC: a flow q into a volume V drained by a laminar orifice G: one pole -beta*G/V, p/q = 1/(G + s*V/beta);
- spring: a mass m on a cylinder whose chambers are shut, damper b: m*s^2 + b*s + k_h = 0 with the oil
  spring k_h = beta*(A_A^2/V_A + A_B^2/V_B), V_A and V_B the chambers' volumes at the piston's position;
- acc: an integrator of the command q: no steady-state gain.
Every expected value here is computed from the netlist's numbers by the formulas above, not by vphs.
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit
from blocks.linearise import (GAIN_DEFECTIVE, GAIN_INTEGRATES, GAIN_UNCOUPLED, at_rest, coupled, frequency_response, integrating,
                              linearise, modes, operating_point, steady_gain)

NETLISTS = Path(__file__).parent / "netlists"
BETA, V, G = 8e8, 2e-3, 2e-11
M, B_DAMP, GRAVITY = 800.0, 2e3, 9.81
A_A, A_B, X0 = 12.57e-4, 6.28e-4, 0.25
V_A, V_B = 0.2e-3 + A_A * X0, 0.3e-3 + A_B * (0.5 - X0)
K_H = BETA * (A_A**2 / V_A + A_B**2 / V_B)


@lru_cache(maxsize=None)
def circuit(name: str) -> Circuit:
    return Circuit.from_file(NETLISTS / f"{name}.yaml")


@lru_cache(maxsize=None)
def model_at_start():
    c = circuit("linear_modes")
    point = operating_point(c, {}, c.settings, at=0.0)
    return linearise(c, point, ["qcmd.value", "m"], ["p", "pA", "v", "x", "qi"])


def state_index(model, name):
    return model.state_names.index(name)


def test_rc_pole_and_frequency_response():
    model = model_at_start()
    pole = [m for m in modes(model) if "P.p" == m.participation[0][0]]
    assert len(pole) == 1 and pole[0].participation[0][1] == pytest.approx(1.0, abs=1e-9)
    assert pole[0].eigenvalue == pytest.approx(-BETA * G / V, rel=1e-7)
    freqs = np.array([0.01, 0.3, 1.27, 10.0, 400.0])
    response = frequency_response(model, freqs)[:, 0, 0]
    expected = 1.0 / (G + 2j * math.pi * freqs * V / BETA)
    np.testing.assert_allclose(response, expected, rtol=1e-7)


def test_oil_spring_mass_pair_and_its_participation():
    model = model_at_start()
    pairs = [m for m in modes(model) if m.oscillating]
    assert len(pairs) == 1
    expected = np.roots([M, B_DAMP, K_H])
    expected = expected[expected.imag > 0][0]
    assert pairs[0].eigenvalue == pytest.approx(expected, rel=1e-7)
    assert pairs[0].natural_frequency == pytest.approx(math.sqrt(K_H / M) / (2 * math.pi), rel=1e-7)
    assert pairs[0].damping == pytest.approx(B_DAMP / (2 * math.sqrt(K_H * M)), rel=1e-6)
    shares = dict(pairs[0].participation)
    # a lightly damped oscillator keeps half its participation in its speed and half in its springs, each
    # spring (chamber) in proportion to its stiffness beta*A^2/V
    assert shares["rod.v"] == pytest.approx(0.5, abs=0.01)
    assert shares["A.p"] / shares["B.p"] == pytest.approx((A_A**2 / V_A) / (A_B**2 / V_B), rel=0.02)
    assert shares["cyl.x"] < 1e-6


def test_the_integrators_are_the_position_and_the_shut_in_oil():
    found = modes(model_at_start())
    at_zero = [m for m in found if m.eigenvalue == 0]
    assert len(at_zero) == 3  # the piston position, the shut-in chambers' combination, the integrator acc
    assert {m.participation[0][0] for m in at_zero} == {"cyl.x", "B.p", "acc.x"}
    assert all(math.isinf(m.time_constant) for m in at_zero)


def test_input_columns_are_the_parameter_sensitivities():
    model = model_at_start()
    q, m = 0, 1
    # dp/dt = beta/V*(q - G*p): d/dq = beta/V
    assert model.B[state_index(model, "P.p"), q] == pytest.approx(BETA / V, rel=1e-7)
    # dv/dt = (p_A*A_A - p_B*A_B - b*v - m*g)/m at rest and in balance: d/dm = -g/m
    assert model.B[state_index(model, "rod.v"), m] == pytest.approx(-GRAVITY / M, rel=1e-6)
    assert model.B[state_index(model, "P.p"), m] == 0.0


def test_steady_gains():
    model = model_at_start()
    gain, why = steady_gain(model)
    q, m = 0, 1
    p, pA, v, x, qi = range(5)
    assert gain[p, q] == pytest.approx(1.0 / G, rel=1e-7)
    # more load: the piston sinks by g*dm/k_h, compressing chamber A
    assert gain[x, m] == pytest.approx(-GRAVITY / K_H, rel=1e-6)
    assert gain[pA, m] == pytest.approx(BETA * A_A / V_A * GRAVITY / K_H, rel=1e-6)
    assert gain[v, m] == 0.0 and why[v, m] == ""
    assert math.isnan(gain[qi, q]) and why[qi, q] == GAIN_INTEGRATES  # it integrates the command
    assert gain[p, m] == 0.0 and why[p, m] == GAIN_UNCOUPLED
    reached = coupled(model)
    assert not reached[p, m] and not reached[pA, q] and not reached[x, q]
    assert reached[p, q] and reached[pA, m] and reached[qi, q]


def test_second_order_block_modes_and_response():
    c = circuit("second_order_step")
    wn, zeta, k = 10.0, 0.3, 2.0
    model = linearise(c, operating_point(c, {}, c.settings), ["u.y1"], ["so", "tf_full"])
    pairs = [m for m in modes(model) if m.oscillating]
    assert len(pairs) == 3  # so, tf, tf_full: one denominator
    for pair in pairs:
        assert pair.eigenvalue == pytest.approx(complex(-zeta * wn, wn * math.sqrt(1 - zeta**2)), rel=1e-7)
        assert pair.damping == pytest.approx(zeta, rel=1e-7)
    freqs = np.array([0.05, 1.0, 1.6, 7.0])
    s = 2j * math.pi * freqs
    den = s**2 + 2 * zeta * wn * s + wn**2
    response = frequency_response(model, freqs)
    np.testing.assert_allclose(response[:, 0, 0], k * wn**2 / den, rtol=1e-7)
    np.testing.assert_allclose(response[:, 1, 0], (0.5 * s**2 + 3 * s + 200) / den, rtol=1e-7)


def test_equilibrium_operating_point_with_a_state_that_keeps_integrating():
    c = circuit("linear_rest")
    q = 3.0 / 60000  # 3 l/min instead of the netlist's 6
    point = operating_point(c, {"qcmd.value": q}, c.settings, at=0.0, equilibrium=True)
    assert point.x[c.structure.net_state["P"].index] == pytest.approx(q / G, rel=1e-9)
    model = linearise(c, point, ["qcmd.value"], ["p", "qi"])
    assert integrating(model, point) == ["acc.x"]  # the integrator of a constant keeps integrating
    assert at_rest(model, point)
    assert "equilibrium" in point.how


def test_no_equilibrium_where_the_shut_in_oil_rests_anywhere():
    from blocks.errors import SimulationError

    c = circuit("linear_modes")
    with pytest.raises(SimulationError, match="singular"):
        operating_point(c, {}, c.settings, at=0.0, equilibrium=True)


def test_the_state_of_the_run_at_a_time():
    c = circuit("linear_rest")
    point = operating_point(c, {}, c.settings, at=0.05)
    tau = V / (BETA * G)  # 0.125 s: the pressure is on its way from 1 bar to q/G
    p_end = 1e-4 / G
    expected = p_end + (1e5 - p_end) * math.exp(-0.05 / tau)
    assert point.x[c.structure.net_state["P"].index] == pytest.approx(expected, rel=1e-6)
    assert point.t == 0.05 and "t = 0.05 s" in point.how


def test_an_input_at_its_bound_is_differenced_one_sided():
    c = circuit("linear_modes")
    for g in (100.0, -100.0, -9.81):  # the mass's gravity at its upper and lower bounds, and inside
        point = operating_point(c, {"load.g_x": g}, c.settings, at=0.0)
        model = linearise(c, point, ["load.g_x"], ["v"])
        assert model.B[state_index(model, "rod.v"), 0] == pytest.approx(1.0, rel=1e-6)  # dv/dt = ... + g_x


def test_a_slow_mode_beside_a_fast_one_is_not_an_integrator():
    """Found by a review: eigenvalues under 1e-9 of the largest were taken as 0, so a 2 l net drained by a
    tiny leak (-0.01/s) beside a 0.01 cm^3 node (-1.6e8/s) was called an integrator, its gain 'none'."""
    from blocks.linearise import LinearModel, OperatingPoint

    A, B = np.diag([-0.01, -1.6e8]), np.array([[BETA / V], [0.0]])
    model = LinearModel(A, B, np.array([[1.0, 0.0]]), np.zeros((1, 1)), ["P.p", "N.p"], ["Pa", "Pa"],
                        np.array([1e5, 1e5]), ["q"], ["m^3/s"], ["p"], ["Pa"], OperatingPoint(0.0, np.zeros(2), {}, ""))
    assert [m.eigenvalue for m in modes(model)] == [pytest.approx(-0.01, rel=1e-12), pytest.approx(-1.6e8)]
    gain, why = steady_gain(model)
    assert gain[0, 0] == pytest.approx(BETA / V / 0.01, rel=1e-12) and why[0, 0] == ""


def test_a_free_body_elsewhere_leaves_the_gains_it_does_not_touch():
    """Found by a review: a Jordan block anywhere (a free body's speed and position) made every steady-state
    gain 'none (it integrates the input)'; the gain is computed on the states between input and output."""
    c = circuit("linear_free")
    point = operating_point(c, {}, c.settings, at=0.0)
    model = linearise(c, point, ["qcmd.value", "fcmd.value"], ["p", "x"])
    scale = model.state_nominal
    _, right = np.linalg.eig(model.A * scale[None, :] / scale[:, None])
    assert np.linalg.cond(right) > 1e12  # the premise: A is defective
    gain, why = steady_gain(model)
    assert gain[0, 0] == pytest.approx(1.0 / G, rel=1e-7) and why[0, 0] == ""  # p/q
    assert why[0, 1] == GAIN_UNCOUPLED and why[1, 0] == GAIN_UNCOUPLED  # p/f, x/q
    assert why[1, 1] == GAIN_DEFECTIVE and math.isnan(gain[1, 1])  # x/f: a double integrator
