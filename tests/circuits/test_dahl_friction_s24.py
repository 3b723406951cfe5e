"""Dahl spool friction in the spool relief valve holds |z| <= 1 and gives the hysteresis its docstring
states (blocks/library/hydraulic/spool_relief_valve.py), on a slow ramp up and back down
(tests/circuits/netlists/dahl_ramp.yaml): where the friction slides (|z| = 1) the spool sits at
u = (p - p_set -+ p_fric)/k_s, going up and coming down.

Found by a physics audit (session 24): the sign of the spool's speed was smoothed as u'/sqrt(u'^2 + w^2),
which settles z at sqrt(u'^2 + w^2)/u' > 1; on a ramp this slow the friction grew without bound and the
valve stayed nearly shut 20 bar above its setting.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np

from blocks.circuit import Circuit

NETLIST = Path(__file__).parent / "netlists" / "dahl_ramp.yaml"


@lru_cache(maxsize=None)
def run():
    circuit = Circuit.from_file(NETLIST)
    return circuit.simulate(), circuit.vectors().values


def test_the_friction_state_never_leaves_its_bound():
    r, _ = run()
    assert np.abs(r["z"]).max() <= 1.0 + 1e-9


def test_sliding_up_and_down_the_spool_sits_where_spring_pressure_and_friction_balance():
    r, v = run()
    for direction, t0, t1 in ((+1.0, 0.0, 1000.0), (-1.0, 1000.0, 2000.0)):
        m = (r.t > t0) & (r.t < t1) & (np.abs(r["z"] - direction) < 1e-6)
        expected = np.clip((r["p"][m] - v["p_set"] - direction * v["p_fric"]) / v["k_s"], 0.0, 1.0)
        interior = (expected > 0.05) & (expected < 0.95)  # away from the rounded stroke limits
        assert interior.sum() > 20, direction
        assert np.allclose(r["u"][m][interior], expected[interior], atol=1e-4), direction


def test_the_hysteresis_is_two_friction_pressures_wide():
    r, v = run()
    up, down = (r.t < 1000.0), (r.t > 1000.0)
    u_mid = 0.5
    p_up = np.interp(u_mid, r["u"][up], r["p"][up])
    p_down = np.interp(u_mid, r["u"][down][::-1], r["p"][down][::-1])
    assert abs((p_up - p_down) - 2.0 * v["p_fric"]) < 1e-3 * v["p_fric"]
