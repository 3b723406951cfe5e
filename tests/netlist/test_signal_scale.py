"""Which nominal magnitude a generic signal block's state gets (blocks/compiler/signal_scale.py, blocks/nominal.py).

The absolute tolerance of a state is atol times its nominal; a filter or integrator on a signal whose
quantity the netlist fixes takes that quantity's nominal (a pressure 1e5 Pa, a force 1e3 N), found from a
port's declared unit, from a parameter written in a unit, or through blocks that pass the same quantity on
(a sum, a filter); otherwise it keeps its declared 1.
"""

from __future__ import annotations

import textwrap

import pytest

from blocks.block import ACROSS
from blocks.compiler.structure import PHYSICAL_STATE_NOMINAL
from blocks.nominal import nominal_magnitude
from blocks.units import parse_unit
from netlist_helpers import load

CHAIN = """
    components:
      src:    {type: pressure_source, params: {p: "50 bar"}}
      sense:  {type: pressure_sensor}
      ref:    {type: constant, params: {value: 4e6}}
      err:    {type: sum, params: {k1: 1, k2: -1}}
      smooth: {type: lowpass2, params: {wn: "30 rad/s"}}
      ctl:    {type: pid, params: {Kp: 1e-6, Ki: 1e-6}}
      total:  {type: integrator}
      scaled: {type: gain, params: {k: 2}}
      after:  {type: lowpass2, params: {wn: "30 rad/s"}}
      force:  {type: step, params: {t_step: "0.1 s", y0: 0, y1: "2 kN"}}
      high:   {type: highpass2, params: {wn: "10 rad/s"}}
      plant:  {type: second_order, params: {wn: "10 rad/s", k: 1e-3}}
    nets:
      P: [src.port, sense.port]
      r: [ref.y, err.u1]
      p: [sense.p, err.u2, scaled.u]
      e: [err.y, smooth.u]
      e_smooth: [smooth.y, ctl.e]
      c: [ctl.y, total.u]
      i: [total.y]
      p2: [scaled.y, after.u]
      a: [after.y]
      f: [force.y, high.u, plant.u]
      h: [high.y]
      x: [plant.y]
    simulation: {t_end: "0.2 s", dt_out: "10 ms"}
"""


def nominals(tmp_path, text: str) -> dict[str, float]:
    path = tmp_path / "n.yaml"
    path.write_text(textwrap.dedent(text))
    return {slot.name: slot.nominal for slot in load(path).structure.states if slot.kind == "block"}


def test_each_generic_state_takes_the_scale_its_netlist_fixes(tmp_path):
    assert nominals(tmp_path, CHAIN) == {
        # a pressure sensor's p [Pa] through the error sum and the filter: a pressure, 1 bar
        "smooth.x": 1e5, "smooth.dx": 1e5,
        "ctl.xd": 1e5,  # the PID's filtered error: e's scale
        "ctl.xi": 1.0,  # its output, an integrator's input: no port or value says what it is
        "total.x": 1.0,
        "after.x": 1.0, "after.dx": 1.0,  # behind a gain: another quantity, not known
        "high.x": 1e3, "high.dx": 1e3,  # a step to "2 kN": a force, 1 kN
        "plant.x": 1.0, "plant.dx": 1.0,  # second_order scales by its output (k changes the quantity)
    }


def test_a_bare_number_fixes_no_scale(tmp_path):
    found = nominals(tmp_path, CHAIN.replace('y1: "2 kN"', "y1: 2000"))
    assert found["high.x"] == found["high.dx"] == 1.0


def test_a_limit_written_in_a_unit_fixes_the_scale_through_the_saturation(tmp_path):
    text = CHAIN.replace("a: [after.y]", "a: [after.y, lim.u]\n      l: [lim.y]").replace(
        "      force:", '      lim:    {type: saturation, params: {lower: "-2 l/min", upper: "2 l/min"}}\n      force:')
    found = nominals(tmp_path, text)
    assert found["after.x"] == found["after.dx"] == 1e-4  # a flow, from the saturation's limits downstream


def test_a_group_that_a_converting_gain_joins_to_another_quantity_takes_the_smaller_nominal(tmp_path):
    # a sum's gain converting a pressure into a force (k1 in m^2): the group holds both; the force's 1e3 N
    # keeps both at least as tight as their own nominal
    found = nominals(tmp_path, CHAIN.replace("f: [force.y, high.u, plant.u]", "f: [force.y, high.u, plant.u, mix.u2]")
                     .replace("p: [sense.p, err.u2, scaled.u]", "p: [sense.p, err.u2, scaled.u, mix.u1]")
                     .replace("      force:", "      mix:    {type: sum, params: {k1: 1e-3, k2: 1}}\n      force:")
                     .replace("x: [plant.y]", "x: [plant.y]\n      m: [mix.y]"))
    assert found["high.x"] == found["smooth.x"] == found["ctl.xd"] == 1e3


@pytest.mark.parametrize("unit, nominal", [
    ("bar", 1e5), ("l/min", 1e-4), ("mm", 0.1), ("m/s", 0.1), ("rpm", 1.0), ("kN", 1e3), ("N*m", 10.0),
    ("l", 1e-3), ("1", 1.0), ("deg", 1.0), ("kg", 1.0), ("1/s", 1.0),
])
def test_the_nominal_of_a_dimension(unit, nominal):
    assert nominal_magnitude(parse_unit(unit)) == nominal


def test_the_nets_states_use_the_same_table():
    assert PHYSICAL_STATE_NOMINAL == {kind: nominal_magnitude(parse_unit(unit)) for kind, (_, unit) in ACROSS.items()}
    assert [PHYSICAL_STATE_NOMINAL[kind] for kind in ACROSS] == [1e5, 1.0, 0.1]  # Pa, rad/s, m/s as before
