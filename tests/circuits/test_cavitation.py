"""Cavitation in a hydraulic net (blocks.library.hydraulic.cavitation) against the volume balance.

A closed 1 l net at 10 bar is drawn from at 0.1 l/s for 1 s, then fed back at 0.1 l/s for 1 s. The liquid
gives up V*(10 bar - p_vap)/beta = 1.375 ml on the way down to the vapour pressure (13.75 ms); the rest of
the 100 ml drawn, 98.625 ml, is a vapour cavity, which the returning oil fills first: the pressure is back
above p_vap once 98.625 ml have returned (t = 1.98625 s) and back at 10 bar at t = 2 s, the oil balanced.
"""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from blocks.circuit import Circuit
from blocks.errors import VphsError
from blocks.library.hydraulic.cavitation import CAVITY_COMPLIANCE, CAVITY_ONSET, cavity_volume

BAR, V, BETA, Q = 1e5, 1e-3, 8e8, 1e-4
P_VAP = -1 * BAR
LIQUID = V * (10 * BAR - P_VAP) / BETA  # m^3 the liquid gives up between 10 bar and p_vap
DRAWN = Q * 1.0
NETLIST = {
    "fluid": {"beta": "8e8 Pa", "vapour_pressure": "-1 bar"},
    "components": {"tank": {"type": "tank"},
                   "q": {"type": "profile", "params": {"times": [0, 0.999995, 1.000005, 3],
                                                       "values": [Q, Q, -Q, -Q]}},
                   "pump": {"type": "flow_source_signal"}},
    "nets": {"A": {"ports": ["pump.a"], "volume": "1 l", "initial": "10 bar"}, "T": ["tank.port", "pump.b"],
             "cmd": ["q.y", "pump.q"]},
    "outputs": {"p": {"of": "A", "unit": "bar"}},
    "simulation": {"t_end": "2 s", "dt_out": "0.1 ms", "rtol": 1e-8, "atol": 1e-8},
}


