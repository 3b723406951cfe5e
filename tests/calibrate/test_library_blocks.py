"""The generic blocks calibration inserts (line_loss, spool_relief_valve, stribeck_friction, pade_delay), each
alone against its closed form (raw functions called by keyword), plus two small circuits."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from blocks.library.hydraulic.flow import turbulent_flow
from blocks.library.hydraulic.line_loss import LineLoss
from blocks.library.hydraulic.spool_relief_valve import SpoolReliefValve, rounded_unit
from blocks.library.mechanical.stribeck_friction import StribeckFriction
from blocks.library.mechanical.trans_stribeck_friction import TransStribeckFriction
from blocks.library.signal.pade_delay import PadeDelay

BAR = 1e5
RHO = 850.0


def named(cls, values) -> dict:
    names = cls.derivative_names()
    assert len(values) == len(names)
    return dict(zip(names, values))


# ---------------------------------------------------------------- line_loss
@pytest.mark.parametrize("q", [-2e-3, -1e-4, 0.0, 3e-5, 1.5e-3])
def test_line_loss_at_rest_obeys_its_pressure_drop_law(q):
    k, R, R0, L = 2e11, 3e8, 1e5, 3e-6
    dp = (R0 + R) * q + k * q * abs(q)  # the law at rest, written independently of the block
    d = named(LineLoss, LineLoss.derivatives(a=50 * BAR + dp, b=50 * BAR, q=q, k=k, R=R, R_0=R0, L=L))
    assert d["der_q"] == pytest.approx(0.0, abs=1e-6 * max(abs(dp), 1.0) / L)
    assert d["q_a"] == -q and d["q_b"] == q  # what leaves a enters b


def test_line_loss_accelerates_the_flow_by_the_unbalanced_drop():
    k, R, R0, L = 1e11, 0.0, 1e5, 2.0
    q, dp = 1e-3, 3 * BAR
    d = named(LineLoss, LineLoss.derivatives(a=dp, b=0.0, q=q, k=k, R=R, R_0=R0, L=L))
    assert d["der_q"] == pytest.approx((dp - R0 * q - k * q * q) / L, rel=1e-12)


# ---------------------------------------------------------------- spool_relief_valve
BASE = dict(p_set=40 * BAR, k_s=60 * BAR, A_max=60e-6, c_ff=0.0, p_fric=0.0, u_z=1e-3, wn=2 * math.pi * 300,
            zeta=1.0, u_w=0.01, Cd=0.7, dp_t=1e4, rho=RHO)


@pytest.mark.parametrize("c_ff", [0.0, 0.3, -0.2])
@pytest.mark.parametrize("dp_bar", [45.0, 52.0, 60.0])
def test_spool_relief_rests_at_its_spring_and_flow_force_balance(c_ff, dp_bar):
    dp = dp_bar * BAR
    u = (dp - BASE["p_set"]) / (BASE["k_s"] + c_ff * dp)  # u*k_s = dp - p_set - c_ff*u*dp, solved by hand
    assert 0.02 < u < 0.98
    d = named(SpoolReliefValve, SpoolReliefValve.derivatives(a=dp + 2 * BAR, b=2 * BAR, u=u, du=0.0, z=0.0,
                                                             **{**BASE, "c_ff": c_ff}))
    assert d["der_du"] == pytest.approx(0.0, abs=1e-6)
    q = 0.7 * 60e-6 * u * math.sqrt(2 / RHO) * dp / (dp * dp + 1e8) ** 0.25
    assert d["q_b"] == pytest.approx(q, rel=1e-12) and d["q_a"] == -d["q_b"]


def test_spool_relief_is_shut_below_its_setting_and_pulls_towards_closing():
    d = named(SpoolReliefValve, SpoolReliefValve.derivatives(a=30 * BAR, b=0.0, u=0.0, du=0.0, z=0.0, **BASE))
    assert d["q_a"] == 0.0 and d["der_du"] == 0.0
    d = named(SpoolReliefValve, SpoolReliefValve.derivatives(a=30 * BAR, b=0.0, u=0.2, du=0.0, z=0.0, **BASE))
    assert d["der_du"] < 0


def test_dahl_friction_holds_the_spool_short_of_its_equilibrium():
    # at rest with z = +1 (came up): balance u*k_s = dp - p_set - p_fric
    p_fric = 2 * BAR
    dp = 50 * BAR
    u = (dp - BASE["p_set"] - p_fric) / BASE["k_s"]
    d = named(SpoolReliefValve, SpoolReliefValve.derivatives(a=dp, b=0.0, u=u, du=0.0, z=1.0,
                                                             **{**BASE, "p_fric": p_fric}))
    assert d["der_du"] == pytest.approx(0.0, abs=1e-6) and d["der_z"] == 0.0  # z stays where it was
    d = named(SpoolReliefValve, SpoolReliefValve.derivatives(a=dp, b=0.0, u=u, du=0.5, z=0.0,
                                                             **{**BASE, "p_fric": p_fric}))
    assert d["der_z"] == pytest.approx(0.5 / 1e-3 * 1.0, rel=1e-12)  # moving up from z = 0: z' = u'/u_z


def test_rounded_unit_is_exact_outside_its_corners_and_c1_at_them():
    w = 0.1
    for x, y in ((-0.3, 0.0), (0.0, 0.0), (0.1, 0.1), (0.5, 0.5), (0.9, 0.9), (1.0, 1.0), (1.4, 1.0)):
        assert rounded_unit(x, w) == pytest.approx(y, abs=1e-15)
    h = 1e-7
    for x in (w, 1 - w):
        left = (rounded_unit(x, w) - rounded_unit(x - h, w)) / h
        right = (rounded_unit(x + h, w) - rounded_unit(x, w)) / h
        assert left == pytest.approx(1.0, abs=1e-5) and right == pytest.approx(1.0, abs=1e-5)


# ---------------------------------------------------------------- stribeck_friction
def test_stribeck_friction_closed_form():
    p = dict(Tc=2.0, dTs=3.0, w_s=5.0, b=0.1, w_w=0.01)
    for w in (0.0, 0.05, 1.0, 5.0, 50.0, -20.0):
        expected = -((2.0 + 3.0 * math.exp(-(w / 5.0) ** 2)) * math.tanh(w / 0.01) + 0.1 * w)
        assert StribeckFriction.derivatives(port=w, **p)[0] == pytest.approx(expected, rel=1e-14, abs=1e-15)
    # near standstill (|w| >> w_w, << w_s) the breakaway torque Tc + dTs; far beyond w_s only Tc + b*w
    assert StribeckFriction.derivatives(port=0.2, **p)[0] == pytest.approx(-(2.0 + 3.0 * math.exp(-0.0016) + 0.02), rel=1e-9)
    assert StribeckFriction.derivatives(port=40.0, **p)[0] == pytest.approx(-(2.0 + 4.0), rel=1e-9)


def test_translational_stribeck_friction_is_the_rotational_law_in_force_and_velocity():
    """f = -((Fc + dFs*exp(-(v/v_s)^2))*tanh(v/v_w) + b*v): the same numbers through both blocks."""
    p = dict(Fc=200.0, dFs=800.0, v_s=5e-3, b=50.0, v_w=1e-4)
    for v in (0.0, 2e-5, 1e-3, 5e-3, 0.1, -0.04):
        expected = -((200.0 + 800.0 * math.exp(-(v / 5e-3) ** 2)) * math.tanh(v / 1e-4) + 50.0 * v)
        assert TransStribeckFriction.derivatives(port=v, **p)[0] == pytest.approx(expected, rel=1e-14, abs=1e-12)
        rot = StribeckFriction.derivatives(port=v, Tc=200.0, dTs=800.0, w_s=5e-3, b=50.0, w_w=1e-4)[0]
        assert TransStribeckFriction.derivatives(port=v, **p)[0] == rot
    # at 1 mm/s (>> v_w, << v_s) nearly the breakaway force Fc + dFs; at 0.1 m/s only Fc + b*v
    assert TransStribeckFriction.derivatives(port=1e-3, **p)[0] == pytest.approx(-(200.0 + 800.0 * math.exp(-0.04)
                                                                                   + 0.05), rel=1e-8)  # tanh(10)
    assert TransStribeckFriction.derivatives(port=0.1, **p)[0] == pytest.approx(-(200.0 + 5.0), rel=1e-9)


# ---------------------------------------------------------------- pade_delay
def _pade_response(T, omega):
    """G(j omega) of the block, from its linear equations: states x1, x2; y = u - T*x2."""
    A = np.array([[0.0, 1.0], [-12.0 / T ** 2, -6.0 / T]])
    B = np.array([0.0, 12.0 / T ** 2])
    # check A, B against the block's derivatives (linear: columns by unit perturbation)
    for k, (x1, x2, u) in enumerate(((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))):
        der = PadeDelay.derivatives(u=u, x1=x1, x2=x2, T=T, T_min=1e-5)
        col = A[:, k] if k < 2 else B
        assert np.allclose(der, col, rtol=1e-12)
    C, D = np.array([0.0, -T]), 1.0
    assert PadeDelay.outputs(u=0.0, x2=1.0, T=T, T_min=1e-5)[0] == pytest.approx(-T)
    s = 1j * omega
    return C @ np.linalg.solve(s * np.eye(2) - A, B) + D


@pytest.mark.parametrize("omega_T", [0.1, 0.5, 1.0, 2.0])
def test_pade_delay_is_all_pass_with_the_delays_phase_at_low_frequency(omega_T):
    T = 0.02
    G = _pade_response(T, omega_T / T)
    assert abs(G) == pytest.approx(1.0, rel=1e-12)  # all-pass: |G| = 1 at every frequency
    # (2,2) Pade: phase = -2*atan(x/2 / (1 - x^2/12)), x = omega*T; matches -x to O(x^5)
    x = omega_T
    expected = -2 * math.atan2(x / 2, 1 - x * x / 12)
    assert np.angle(G) == pytest.approx(expected, abs=1e-12)
    if x <= 0.5:
        assert np.angle(G) == pytest.approx(-x, abs=2e-4)


def test_pade_delay_passes_through_below_t_min():
    assert PadeDelay.outputs(u=0.7, x2=5.0, T=0.0, T_min=1e-5) == (0.7,)
    assert PadeDelay.derivatives(u=0.7, x1=0.3, x2=5.0, T=1e-6, T_min=1e-5) == (0.0, 0.0)


# ---------------------------------------------------------------- small circuits
def test_circuit_pade_delays_a_ramp(tmp_path):
    from blocks.circuit import Circuit

    T = 0.05
    net = {"components": {"r": {"type": "ramp", "params": {"slope": 2.0, "t_start": 0.1}},
                          "d": {"type": "pade_delay", "params": {"T": T}}},
           "nets": {"u": ["r.y", "d.u"]}, "outputs": {"u": "r.y", "y": "d.y"},
           "simulation": {"t_end": 1.0, "dt_out": "1 ms", "rtol": 1e-8, "atol": 1e-8}}
    path = tmp_path / "delay.yaml"
    path.write_text(yaml.safe_dump(net))
    r = Circuit.from_file(path).simulate()
    late = r.t > 0.5
    # a ramp delayed by T: y = 2*(t - 0.1 - T) once the transient (a few T) has passed
    assert np.allclose(r["y"][late], 2.0 * (r.t[late] - 0.1 - T), atol=1e-5)


def test_circuit_flow_through_line_loss_settles_on_its_law(tmp_path):
    from blocks.circuit import Circuit

    q, k = 1e-3, 4e11
    net = {"components": {"tank": {"type": "tank"}, "pump": {"type": "flow_source", "params": {"q": q}},
                          "loss": {"type": "line_loss", "params": {"k": k}}},
           "nets": {"T": ["tank.port", "pump.a", "loss.b"], "P": {"ports": ["pump.b", "loss.a"], "volume": "1 ml"}},
           "outputs": {"p": "P"}, "simulation": {"t_end": 0.05, "dt_out": "1 ms", "rtol": 1e-8, "atol": 1e-8}}
    path = tmp_path / "loss.yaml"
    path.write_text(yaml.safe_dump(net))
    r = Circuit.from_file(path).simulate()
    assert r["p"][-1] == pytest.approx(1e5 * q + k * q * q, rel=1e-6)  # R_0*q + k*q^2 (R_0 = 1e5 by default)
    assert turbulent_flow(0.0, 1.0, 0.7, RHO, 1e4) == 0.0
