"""Logging what a block delivers at a port, and leaving signal outputs unconnected."""

import math
from pathlib import Path

import pytest

from blocks.circuit import Circuit
from blocks.errors import NetlistError
from blocks.netlist.flatten import flatten

NETLIST = """
components:
  supply: {type: pressure_source, params: {p: "100 bar"}}
  orif: {type: orifice, params: {A: "1 mm^2", Cd: 0.7, dp_t: "1 Pa"}}
  sens: {type: pressure_sensor}
nets:
  P: [supply.port, orif.a]
  V: {ports: [orif.b, sens.port], volume: "1 l"}
outputs:
  q_into_V: {of: orif.b.flow, unit: l/min}
  q_into_P: orif.a.flow
  pV: V
simulation: {t_end: "0.2 s", dt_out: "0.05 s", rtol: 1e-8}
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "net.yaml"
    path.write_text(text)
    return path


def test_port_flow_is_the_orifice_law_and_conserved(tmp_path):
    """The logged flow at b is Cd*A*sqrt(2*dp/rho) into V; at a the same flow leaves P (sensor unconnected)."""
    result = Circuit.from_file(write(tmp_path, NETLIST)).simulate()
    rho = 850.0
    for k in range(len(result.t)):
        dp = 100e5 - result["pV"][k]
        expected = 0.7 * 1e-6 * math.sqrt(2 * dp / rho) if dp > 1e3 else None
        if expected is not None:
            assert result["q_into_V"][k] == pytest.approx(expected, rel=1e-6)
        assert result["q_into_P"][k] == pytest.approx(-result["q_into_V"][k], rel=1e-12, abs=1e-18)
    assert result.display_units[0] == "l/min"


def test_through_value_of_the_wrong_kind_is_refused(tmp_path):
    path = write(tmp_path, NETLIST.replace("orif.b.flow", "orif.b.torque"))
    with pytest.raises(NetlistError) as info:
        Circuit(flatten(path), compile=False)
    assert "port b is hydraulic; ask for its flow" in str(info.value)


def test_outputs_may_name_subsystem_ports_and_merged_nets():
    """'bridge.P' is the exposed port of a subsystem, merged into the outer supply net P: logging it logs P."""
    root = Path(__file__).resolve().parents[2]
    circuit = Circuit(flatten(root / "netlists" / "examples" / "three_axes.yaml"), compile=False)
    generator = circuit.generator
    assert generator.resolve_output("bridge.P") == generator.resolve_output("P")
    assert generator.resolve_output("slew.T") == generator.resolve_output("T")
    assert generator.resolve_output("bridge.A")[1] == "Pa"


def test_a_generic_signal_is_shown_in_the_unit_its_readers_agree_on():
    """The drive line's spool signal comes from a generic second-order block ("SI") and is read by the valve's
    x, a plain number [1]: its column is 'spool [1]', not 'spool [SI]' (a usability review: "[SI]" is not a
    unit). A generic signal no port declares stays "SI"; a written unit wins."""
    from pathlib import Path

    from blocks.circuit import Circuit

    examples = Path(__file__).resolve().parents[2] / "netlists" / "examples"
    shown = {o.name: o.display_unit for o in Circuit.from_file(examples / "drive_line.yaml", compile=False).outputs}
    assert shown["spool"] == "1" and shown["x"] == "mm" and shown["pA"] == "bar"