def run(tmp_path, **fluid):
    doc = dict(NETLIST, fluid=dict(NETLIST["fluid"], **fluid))
    (tmp_path / "net.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return Circuit.from_file(tmp_path / "net.yaml").simulate()


def test_a_net_drawn_empty_holds_a_cavity_that_the_returning_oil_fills_first(tmp_path):
    result = run(tmp_path)
    t, p = result.t, result["p"]
    # at its deepest the pressure measures the cavity: its size is the oil drawn less what the liquid gave up
    assert cavity_volume(p.min(), P_VAP) == pytest.approx(DRAWN - LIQUID, rel=1e-3)
    assert P_VAP - CAVITY_ONSET - (DRAWN - LIQUID) / CAVITY_COMPLIANCE < p.min() < P_VAP  # a little under p_vap
    # the cavity opens when the liquid has given up LIQUID, and closes when as much has returned
    opened = t[np.argmax(p < P_VAP)]
    closed = t[np.nonzero(p < P_VAP)[0][-1] + 1]
    assert opened == pytest.approx(LIQUID / Q, abs=2e-4)
    assert closed == pytest.approx(1.0 + (DRAWN - LIQUID) / Q, abs=2e-4)
    assert p[-1] == pytest.approx(10 * BAR, rel=1e-4)  # the oil balanced: back where it started
    (warning,) = result.warnings
    assert ("net 'A' reached the vapour pressure -1 bar, first seen at t = 0.0138 s; a vapour cavity of up to "
            "98.6 cm^3 formed there") in warning


def test_without_the_law_the_liquid_is_stretched_into_tension_and_warned_of(tmp_path):
    result = run(tmp_path, cavitation=False)
    p = result["p"]
    assert p.min() == pytest.approx(10 * BAR - BETA * DRAWN / V, rel=1e-4)  # -790 bar: a tension oil cannot carry
    assert p[-1] == pytest.approx(10 * BAR, rel=1e-4)
    (warning,) = result.warnings
    assert "net 'A' fell to -790 bar, below the vapour pressure -1 bar" in warning and "cavitation: false" in warning


def test_the_cavity_is_the_oil_that_left_even_as_the_volume_changes(tmp_path):
    """A sealed cylinder chamber (0.1 l dead volume, 20 cm^2) at 0 bar, its piston pulled out 45 mm at
    0.1 m/s by a speed source: the liquid gives up V*(0 - p_vap)/beta, the rest of the 90 cm^3 the piston
    sweeps is vapour, whatever the chamber's volume did meanwhile; pushed back, the cavity is gone once the
    piston has returned that far, and the pressure is back at 0 bar at the start position."""
    doc = {
        "fluid": {"beta": "8e8 Pa", "vapour_pressure": "-1 bar"},
        "components": {"tank": {"type": "tank"},
                       "cyl": {"type": "cylinder", "params": {"A_A": "20 cm^2", "A_B": "10 cm^2", "stroke": "0.5 m",
                                                               "V0_A": "0.1 l", "V0_B": "0.1 l"},
                               "initial": {"x": "0.1 m"}},
                       "v": {"type": "profile", "params": {"times": [0, 0.449995, 0.450005, 2],
                                                           "values": [0.1, 0.1, -0.1, -0.1]}},
                       "drive": {"type": "velocity_source"}},
        "nets": {"A": {"ports": ["cyl.A"], "initial": "0 bar"}, "B": ["cyl.B", "tank.port"],
                 "rod": ["cyl.rod", "drive.port"], "cmd": ["v.y", "drive.v"]},
        "outputs": {"pA": {"of": "A", "unit": "bar"}, "x": "cyl.position"},
        "simulation": {"t_end": "0.9 s", "dt_out": "0.5 ms", "rtol": 1e-8, "atol": 1e-8},
    }
    (tmp_path / "cyl.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    result = Circuit.from_file(tmp_path / "cyl.yaml").simulate()
    p, x = result["pA"], result["x"]
    V_start = 1e-4 + 20e-4 * 0.1
    liquid = V_start * (0 - P_VAP) / BETA  # ~0.04 cm^3: the chamber opens a cavity almost at once
    swept = 20e-4 * 0.045
    assert cavity_volume(p.min(), P_VAP) == pytest.approx(swept - liquid, rel=2e-3)
    assert "a vapour cavity of up to 90 cm^3" in result.warnings[0]  # 89.96 to 3 digits
    assert x[-1] == pytest.approx(0.1, abs=1e-6) and p[-1] == pytest.approx(0.0, abs=200.0)  # Pa: back at 0 bar


def test_above_the_vapour_pressure_the_law_changes_nothing(tmp_path):
    """Bit for bit: the liquid's equation is the same expression (beta * 1 is beta)."""
    doc = dict(NETLIST, simulation=dict(NETLIST["simulation"], t_end="0.01 s"))  # 10 -> 2 bar, no cavity
    on, off = (Circuit.from_file(_write(tmp_path / f"{k}.yaml", doc, k)).simulate() for k in ("on", "off"))
    assert on.warnings == off.warnings == []
    np.testing.assert_array_equal(on["p"], off["p"])


def _write(path, doc, which):
    doc = dict(doc, fluid=dict(doc["fluid"], cavitation=which == "on"))
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


@pytest.mark.parametrize("key, value, what", [("cavitation", False, "fluid cavitation"),
                                             ("air", "1 %", "the entrained air"),
                                             ("air_index", 1.4, "the entrained air's index")])
def test_a_subsystem_cannot_set_cavitation_of_its_own(tmp_path, key, value, what):
    part = {"fluid": {key: value}, "ports": {"A": "A"}, "components": {"tank": {"type": "tank"}},
            "nets": {"A": ["tank.port"]}}
    (tmp_path / "part.yaml").write_text(yaml.safe_dump(part))
    top = {"subsystems": {"left": {"netlist": "part.yaml"}}, "components": {},
           "nets": {"A": ["left.A"]}}
    (tmp_path / "top.yaml").write_text(yaml.safe_dump(top))
    with pytest.raises(VphsError, match=rf"part\.yaml:\d+:\d+: {what} is set by the top-level netlist only"):
        Circuit.from_file(tmp_path / "top.yaml", compile=False)
