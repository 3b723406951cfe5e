"""The VAA motion-control valve's flow force (eq. 3.13) is a fit up to q_ff_max of relief flow, at crack
settings from 95.4 to 211.5 bar (table 3.2). Beyond the flow the block holds the polynomial at its end, and
beyond the settings it extrapolates the nearest one's; a run that goes there is warned of
(blocks/valid_ranges.py). Checked on the chapter-3 test rig's step test (netlists/rig/mcv_rig_step.yaml,
relief flow up to about 100 l/min) with q_ff_max lowered to 60 l/min: its largest value is the rig's flow
meter's (which reads the flow the valve meters out, within its sensor's 1 % here); with the flow force off
the fit's range does not apply."""

from __future__ import annotations

import re
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit
from blocks.netlist.flatten import flatten
from vphs_blocks.mcv_vaa import LPM, MotionControlValveVAA

NETLIST = Path(__file__).resolve().parents[2] / "netlists" / "rig" / "mcv_rig_step.yaml"


@lru_cache(maxsize=None)
def rig():
    flat = flatten(NETLIST)
    return Circuit(flat)


def run(**overrides):
    return rig().simulate({f"mcv.{k}": v for k, v in overrides.items()})


def fit_warnings(result) -> list[str]:
    return [w for w in result.warnings if "flow force's polynomial" in w]


def test_a_relief_flow_beyond_the_fit_is_warned_of_with_its_largest_value():
    r = run(q_ff_max=60.0 / LPM)
    (line,) = fit_warnings(r)
    m = re.match(r"mcv: C2\.flow left its valid range \(at least -60 l/min\) at t = ([\d.]+) s, reaching "
                 r"(-[\d.]+) l/min at t = ([\d.]+) s", line)
    assert m, line
    first, worst, when = (float(g) for g in m.groups())
    assert first < when and -worst > 60.0
    assert -worst == pytest.approx(r["Q"].max() * LPM, rel=0.01)
    assert "fitted up to q_ff_max = 60 l/min" in line


def test_with_the_flow_force_off_the_fits_range_does_not_apply():
    assert fit_warnings(run(q_ff_max=60.0 / LPM, flow_force=0.0)) == []


def test_the_ranges_are_the_relief_flows_out_of_both_c_ports():
    values = {p.name: p.default for p in MotionControlValveVAA.params} | {"flow_force": 1.0, "q_ff_max": 1e-3}
    ranges = MotionControlValveVAA.valid_ranges(values)
    assert [(r.signal, r.lower, r.upper) for r in ranges] == [("C1.flow", -1e-3, np.inf), ("C2.flow", -1e-3, np.inf)]
    assert MotionControlValveVAA.valid_ranges(values | {"flow_force": 0.0}) == ()


def crack_warnings(result) -> list[str]:
    return [w for w in result.warnings if "crack settings the flow force was fitted at" in w]


def test_a_crack_setting_beyond_the_fits_is_warned_of():
    """The flow force's polynomials were fitted at 95.4, 152 and 211.5 bar (table 3.2): 230 bar (the bridge
    crane's setting) extrapolates; 211.5 bar does not; with the flow force off nothing is fitted."""
    (line,) = crack_warnings(run(p_crack=230e5))
    assert line == ("mcv: p_crack = 230 bar is outside the crack settings the flow force was fitted at (95.4 to "
                    "211.5 bar, table 3.2): its polynomial for the nearest is extrapolated")
    assert crack_warnings(run(p_crack=211.5e5)) == []
    assert crack_warnings(run(p_crack=230e5, flow_force=0.0)) == []
