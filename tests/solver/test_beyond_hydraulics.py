"""A pressure no hydraulic circuit reaches (over 10000 bar) is not passed off as a result (blocks.circuit
P_BEYOND). Found by a usability review: the drive line with 0.01 ml lines at a fixed step of 20 ms ran to
exit 0 with 1e11 bar in its lines and -41 km of travel, said only as 'cavitation'."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from blocks.circuit import P_BEYOND, Circuit
from blocks.errors import SimulationError

ROOT = Path(__file__).resolve().parents[2]
CLOSED = {"components": {"pump": {"type": "flow_source", "params": {"q": "60 l/min"}}, "tank": {"type": "tank"}},
          "nets": {"T": ["tank.port", "pump.a"], "V": {"ports": ["pump.b"], "volume": "1 l"}},
          "outputs": {"p": {"of": "V", "unit": "bar"}}}


def _circuit(tmp_path, doc) -> Circuit:
    (tmp_path / "net.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return Circuit.from_file(tmp_path / "net.yaml")


def test_a_closed_volume_filled_past_any_hydraulic_pressure_is_warned_of(tmp_path):
    """1 l/s into 1 l of oil: dp/dt = K Q / V, so the pressure passes 10000 bar after about 0.6 s at the
    default bulk modulus; the run itself is right (its pressure is the closed form's) and is kept, warned."""
    circuit = _circuit(tmp_path, dict(CLOSED, simulation={"t_end": "2 s", "dt_out": "0.1 s"}))
    result = circuit.simulate()
    p = result["p"]
    assert p[-1] > P_BEYOND and np.allclose(np.diff(p), np.diff(p)[0], rtol=1e-6)  # linear, as the closed form
    (warning,) = [w for w in result.warnings if "beyond any hydraulic pressure" in w]
    assert warning.startswith(f"net 'V' reached {p[-1] / 1e5:.3g} bar at t = 2 s") and "no relief valve" in warning
    short = _circuit(tmp_path, dict(CLOSED, simulation={"t_end": "0.2 s", "dt_out": "0.1 s"})).simulate()
    assert not any("beyond" in w for w in short.warnings)  # 3200 bar: high, but a pressure


def test_a_fixed_step_that_diverges_is_an_error(tmp_path):
    doc = yaml.safe_load((ROOT / "netlists" / "examples" / "drive_line.yaml").read_text())
    doc["parameters"]["V_line"] = "0.00001 l"
    doc["simulation"].update(solver="fixed", fixed_step="20 ms")
    with pytest.raises(SimulationError, match=r"net.yaml: net '[AB]' reached .* bar at t = .* s, beyond any "
                                              r"hydraulic pressure \(over 10000 bar\): either the fixed step of 0\.02 s"):
        _circuit(tmp_path, doc).simulate()
    doc["simulation"]["fixed_step"] = "0.1 ms"  # short enough: the same circuit runs, within hydraulics
    result = _circuit(tmp_path, dict(doc, simulation=dict(doc["simulation"], t_end="0.3 s"))).simulate()
    assert np.max(np.abs(result["pA"])) < 300e5
