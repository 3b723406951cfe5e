"""An edited netlist written over its original text: only the edited entries change (blocks/netlist/yaml_roundtrip.py,
used by every netlist and experiment that `vphs calibrate` writes)."""

import copy
import difflib
from pathlib import Path

import pytest
import yaml

from blocks.calibrate.patch import HEADER_RULE, NetlistDoc
from blocks.netlist.yaml_roundtrip import dump_over
from blocks.netlist.yaml_source import parse_yaml_text, read_yaml

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted((ROOT / "netlists").rglob("*.yaml"))

ORIGINAL = """\
# A relief rig (drawing 12-345, sheet 2)
parameters:
  k_s: "60 bar"             # spring, per unit stroke
  A_ret: "40 mm^2"

components:
  tank:   {type: tank}
  relief: {type: spool_relief_valve, params: {p_set: "100 bar", k_s: k_s}}   # the valve under test
  ret:    {type: orifice,
           params: {A: A_ret, Cd: 0.7}}

nets:
  T:  [tank.port, ret.b]
  R:
    - relief.b       # spring chamber drain
    - ret.a
  P1: {ports: [relief.a], volume: "0.5 l"}   # the pump line
"""


def changed_lines(before: str, after: str) -> list[str]:
    return [line for line in difflib.unified_diff(before.splitlines(), after.splitlines(), lineterm="", n=0)
            if line[:1] in "+-" and not line.startswith(("+++", "---"))]


@pytest.mark.parametrize("file", SHIPPED, ids=lambda f: str(f.relative_to(ROOT)))
def test_an_unedited_shipped_file_is_written_back_byte_for_byte(file):
    text = file.read_text()
    assert dump_over(text, read_yaml(file).data) == text


def test_each_edit_changes_only_its_own_text_and_reads_back_as_the_edited_document():
    data = parse_yaml_text(ORIGINAL, "rig.yaml").data
    edited = copy.deepcopy(data)
    edited["parameters"]["k_s"] = "59.118 bar"                                   # a value replaced
    edited["parameters"]["cal_G"] = 1.5e-12                                      # a new entry, block mapping
    edited["components"]["relief"]["params"]["c_ff"] = "cal_cff"                 # a new entry, flow mapping
    edited["components"]["leak"] = {"type": "laminar_orifice", "params": {"G": "cal_G"}}
    edited["nets"]["R"] = ["relief.b", "leak.a"]                                 # a block list replaced
    edited["nets"]["P1"]["ports"] = ["relief.a", "leak.b"]                       # a flow list replaced
    edited["outputs"] = {"p1": {"of": "P1", "unit": "bar"}}                     # a new section
    text = dump_over(ORIGINAL, edited)
    assert text is not None and parse_yaml_text(text, "new.yaml").data == edited
    assert changed_lines(ORIGINAL, text) == [
        '-  k_s: "60 bar"             # spring, per unit stroke',
        '+  k_s: "59.118 bar"             # spring, per unit stroke',
        '+  cal_G: 1.5e-12',
        '-  relief: {type: spool_relief_valve, params: {p_set: "100 bar", k_s: k_s}}   # the valve under test',
        '+  relief: {type: spool_relief_valve, params: {p_set: "100 bar", k_s: k_s, c_ff: cal_cff}}   # the valve under test',
        '+  leak: {type: laminar_orifice, params: {G: cal_G}}',
        '-  R:',
        '-    - relief.b       # spring chamber drain',
        '-    - ret.a',
        '-  P1: {ports: [relief.a], volume: "0.5 l"}   # the pump line',
        '+  R: [relief.b, leak.a]',
        '+  P1: {ports: [relief.a, leak.b], volume: "0.5 l"}   # the pump line',
        '+outputs:',
        '+  p1: {of: P1, unit: bar}',
    ]


@pytest.mark.parametrize("value", ["a, b", "x: y", "{odd}", "1e-6", "yes", "", "# not a comment", 1e-300,
                                   float("inf"), True, None, 7, [1, "2 bar", [3]]])
def test_a_value_that_yaml_reads_otherwise_unquoted_is_written_so_that_it_reads_back(value):
    edited = parse_yaml_text(ORIGINAL, "rig.yaml").data
    edited["components"]["ret"]["params"]["Cd"] = value      # inside a flow mapping
    edited["parameters"]["new"] = value                       # a block mapping's new entry
    text = dump_over(ORIGINAL, edited)
    assert text is not None and parse_yaml_text(text, "new.yaml").data == edited


