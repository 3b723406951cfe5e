"""Names in a netlist are read as written: YAML 1.1 would read the keys `on:`, `off:`, `yes:`, `no:` as
booleans (a component `on` became 'True', and its nets said "unknown component 'on'")."""

from __future__ import annotations

from blocks.netlist.yaml_source import parse_yaml_text
from blocks.circuit import Circuit

NETLIST = """
components:
  on:   {type: step, params: {t_step: 1, y0: 0, y1: 2}}
  off:  {type: step, params: {t_step: 2, y0: 0, y1: 2}}
  no:   {type: sum, params: {k1: 1, k2: -1}}
nets:
  yes: [on.y, no.u1]
  n: [off.y, no.u2]
  y: [no.y]
outputs:
  pulse: no.y
simulation: {t_end: 3 s, dt_out: 0.5 s}
"""


def test_yaml_boolean_words_as_keys_are_names():
    data = parse_yaml_text("on: 1\nOFF: 2\nyes: {no: 3}\nnull: 4\ntrue: [on, yes]\n", "f.yaml").data
    assert data == {"on": 1, "OFF": 2, "yes": {"no": 3}, "null": 4, "true": [True, True]}  # values: YAML's


def test_components_and_nets_named_on_off_yes_no_run(tmp_path):
    path = tmp_path / "words.yaml"
    path.write_text(NETLIST)
    result = Circuit.from_file(path).simulate()
    assert list(result.values[:, 0]) == [0, 0, 2, 2, 0, 0, 0]
