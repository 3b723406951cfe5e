"""A netlist expression may read a component's parameter or a net's value of the same file by its dotted
name (``initial: supply.p``): evaluated in dependency order, so an override of ``supply.p`` (a group of a
calibration, a run, an optimiser) moves everything that reads it."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from blocks.circuit import Circuit
from blocks.errors import VphsError

CASE = Path(__file__).resolve().parent / "cases" / "expression_attribute.yaml"


def _netlist(tmp_path: Path, **changes) -> Path:
    """The error fixture's circuit, made valid: supply.p = 100 bar; ``changes`` edit it (a callable each)."""
    net = yaml.safe_load(CASE.read_text())
    net["components"]["supply"]["params"]["p"] = "p_s"
    for edit in changes.values():
        edit(net)
    path = tmp_path / "dotted.yaml"
    path.write_text(yaml.safe_dump(net, sort_keys=False))
    return path


def _initial_from_supply(net):
    net["nets"]["M"]["initial"] = "supply.p - 5 bar"


def test_a_net_starts_at_a_components_parameter_and_follows_its_override(tmp_path):
    circuit = Circuit.from_file(_netlist(tmp_path, a=_initial_from_supply), compile=False)
    values = circuit.flat.parameters.evaluate({})
    assert values["M.initial"] == pytest.approx(95e5)
    assert circuit.flat.parameters.evaluate({"supply.p": 150e5})["M.initial"] == pytest.approx(145e5)
    assert circuit.flat.parameters.evaluate({"p_s": 50e5})["M.initial"] == pytest.approx(45e5)


def test_a_dotted_name_of_the_wrong_dimension_is_a_located_error(tmp_path):
    def area(net):
        net["nets"]["M"]["initial"] = "inlet.A"

    with pytest.raises(VphsError, match=r"dotted\.yaml:\d+:\d+: M\.initial: wrong unit"):
        Circuit.from_file(_netlist(tmp_path, a=area), compile=False)


def test_an_unknown_dotted_name_is_a_located_error_with_a_hint(tmp_path):
    def typo(net):
        net["nets"]["M"]["initial"] = "suply.p"

    with pytest.raises(VphsError, match=r"dotted\.yaml:\d+:\d+: unknown parameter 'suply\.p' in M\.initial "
                                        r"\(did you mean supply\.p"):
        Circuit.from_file(_netlist(tmp_path, a=typo), compile=False)


def test_dotted_names_in_a_cycle_are_named(tmp_path):
    def cycle(net):
        net["components"]["supply"]["params"]["p"] = "M.initial"
        net["nets"]["M"]["initial"] = "supply.p"

    with pytest.raises(VphsError, match=r"parameters depend on each other in a cycle: .*supply\.p"):
        Circuit.from_file(_netlist(tmp_path, a=cycle), compile=False)


def test_a_subsystem_reads_its_own_components_and_its_parent_does_not_reach_inside(tmp_path):
    """Within a subsystem file ``ctrl.k2`` is that instance's own component; from the parent, a name two
    dots deep (``bridge.ctrl.k2``) is not in scope."""
    examples = Path(__file__).resolve().parents[2] / "netlists" / "examples"
    (tmp_path / "parts").mkdir()
    axis = yaml.safe_load((examples / "parts" / "axis.yaml").read_text())
    axis["parameters"]["k_twice"] = "2*ctrl.k2"
    (tmp_path / "parts" / "axis.yaml").write_text(yaml.safe_dump(axis, sort_keys=False))
    top = yaml.safe_load((examples / "three_axes.yaml").read_text())
    (tmp_path / "three_axes.yaml").write_text(yaml.safe_dump(top, sort_keys=False))
    values = Circuit.from_file(tmp_path / "three_axes.yaml", compile=False).flat.parameters.evaluate({})
    for axis_name in ("bridge", "trolley", "slew"):
        assert values[f"{axis_name}.k_twice"] == pytest.approx(2 * values[f"{axis_name}.ctrl.k2"])
    assert values["trolley.k_twice"] == pytest.approx(12.0)  # the trolley's Kp = 6 reaches its own ctrl
    top["parameters"]["reach"] = "bridge.ctrl.k2"
    (tmp_path / "three_axes.yaml").write_text(yaml.safe_dump(top, sort_keys=False))
    with pytest.raises(VphsError, match=r"unknown parameter 'bridge\.ctrl\.k2' in reach"):
        Circuit.from_file(tmp_path / "three_axes.yaml", compile=False)


