"""Signals that leave their block's valid range are warned of after a run (blocks/valid_ranges.py), on
tests/circuits/netlists/valid_ranges.yaml, whose closed forms are in its description: a ramp u = t
leaves a table on [0, 1.5] at t = 1.5 s and a range_check's upper limit 1.2 at t = 1.2 s; a closed volume
filled at a constant flow, p = beta*q*t/V, passes a 100 bar range_check at t = 0.6 s. Each warning gives
the first output sample outside the range and the value furthest outside; a table told not to warn and a
check whose range holds the signal say nothing; the checked signals are observed but not logged.
"""

from __future__ import annotations

import re
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit
from vphs_blocks import lga_geometry as lga
from vphs_blocks.lga_jib_load import LgaJibLoad

NETLIST = Path(__file__).parent / "netlists" / "valid_ranges.yaml"
DT = 0.01  # dt_out
BETA, Q, V = 1e9, 1e-3 / 60.0, 1e-3
WARNING = re.compile(r"^(\w+): (\w+) left its valid range \((.+)\) at t = ([\d.e+-]+) s, reaching ([\d.e+-]+)"
                     r"(?: (\S+))? at t = ([\d.e+-]+) s; outside it (.+)$")


@lru_cache(maxsize=None)
def circuit():
    return Circuit.from_file(NETLIST)


@lru_cache(maxsize=None)
def warned():
    """{block: (range text, first time out, furthest value, its unit, its time, what the block does)}."""
    found = {}
    for line in circuit().simulate().warnings:
        m = WARNING.match(line)
        assert m, line
        block, _, shown, first, worst, unit, when, outside = m.groups()
        found[block] = (shown, float(first), float(worst), unit, float(when), outside)
    return found


def test_a_table_read_beyond_its_breakpoints_says_when_and_how_far():
    shown, first, worst, _, when, outside = warned()["table"]
    assert shown == "0 to 1.5"
    assert 1.5 <= first <= 1.5 + DT  # u = t passes 1.5 at t = 1.5 s
    assert (worst, when) == (pytest.approx(2.0, rel=1e-9), pytest.approx(2.0))
    assert outside == "the table's end value is held"


def test_range_checks_say_when_a_limit_was_broken():
    shown, first, worst, _, when, _ = warned()["limit"]
    assert shown == "at most 1.2" and 1.2 <= first <= 1.2 + DT and worst == pytest.approx(2.0, rel=1e-9)
    shown, first, worst, unit, when, _ = warned()["rating"]
    assert shown == "at most 100 bar"  # the sensor's output is a pressure: said in bar
    assert 0.6 <= first <= 0.6 + DT  # beta*q*t/V = 100 bar at t = 0.6 s
    assert worst == pytest.approx(BETA * Q * 2.0 / V / 1e5, rel=1e-3) and unit == "bar" and when == pytest.approx(2.0)


def test_signals_inside_their_range_or_not_to_be_checked_say_nothing():
    assert set(warned()) == {"table", "limit", "rating"}  # not 'quiet' (warn_outside 0), not 'inside'


def test_checked_signals_are_observed_but_not_logged():
    c = circuit()
    r = c.simulate()
    assert r.names == ["y", "pA"] and r.values.shape == (len(r.t), 2)
    assert [m.name for m in c.monitors] == ["table.u", "quiet.u", "limit.u", "inside.u", "rating.u"]
    y = np.full(c.n_observed + 1, np.nan)  # one more than observe may write: it must stay untouched
    vec = c.vectors()
    x = vec.x0.copy()
    c.module.observe(0.75, x, vec.theta, y[:-1])
    assert np.allclose(y[2:6], 0.75) and y[6] == pytest.approx(x[0]) and np.isnan(y[-1])


def test_the_jib_loads_range_is_its_angle_range():
    values = {p.name: p.default for p in LgaJibLoad.params} | {"d1_0": 2.24}
    (valid,) = LgaJibLoad.valid_ranges(values)
    geo = lga.LGA(*(values[name] for name in lga.LGA._fields))
    ends = sorted(lga.cylinder_length(values[end], geo) - 2.24 for end in ("theta_min", "theta_max"))
    assert (valid.signal, valid.lower, valid.upper) == ("x1", pytest.approx(ends[0]), pytest.approx(ends[1]))
    # inside the range the angle is not clamped; just beyond it, it is
    for x1, clamped in ((valid.lower + 1e-4, False), (valid.upper - 1e-4, False), (valid.upper + 1e-3, True)):
        theta = lga.theta1_from_d1(2.24 + x1, geo, values["theta_min"], values["theta_max"])
        assert (theta in (values["theta_min"], values["theta_max"])) == clamped, (x1, theta)
