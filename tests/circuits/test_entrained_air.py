"""Entrained air (blocks/library/hydraulic/entrained_air.py) against the mixture's own volume law.

Per unit volume of liquid at gauge 0, oil with the free-air fraction a (at atmospheric pressure p_atm) takes

    Vm(p) = exp(-p/beta) + a/(1 - a) * (p_atm/(p + p_atm))^(1/n)

at gauge pressure p. A shut net of volume V into which a flow q is pushed keeps its volume while its
mixture's mass grows: V * (-dVm/dp)/Vm * dp/dt = q, so ln(Vm(p0)/Vm(p)) = q*t/V exactly. The expected
pressure at each time is the root of that (brentq) on Vm as written here, not on vphs's bulk modulus.
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from blocks.circuit import Circuit
from blocks.library.hydraulic.cavitation import CAVITY_COMPLIANCE, cavity_volume
from blocks.library.hydraulic.entrained_air import effective_bulk_modulus

NETLIST = Path(__file__).parent / "netlists" / "entrained_air.yaml"
BETA, V, Q, AIR, P_ATM = 8e8, 1e-3, 1e-3 / 60, 0.01, 101325.0


def mixture_volume(p, n=1.0, air=AIR):
    return math.exp(-p / BETA) + air / (1 - air) * (P_ATM / (p + P_ATM)) ** (1 / n)


def pressure_after(volume_in, p0=0.0, n=1.0):
    """The pressure once volume_in [m^3] was pushed into the shut net (volume_in < 0: drawn out)."""
    target = mixture_volume(p0, n) * math.exp(-volume_in / V)
    return brentq(lambda p: mixture_volume(p, n) - target, -0.99 * P_ATM, 1e9, xtol=1e-6, rtol=1e-14)


@lru_cache(maxsize=None)
def circuit() -> Circuit:
    return Circuit.from_file(NETLIST)


@pytest.mark.parametrize("n", [1.0, 1.4])
def test_a_shut_net_filled_follows_the_mixture_law(n):
    result = circuit().simulate({"fluid.air_index": n})
    for t in (0.05, 0.2, 0.5, 1.0):
        k = int(round(t / 0.01))
        expected = pressure_after(Q * t, n=n)
        assert result["p"][k] == pytest.approx(expected, rel=1e-6, abs=1.0), (n, t)
    liquid_only = BETA * Q * 1.0 / V  # 133 bar: the air takes most of the first pushes
    assert result["p"][-1] < 0.5 * liquid_only


def test_the_law_alone():
    # no air: the liquid's modulus exactly; at high pressure the air is squeezed out of the picture
    assert effective_bulk_modulus(50e5, BETA, 0.0, 1.0) == BETA
    for p in (1e5, 10e5, 100e5):
        h = 1.0
        expected = -mixture_volume(p) / ((mixture_volume(p + h) - mixture_volume(p - h)) / (2 * h))
        assert effective_bulk_modulus(p, BETA, AIR, 1.0) == pytest.approx(expected, rel=1e-6)
    assert effective_bulk_modulus(1e5, BETA, AIR, 1.0) < 0.05 * BETA  # soft near the tank's pressure
    assert effective_bulk_modulus(300e5, BETA, AIR, 1.0) > 0.99 * BETA  # stiff at working pressure


def test_no_air_is_the_liquid_above_the_vapour_pressure():
    with_zero = circuit().simulate({"fluid.air": 0.0})
    t = with_zero.t
    np.testing.assert_allclose(with_zero["p"], BETA * Q * t / V, rtol=1e-8, atol=1e-3)  # beta*q*t/V


def test_a_net_drawn_below_the_vapour_pressure_holds_a_cavity_beside_the_expanded_air():
    q_pull = 120e-3 / 60  # 120 l/min for 1 s: 2 l, far more than the air's expansion down to -0.9 bar (77 cm^3)
    result = circuit().simulate({"q_pull": q_pull})
    p_vap = -0.9e5
    p_end = result["pC"][-1]
    assert p_end < p_vap
    # the oil drawn = the mixture's expansion down to p_vap + its compliance below + the vapour cavity
    expansion = V * math.log(mixture_volume(p_vap) / mixture_volume(0.0))
    compliance = V / effective_bulk_modulus(p_vap, BETA, AIR, 1.0)
    cavity = q_pull * 1.0 - expansion - compliance * (p_vap - p_end)
    assert cavity > 0.2 * q_pull
    assert cavity_volume(p_end, p_vap) == pytest.approx(cavity, rel=2e-3)
    warning = [w for w in result.warnings if "net 'C'" in w]
    assert warning and "vapour cavity of up to" in warning[0]
    assert CAVITY_COMPLIANCE > compliance  # the case where the cavity, not the air, takes the draw
