"""pressure_source_signal holds its net at the signal's pressure: a ramp through a laminar orifice into a
volume, against the first-order system's ramp response in closed form."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from blocks.circuit import Circuit

NETLIST = Path(__file__).parent / "netlists" / "pressure_ramp.yaml"


def test_a_ramped_supply_through_an_orifice_into_a_volume():
    result = Circuit.from_file(NETLIST).simulate()
    t = result.t
    slope, tau = 100e5, 1e-3 / (8e8 * 1e-11)  # Pa/s; V/(beta*G) = 0.125 s
    np.testing.assert_allclose(result["p_s"], slope * t, rtol=1e-12, atol=1e-6)
    expected = slope * (t - tau * (1 - np.exp(-t / tau)))
    np.testing.assert_allclose(result["p"], expected, rtol=1e-6, atol=1.0)
    assert result["p"][-1] < 0.9 * slope * t[-1]  # the lag is there: a mis-wired source would not show it
    assert math.isclose(result["p_s"][-1], 100e5)
