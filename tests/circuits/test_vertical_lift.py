"""A mass's weight along a vertical motion (mass g_x): a free fall at g, and a load lifted by a cylinder at
the pump's flow over the piston area with the pressure its weight needs (netlists/vertical_lift.yaml)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from blocks.circuit import Circuit

NETLIST = Path(__file__).parent / "netlists" / "vertical_lift.yaml"
G, M, A_A, Q, B = 9.81, 2000.0, 19.63e-4, 10e-3 / 60, 1e5


def test_a_free_mass_falls_at_g_and_a_lifted_load_needs_its_weight_over_the_area():
    r = Circuit.from_file(NETLIST).simulate()
    assert np.max(np.abs(r["vs"] + G * r.t)) < 1e-6  # v = -g t (free fall: the 50 kg's weight on its mass)
    late = r.t > 1.0  # the 99 bar start settles within a few hundred ms (damping ratio about 0.5)
    v = Q / A_A
    assert np.max(np.abs(r["v"][late] - v)) < 1e-6  # m/s, of 84.9 mm/s
    assert np.max(np.abs(r["pA"][late] - (M * G + B * v) / A_A)) < 10.0  # Pa: weight and damping, 143.2 bar
    assert abs((M * G + B * v) / A_A - 143.2e5) < 0.1e5  # the numbers above, by hand
    assert np.max(np.abs(r["pA"][late] - B * v / A_A)) > 90e5  # without the weight: 43 bar
