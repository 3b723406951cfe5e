"""The lumped pipe (blocks/library/hydraulic/pipe.py) against Hagen-Poiseuille, Blasius and its own first
mode; tests/circuits/netlists/pipe.yaml. Expected values are computed here from the textbook laws."""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from blocks.circuit import Circuit
from blocks.library.hydraulic.pipe import Pipe, friction_drop
from blocks.linearise import linearise, modes, operating_point

NETLIST = Path(__file__).parent / "netlists" / "pipe.yaml"
RHO, NU, BETA = 850.0, 3.2e-5, 1.5e9


@lru_cache(maxsize=None)
def circuit() -> Circuit:
    return Circuit.from_file(NETLIST)


@lru_cache(maxsize=None)
def run():
    return circuit().simulate()


def test_laminar_flow_is_hagen_poiseuille():
    resistance = 128 * RHO * NU * 5.0 / (math.pi * 0.006**4)  # Pa*s/m^3
    q = 20e5 / (resistance + 1 / 2e-11)
    assert run()["q_lam"][-1] == pytest.approx(q, rel=1e-7)
    assert q / (math.pi * 0.003**2) * 0.006 / NU < 2000  # laminar indeed
    assert run()["pM"][-1] == pytest.approx(q / 2e-11, rel=1e-7)


def test_turbulent_flow_is_blasius():
    d, l, area = 0.01, 2.0, math.pi * 0.005**2

    def drop(q):  # Darcy-Weisbach with Blasius' friction factor
        v = q / area
        reynolds = v * d / NU
        return 0.3164 * reynolds**-0.25 * l / d * RHO * v * v / 2

    q = brentq(lambda q: drop(q) - 50e5, 1e-6, 1.0, xtol=1e-14)
    assert q / area * d / NU > 4000
    assert run()["q_turb"][-1] == pytest.approx(q, rel=1e-7)


def test_the_shut_pipe_rings_at_its_lumped_first_mode():
    c = circuit()
    model = linearise(c, operating_point(c, {}, c.settings, at=0.0), [], [])
    l, area = 10.0, math.pi * 0.006**2
    inertance, capacity = RHO * l / area, area * l / 2 / BETA  # the shut end holds half the pipe's oil
    expected = 1 / math.sqrt(inertance * capacity) / (2 * math.pi)
    assert expected == pytest.approx(math.sqrt(2 * BETA / RHO) / l / (2 * math.pi), rel=1e-12)
    rings = [m for m in modes(model) if m.oscillating and dict(m.participation).get("shut.q", 0) > 0.3]
    assert len(rings) == 1
    assert rings[0].natural_frequency == pytest.approx(expected, rel=1e-6)
    laminar_r = 128 * RHO * NU * l / (math.pi * 0.012**4)
    assert rings[0].damping == pytest.approx(laminar_r / 2 * math.sqrt(capacity / inertance), rel=1e-4)


@settings(max_examples=200, deadline=None)
@given(st.floats(1e-7, 1e-2), st.floats(1e-7, 1e-2))
def test_friction_rises_with_the_flow_and_is_odd(q1, q2):
    lo, hi = sorted((q1, q2))
    args = (3.0, 0.008, RHO, NU)
    assert friction_drop(hi, *args) >= friction_drop(lo, *args)
    assert friction_drop(-hi, *args) == -friction_drop(hi, *args)


def test_the_blend_is_continuous_through_the_transition():
    d, area = 0.008, math.pi * 0.004**2
    q_at = [re * NU / d * area for re in (2000.0, 4000.0)]
    for q in q_at:
        assert friction_drop(q * (1 + 1e-9), 3.0, d, RHO, NU) == pytest.approx(
            friction_drop(q * (1 - 1e-9), 3.0, d, RHO, NU), rel=1e-6)


def test_the_block_stores_half_its_volume_at_each_end():
    out = Pipe.derivatives(50e5, 50e5, 0.0, 4.0, 0.01, RHO, NU)
    half = math.pi * 0.005**2 * 4.0 / 2
    assert out[:4] == (-0.0, 0.0, pytest.approx(half), pytest.approx(half)) and out[4] == 0.0
