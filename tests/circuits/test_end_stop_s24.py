"""A cylinder's end stop can only push (blocks/library/hydraulic/cylinder.py), on a free piston hitting
its retracted stop at 0.5 m/s (tests/circuits/netlists/end_stop.yaml).

Found by a physics audit (session 24): the stop's force k*d - c*v*s(d) had no lower limit, and while the
piston left the stop faster than the spring relaxed (v > k/c*d) the damping pulled it back in: -5.0 kN at
0.1 mm inside the stop. Now the stop pushes or lets go.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np

from blocks.circuit import Circuit

NETLIST = Path(__file__).parent / "netlists" / "end_stop.yaml"


@lru_cache(maxsize=None)
def run():
    return Circuit.from_file(NETLIST).simulate()


def test_the_stop_only_pushes():
    r = run()
    inside = r["x"] < 0.0
    assert inside.any() and r["f"][inside].max() > 1e3  # it did hit the stop, hard
    assert r["f"].min() >= 0.0  # chambers at the tank: the rod force is the stop's alone
    assert np.all(r["f"][~inside] == 0.0)


def test_the_piston_leaves_the_stop_slower_than_it_came():
    r = run()
    assert r["x"][-1] > 0.0 and r["v"][-1] > 0.0
    assert r["v"][-1] < 0.5
    # free flight after the contact: the speed it left with is kept
    after = r.t > r.t[np.flatnonzero(r["f"] > 0.0)[-1]]
    assert np.ptp(r["v"][after]) < 1e-9
