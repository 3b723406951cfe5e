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
