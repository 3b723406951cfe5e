"""A generic signal whose dimension the netlist gives twice, by a written value and by a port's declared
unit, must agree (blocks/netlist/signal_dimensions.py): found by a review, a constant of "6 bar" driving a
flow source ran as 6e5 m^3/s."""

from __future__ import annotations

import textwrap

import pytest

import cli

FLOW = """
    fluid: {beta: "1e9 Pa"}
    parameters: {q0: Q0}
    components:
      tank:  {type: tank}
      qcmd:  SOURCE
      pump:  {type: flow_source_signal}
      drain: {type: laminar_orifice, params: {G: "1e-11 m^3/(s*Pa)"}}
    nets:
      T: [tank.port, pump.a, drain.b]
      P: {ports: [pump.b, drain.a], volume: "1 l"}
      q: [qcmd.y, pump.q]
    simulation: {t_end: "0.1 s", dt_out: "10 ms"}
"""


def validate(tmp_path, capsys, text: str) -> tuple[int, str]:
    path = tmp_path / "n.yaml"
    path.write_text(textwrap.dedent(text))
    code = cli.main(["validate", str(path)])
    out, err = capsys.readouterr()
    return code, err.strip() or out.strip()


@pytest.mark.parametrize("q0, source, message", [
    ('"6 bar"', "{type: constant, params: {value: \"6 bar\"}}",
     "n.yaml:6:36: qcmd.value = '6 bar' is a pressure, but the signal qcmd.y is a flow: pump.q reads it in m^3/s"),
    ('"6 bar"', "{type: constant, params: {value: q0}}",
     "qcmd.value = 'q0' is a pressure, but the signal qcmd.y is a flow: pump.q reads it in m^3/s"),
    ('"6 bar"', "{type: constant, params: {value: \"2*q0\"}}", "qcmd.value = '2*q0' is a pressure"),
    ('"1 s"', "{type: profile, params: {times: [0, 1], values: [\"0 bar\", \"5 bar\"]}}",
     "qcmd.values = [0 bar, 5 bar] is a pressure, but the signal qcmd.y is a flow"),
    ('"1 s"', "{type: step, params: {y0: 0, y1: \"3 rpm\"}}", "qcmd.y1 = '3 rpm' is an angular velocity, but"),
])
def test_a_value_of_another_dimension_is_refused_at_its_place(tmp_path, capsys, q0, source, message):
    code, said = validate(tmp_path, capsys, FLOW.replace("Q0", q0).replace("SOURCE", source))
    assert code == 2
    assert message in said and said.count("\n") == 0


@pytest.mark.parametrize("q0, source", [
    ('"6 l/min"', "{type: constant, params: {value: \"6 l/min\"}}"),
    ('"6 l/min"', "{type: constant, params: {value: q0}}"),
    ("1e-4", "{type: constant, params: {value: q0}}"),  # a bare number: SI, not checked
    ('"1 s"', "{type: profile, params: {times: [0, 1], values: [0, \"5 l/min\"]}}"),
])
def test_a_value_of_the_readers_dimension_or_a_bare_number_is_taken(tmp_path, capsys, q0, source):
    code, said = validate(tmp_path, capsys, FLOW.replace("Q0", q0).replace("SOURCE", source))
    assert code == 0, said


def test_a_table_read_with_a_signal_of_another_dimension_is_refused(tmp_path, capsys):
    code, said = validate(tmp_path, capsys, """
        fluid: {beta: "1e9 Pa"}
        components:
          src:   {type: pressure_source, params: {p: "50 bar"}}
          sense: {type: pressure_sensor}
          map:   {type: lookup_1d, params: {x_table: ["0 l/min", "60 l/min"], y_table: [0, 1]}}
        nets:
          P: [src.port, sense.port]
          p: [sense.p, map.u]
          y: [map.y]
        simulation: {t_end: "0.1 s", dt_out: "10 ms"}
    """)
    assert code == 2
    assert ("map.x_table = [0 l/min, 60 l/min] is a flow, but the signal map.u is a pressure: sense.p drives "
            "it in Pa") in said


def test_a_spool_command_in_mm_is_refused(tmp_path, capsys):
    code, said = validate(tmp_path, capsys, """
        fluid: {beta: "1e9 Pa"}
        components:
          supply: {type: pressure_source, params: {p: "100 bar"}}
          tank:   {type: tank}
          cmd:    {type: saturation, params: {lower: "-5 mm", upper: "5 mm"}}
          ref:    {type: constant, params: {value: 0.5}}
          valve:  {type: valve_4_3, params: {A_max: "10 mm^2", x_db: 0.02}}
        nets:
          P: [supply.port, valve.P]
          T: [tank.port, valve.T, valve.A, valve.B]
          r: [ref.y, cmd.u]
          x: [cmd.y, valve.x]
        simulation: {t_end: "0.1 s", dt_out: "10 ms"}
    """)
    assert code == 2
    assert "cmd.lower = '-5 mm' is a length, but the signal cmd.y is a plain number: valve.x reads it in 1" in said