def test_an_edit_it_cannot_place_gives_none_and_the_file_is_written_afresh(tmp_path):
    """An entry removed is not placed in the text: the document is written whole (its comments lost),
    never a text that reads as something else."""
    data = parse_yaml_text(ORIGINAL, "rig.yaml").data
    del data["parameters"]["A_ret"]
    assert dump_over(ORIGINAL, data) is None
    (tmp_path / "rig.yaml").write_text(ORIGINAL)
    doc = NetlistDoc.read(tmp_path / "rig.yaml")
    del doc.data["parameters"]["A_ret"]
    written = doc.write(tmp_path / "out" / "new.yaml").read_text()
    assert "drawing 12-345" not in written and yaml.safe_load(written) == doc.data


def test_a_file_written_from_one_vphs_wrote_has_the_new_header_only(tmp_path):
    (tmp_path / "rig.yaml").write_text(ORIGINAL)
    doc = NetlistDoc.read(tmp_path / "rig.yaml")
    doc.add_parameter("cal_a", 1.0)
    first = doc.write(tmp_path / "round1" / "augmented.yaml", header="Round 1.\nAdded: a.")
    again = NetlistDoc.read(first)
    again.add_parameter("cal_b", 2.0)
    second = again.write(tmp_path / "round2" / "augmented.yaml", header="Round 2.").read_text()
    assert second.startswith(f"# Round 2.\n{HEADER_RULE}\n# A relief rig (drawing 12-345, sheet 2)\n")
    assert "Round 1" not in second
    assert changed_lines(ORIGINAL, second.split(HEADER_RULE + "\n", 1)[1]) == ["+  cal_a: 1.0", "+  cal_b: 2.0"]


def test_a_subsystem_path_moved_for_the_new_folder_changes_only_that_path(tmp_path):
    (tmp_path / "parts").mkdir()
    (tmp_path / "top.yaml").write_text(
        "# three axes\nsubsystems:\n  bridge: {netlist: parts/axis.yaml}   # the bridge\n")
    doc = NetlistDoc.read(tmp_path / "top.yaml")
    written = doc.write(tmp_path / "out" / "top.yaml").read_text()
    assert written == "# three axes\nsubsystems:\n  bridge: {netlist: ../parts/axis.yaml}   # the bridge\n"


def test_an_effect_added_as_calibrate_adds_it_keeps_every_comment_and_adds_no_empty_section(tmp_path):
    """Found by the diff review: NetlistDoc.unique() made an empty `subsystems:` section, whose insertion
    shared its place with the new net's at the end of `nets:` and was made in the wrong order there, so
    every such file was written afresh, its comments lost."""
    (tmp_path / "rig.yaml").write_text(ORIGINAL)
    doc = NetlistDoc.read(tmp_path / "rig.yaml")
    name = doc.unique("cal_leak")
    doc.add_parameter("cal_G", 1e-12)
    doc.add_component(name, "laminar_orifice", {"G": "cal_G"})
    doc.move_port("relief.a", "cal_node", f"{name}.a", f"{name}.b", volume=1e-6, initial="20 bar")
    written = doc.write(tmp_path / "out" / "augmented.yaml").read_text()
    assert yaml.safe_load(written) == {k: v for k, v in doc.data.items() if v != {}}
    assert changed_lines(ORIGINAL, written) == [
        "+  cal_G: 1.0e-12",
        "+  cal_leak: {type: laminar_orifice, params: {G: cal_G}}",
        '-  P1: {ports: [relief.a], volume: "0.5 l"}   # the pump line',
        '+  P1: {ports: [cal_leak.a], volume: "(0.5 l) - 1e-06 m^3"}   # the pump line',
        '+  cal_node: {ports: [relief.a, cal_leak.b], volume: 1.0e-06, initial: "20 bar"}',
    ]


def test_a_crlf_file_stays_crlf(tmp_path):
    (tmp_path / "rig.yaml").write_bytes(ORIGINAL.replace("\n", "\r\n").encode())
    doc = NetlistDoc.read(tmp_path / "rig.yaml")
    doc.add_parameter("cal_a", 1.0)
    written = doc.write(tmp_path / "out" / "rig.yaml", header="Added: a.").read_bytes()
    assert written.count(b"\n") == written.count(b"\r\n") == ORIGINAL.count("\n") + 3  # + cal_a, header, rule


def test_anchors_and_aliases_are_written_afresh_not_misplaced():
    """An alias's node is its anchor's, positions and all: an entry placed after it would land after the
    anchor instead (found by the diff review)."""
    text = "base: &b {A: 1}\nc:\n  x: *b\n"
    data = parse_yaml_text(text, "a.yaml").data
    data["n"] = 1
    assert dump_over(text, data) is None
