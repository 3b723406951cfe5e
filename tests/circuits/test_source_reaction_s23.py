"""What an ideal speed or velocity source delivers to its net, logged as ``<source>.port.torque`` /
``.force`` (fault s23-1: it could not be logged; an engineer sizing the prime mover read a pump's shaft
torque instead).

The source holds its net's speed whatever it takes: the torque it delivers is what makes the rigid body
follow, tau = J_eq*dw/dt - sum(r_k*tau_k) (blocks/library/mechanical/speed_source.py). The closed forms are in
the netlist's description (tests/circuits/netlists/source_reaction.yaml).
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

import cli
from blocks.circuit import Circuit

NETLIST = Path(__file__).parent / "netlists" / "source_reaction.yaml"
T0 = 0.2  # s: both ramps start here (the rate of the speed jumps: samples next to it are left out)


@lru_cache(maxsize=None)
def run():
    circuit = Circuit.from_file(NETLIST)
    return circuit.simulate(), circuit.vectors().values


def away_from_the_kink(t):
    return np.abs(t - T0) > 1e-3


def test_a_speed_source_ramping_an_inertia_through_a_gear_delivers_j_a_plus_the_damping():
    r, v = run()
    J_eq = v["load.J"] + v["load2.J"] / v["n"] ** 2
    rate = np.where(r.t > T0, v["a"], 0.0)
    w = v["w0"] + v["a"] * np.maximum(r.t - T0, 0.0)
    assert np.allclose(r["w"], w, rtol=1e-12)
    expected = J_eq * rate + v["b2"] * w / v["n"] ** 2
    keep = away_from_the_kink(r.t)
    assert np.allclose(r["tau"][keep], expected[keep], rtol=1e-6, atol=1e-9)
    assert r["tau"][-1] > v["b2"] * w[-1] / v["n"] ** 2 + 0.9 * J_eq * v["a"]  # the inertia's part is there


def test_a_velocity_source_lifting_a_mass_delivers_its_weight_and_m_a():
    r, v = run()
    expected = v["m"] * (np.where(r.t > T0, v["av"], 0.0) + 9.81)
    keep = away_from_the_kink(r.t)
    assert np.allclose(r["f"][keep], expected[keep], rtol=1e-6)


def test_a_speed_source_turning_a_pump_at_constant_speed_delivers_the_pumps_torque_reversed():
    r, v = run()
    assert np.allclose(r["tau_m"], -r["tau_pump"], rtol=1e-9, atol=1e-9)
    assert np.allclose(r["tau_m"], v["pump.D"] * r["pP"], rtol=1e-9, atol=1e-9)
    assert r["pP"][-1] > 50e5  # the pump works against a pressure: the torque is not trivially 0


def test_a_source_torque_is_in_newton_metres_in_the_csv(tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert cli.main(["run", str(NETLIST), "-o", str(out)]) == 0
    header = next(line for line in out.read_text().splitlines() if not line.startswith("#"))
    assert "tau [N*m]" in header and "f [N]" in header, header