def _write(tmp_path: Path, name: str, text: str) -> Path:
    (tmp_path / name).write_text(text)
    return tmp_path / name


SUB = """parameters:
  V: "0.1 l"
  secret: 42
  p_start: "P.initial"
components:
  orif: {type: orifice, params: {A: "5 mm^2", Cd: 0.7}}
nets:
  P: {ports: [orif.a], volume: V, initial: "50 bar"}
  T: [orif.b]
ports:
  P: P
  T: T
"""

TOP = """parameters:
  pa: "A.initial"
components:
  o2: {type: orifice, params: {A: "5 mm^2", Cd: 0.7}}
  tank: {type: tank}
subsystems:
  left: {netlist: sub.yaml}
nets:
  A: {ports: [o2.a, left.P], volume: "0.2 l"OUTER}
  T: [tank.port, left.T, o2.b]
"""


@pytest.mark.parametrize("outer", ["", ', initial: "80 bar"'], ids=["inner initial only", "outer initial wins"])
def test_a_net_merged_through_a_subsystem_port_has_one_initial_read_from_both_sides(tmp_path, outer):
    """The subsystem's P joins the parent's A: one net, one start; P.initial inside and A.initial outside
    both read it (the outer value wins when both are written)."""
    _write(tmp_path, "sub.yaml", SUB)
    top = _write(tmp_path, "top.yaml", TOP.replace("OUTER", outer))
    values = Circuit.from_file(top, compile=False).flat.parameters.evaluate({})
    start = 80e5 if outer else 50e5
    assert values["A.initial"] == pytest.approx(start)
    assert values["pa"] == pytest.approx(start) and values["left.p_start"] == pytest.approx(start)


def test_a_net_cannot_share_a_subsystems_name(tmp_path):
    _write(tmp_path, "sub.yaml", SUB)
    top = _write(tmp_path, "top.yaml", TOP.replace("OUTER", "") + "  left: {ports: [], volume: \"1 l\"}\n")
    with pytest.raises(VphsError, match=r"top\.yaml:\d+:\d+: duplicate name 'left' \(a component, subsystem or "
                                        r"net already has it\)"):
        Circuit.from_file(top, compile=False)


def test_a_unit_before_a_dotted_name_stays_a_unit(tmp_path):
    """"1 bar/A.initial": the unit is bar, and A.initial a dotted name (not a unit bar/A, per ampere)."""
    def ratio(net):
        net["nets"]["A"] = net["nets"].pop("M")  # A: a usual net name, and the ampere's symbol
        net["outputs"]["pM"]["of"] = "A"
        net["parameters"]["ratio"] = "1 bar/A.initial"
        net["parameters"]["twice"] = "2 bar*A.initial/p_s"

    values = Circuit.from_file(_netlist(tmp_path, a=ratio), compile=False).flat.parameters.evaluate({})
    assert values["ratio"] == pytest.approx(1e5 / 10e5) and values["twice"] == pytest.approx(2e5 * 10e5 / 100e5)


def test_a_dotted_name_reads_one_value_not_a_list(tmp_path):
    def reads_times(net):
        net["components"]["ref"] = {"type": "profile", "params": {"times": [0, 1], "values": [0, 1]}}
        net["parameters"]["t_last"] = "max(ref.times)"

    with pytest.raises(VphsError, match=r"t_last: 'ref\.times' is a list of values; an expression reads one value"):
        Circuit.from_file(_netlist(tmp_path, a=reads_times), compile=False)
