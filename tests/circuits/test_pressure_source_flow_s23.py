"""What an ideal pressure source (a tank) delivers to its net, logged as ``<source>.port.flow``: the flow that
holds its pressure, q = -sum(q_k) of the other blocks on the net (blocks/compiler/codegen.py). Before, it
could not be logged ("pressure_source delivers no flow at 'port'"): the supply flow a pump must give was
read off the blocks beside it.

The circuit and its closed form: tests/circuits/netlists/pressure_source_flow.yaml.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from blocks.circuit import Circuit

NETLIST = Path(__file__).parent / "netlists" / "pressure_source_flow.yaml"
PS, G1, G2, V, BETA = 100e5, 1e-11, 3e-11, 1e-3, 8e8
TAU = V / (BETA * (G1 + G2))


def test_the_supply_and_the_tank_deliver_the_orifices_flows_and_conserve_the_volumes_oil():
    r = Circuit.from_file(NETLIST).simulate()
    p = PS * G1 / (G1 + G2) * (1.0 - np.exp(-r.t / TAU))
    assert np.allclose(r["pA"], p, rtol=1e-6, atol=1e-3 * PS * 1e-6)
    assert np.allclose(r["q_supply"], G1 * (PS - p), rtol=1e-6, atol=1e-12)
    assert np.allclose(r["q_tank"], -G2 * p, rtol=1e-6, atol=1e-12)
    # what goes into the volume compresses its oil: q_s + q_t = (V/beta) dp/dt
    rate = PS * G1 / (G1 + G2) / TAU * np.exp(-r.t / TAU)
    assert np.allclose(r["q_supply"] + r["q_tank"], V / BETA * rate, rtol=1e-5, atol=1e-13)
    assert r["q_supply"][0] > 0 > r["q_tank"][-1]  # the supply feeds, the tank takes
