"""Bad input the session-20 fuzzer found accepted, or refused in words that were not the user's.

Each bad netlist is a small change to ``cases/base.yaml`` (or a subsystem pair written here); each must
be refused by ``vphs validate`` with exit code 2 and ONE line ``file:line:col: what is wrong``, the place
computed from the text (the needle), never copied from what the code prints.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import cli
from blocks.errors import NetlistError, shorten_values
from netlist_helpers import CASES, load, load_error, position, split_message

BASE = (CASES / "base.yaml").read_text()


def variant(tmp_path: Path, old: str, new: str, name: str = "net.yaml", text: str = BASE) -> Path:
    """``text`` with ``old`` (present once) replaced by ``new``, written to ``tmp_path/name``."""
    assert text.count(old) == 1, old
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path


def refused(path: Path, capsys, needle: str, *words: str, nth: int = 0) -> str:
    """``vphs validate path`` exits with 2 and one line placed at ``needle`` saying ``words``; the message."""
    assert cli.main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("vphs: "), err
    file, line, col, what = split_message(err[len("vphs: "):].rstrip("\n"))
    assert file == str(path), err
    assert (line, col) == position(path.read_text(), needle, nth), err
    for word in words:
        assert word in what, err
    return what


# ---- 1. output names --------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ['"pM "', '" pM"', '"pM\\t"', '"a,b"', '"  "'])
def test_an_output_name_with_spaces_around_it_a_tab_or_a_comma_is_refused(tmp_path, capsys, name):
    """`"x ": {of: ...}` beside `x:` collapsed into one output (the schema strips a name's spaces) and the
    CSV showed the second's values under the first's name; a comma split the header of a spreadsheet."""
    path = variant(tmp_path, "  err:   mix.y", f"  err:   mix.y\n  {name}: {{of: shaft, unit: rpm}}")
    what = refused(path, capsys, name)
    assert ("spaces around" in what or "cannot be empty" in what) if name != '"a,b"' else "','" in what, what


def test_two_outputs_that_would_head_one_csv_column_are_refused(tmp_path):
    """The fuzzer's case: outputs "x" and "x " (the second's values were written under x)."""
    path = variant(tmp_path, "  err:   mix.y", '  err:   mix.y\n  "pM ": {of: shaft, unit: rpm}')
    exc = load_error(path)
    assert isinstance(exc, NetlistError) and "'pM '" in exc.message, exc


@pytest.mark.parametrize("old, new, needle", [
    ("  tank:   {type: tank}", '  tank:   {type: tank}\n  "tank ": {type: tank}', '"tank "'),
    ("  r:     [ref.y, amp.u]", '  "r ":     [ref.y, amp.u]', '"r "'),
    ('  area: "10 mm^2"', '  area: "10 mm^2"\n  "area ": "20 mm^2"', '"area "'),
    ("{A: area, Cd: 0.7}", '{A: area, " Cd": 0.7}', '" Cd"'),
])
def test_any_name_with_spaces_around_it_is_refused(tmp_path, capsys, old, new, needle):
    """A component, net, parameter or block parameter so written silently replaced (or became) another."""
    refused(variant(tmp_path, old, new), capsys, needle, "spaces around")


# ---- 2. initial values that are not finite ----------------------------------------------------------

@pytest.mark.parametrize("value", [".nan", ".inf", "-.inf", '"1e400 bar"'])
def test_a_net_initial_value_that_is_not_finite_is_refused_by_validate(tmp_path, capsys, value):
    """validate said ok and only the run failed (exit 1)."""
    path = variant(tmp_path, 'initial: "10 bar"', f"initial: {value}")
    refused(path, capsys, "initial", "M.initial", "is not finite")


def test_a_state_initial_value_that_is_not_finite_is_refused(tmp_path, capsys):
    path = variant(tmp_path, "  sense:  {type: speed_sensor}",
                   "  sense:  {type: speed_sensor}\n  angle:  {type: angle_sensor, initial: {theta: .nan}}")
    path.write_text(path.read_text().replace("[motor.shaft, load.port, sense.port]",
                                             "[motor.shaft, load.port, sense.port, angle.port]")
                    .replace("  e:     [mix.y]", "  e:     [mix.y]\n  th:    [angle.angle]"))
    refused(path, capsys, "theta", "angle.initial.theta", "is not finite")


def test_a_netlist_parameter_that_is_not_finite_is_refused_even_if_unread(tmp_path, capsys):
    refused(variant(tmp_path, '  area: "10 mm^2"', '  area: "10 mm^2"\n  spare: .nan'), capsys, "spare",
            "is not finite")


# ---- 3. a subsystem port listed twice --------------------------------------------------------------

INNER = """description: an orifice between two nets the file exposes
components:
  orf: {type: orifice, params: {A: "2 mm^2"}}
nets:
  IN: [orf.a]
  OUT: [orf.b]
ports: {in: IN, out: OUT}
"""

OUTER = """description: a supply through the subsystem to a tank
components:
  supply: {type: pressure_source, params: {p: "50 bar"}}
  tank:   {type: tank}
subsystems:
  r1: {netlist: inner.yaml}
nets:
  P: [supply.port, r1.in]
  T: [r1.out, tank.port]
"""


def test_the_subsystem_pair_is_valid(tmp_path):
    (tmp_path / "inner.yaml").write_text(INNER)
    (tmp_path / "outer.yaml").write_text(OUTER)
    load(tmp_path / "outer.yaml")


def test_a_subsystem_port_listed_twice_in_one_net_is_refused(tmp_path, capsys):
    """A component's port twice was refused ("port travel.u is listed twice in net 'theta'"); an exposed
    subsystem port naming an inner net was not."""
    (tmp_path / "inner.yaml").write_text(INNER)
    path = variant(tmp_path, "[supply.port, r1.in]", "[supply.port, r1.in, r1.in]", "outer.yaml", OUTER)
    refused(path, capsys, "r1.in", "port r1.in is listed twice in net 'P'", nth=1)


def test_a_subsystem_port_in_two_nets_is_refused(tmp_path, capsys):
    """It silently joined the two nets into one (the supply straight onto the tank)."""
    (tmp_path / "inner.yaml").write_text(INNER)
    path = variant(tmp_path, "[r1.out, tank.port]", "[r1.out, tank.port, r1.in]", "outer.yaml", OUTER)
    refused(path, capsys, "r1.in", "port r1.in is connected twice (nets 'P' and 'T')", nth=1)


# ---- 4. simulation settings -------------------------------------------------------------------------

@pytest.mark.parametrize("key, value", [("max_step", '"0 s"'), ("max_step", "0"), ("max_step", ".nan"),
                                        ("fixed_step", '"0 s"'), ("t_start", "-.inf")])
def test_a_step_of_zero_or_a_time_that_is_not_finite_is_refused(tmp_path, capsys, key, value):
    """max_step "-1 s" was refused ("must be positive (or left out)"), "0 s" (and nan) accepted."""
    path = variant(tmp_path, '  dt_out: "1 ms"', f'  dt_out: "1 ms"\n  {key}: {value}')
    what = refused(path, capsys, key, f"simulation.{key}")
    assert "must be positive (or left out)" in what or "is not finite" in what, what


# ---- 5. overflow ------------------------------------------------------------------------------------

@pytest.mark.parametrize("expression", ["10.0**400", "exp(1000)"])
def test_an_overflowing_expression_says_so_in_words(tmp_path, capsys, expression):
    """It said "cannot evaluate '10.0**400': (34, 'Numerical result out of range')"."""
    path = variant(tmp_path, '  area: "10 mm^2"', f'  area: "10 mm^2"\n  big: "{expression}"')
    what = refused(path, capsys, "big", f"'{expression}' overflows")
    assert "Numerical result" not in what and "range error" not in what, what


# ---- 6. long values in messages ---------------------------------------------------------------------

def test_a_long_value_is_cut_short_in_the_message(tmp_path, capsys):
    """A 200,000-character preset name gave a 400 kB error line."""
    long = "é" * 200_000
    path = variant(tmp_path, "  tank:   {type: tank}", f'  tank:   {{type: tank, preset: "{long}"}}')
    what = refused(path, capsys, "preset", "has no preset", "…")
    assert len(what) < 300, len(what)


def test_a_long_name_is_cut_short_in_the_message(tmp_path, capsys):
    name = "x" * 1000  # YAML takes a key of up to 1024 characters
    path = variant(tmp_path, "{A: area, Cd: 0.7}", f"{{A: area, Cd: 0.7, {name}: 1}}")
    what = refused(path, capsys, name, "not a parameter of orifice", "…")
    assert len(what) < 400, len(what)


@pytest.mark.parametrize("message, expected", [
    ("short 'abc' stays", "short 'abc' stays"),
    (f"no preset '{'a' * 100}' (its presets: X)", f"no preset '{'a' * 80}…' (its presets: X)"),
    (f'got "{"b" * 90}"', f'got "{"b" * 80}…"'),
    (f"the netlist's value {'c' * 300} is bad", f"the netlist's value {'c' * 60}…{'c' * 20} is bad"),
])
def test_shorten_values(message, expected):
    assert shorten_values(message) == expected


def test_a_message_without_long_values_is_not_changed():
    message = ("the netlist's t_start and the job's t_end: " + "a, " * 30).strip()
    assert shorten_values(message) == message


# ---- 7. a parameter of the wrong shape --------------------------------------------------------------

@pytest.mark.parametrize("value, needle, words", [
    ('{value: "5 mm^2"}', "A: {value", ["components.outlet.params.A: a parameter value must be a number, a '<number> "
                                 "<unit>' string, an expression, a list of these, or {csv: FILE, column: NAME}",
                                 "'value'"]),
    ("{csv: data.csv}", "A: {csv", ["components.outlet.params.A", "missing 'column'"]),
    ("{column: A}", "A: {column", ["components.outlet.params.A", "missing 'csv'"]),
    ("{csv: data.csv, column: A, unit: mm}", "unit", ["unknown key 'unit'", "{csv: FILE, column: NAME}"]),
    ("[1, {a: 2}]", "{a: 2}", ["components.outlet.params.A.1: a value must be a number"]),
])
def test_a_parameter_of_the_wrong_shape_is_said_in_words(tmp_path, capsys, value, needle, words):
    """It said "components.motors.params.D.function-before[_no_boolean(), union[float,int,constrained-str]]:
    Input should be a valid number"."""
    path = variant(tmp_path, '{A: "5 mm^2"}', f"{{A: {value}}}")
    what = refused(path, capsys, needle, *words)
    assert "function-before" not in what and "Input should" not in what, what


@pytest.mark.parametrize("old, new, needle, where", [
    ('  p_s: "100 bar"', "  p_s: {a: 1}", "p_s", "parameters.p_s"),
    ('initial: "10 bar"', "initial: [1]", "initial", "nets.M.initial"),
    ('  t_end: "0.5 s"', "  t_end: [1]", "t_end", "simulation.t_end"),
])
def test_a_value_of_the_wrong_shape_is_said_in_words(tmp_path, capsys, old, new, needle, where):
    what = refused(variant(tmp_path, old, new), capsys, needle, f"{where}: a value must be a number")
    assert "Input should" not in what, what


# ---- 8. defaults, a subsystem's simulation, cavitation ----------------------------------------------

@pytest.mark.parametrize("value, words", [('"1 bar"', ["wrong unit"]), (".nan", ["is not finite"]),
                                          ('"-1 l"', ["must be positive"]), ('"0 l"', ["must be positive"]),
                                          ('"2*p_s"', ["wrong unit"]), ('"2*nothing"', ["unknown parameter"])])
def test_an_unused_default_volume_is_checked(tmp_path, capsys, value, words):
    """Every net of base.yaml names its volume or is held: the default applies to none, and was unchecked."""
    path = variant(tmp_path, "\nparameters:\n", f"\ndefaults: {{volume: {value}}}\nparameters:\n")
    refused(path, capsys, "volume", *words)


def test_a_used_default_volume_still_works(tmp_path):
    path = variant(tmp_path, '{ports: [inlet.b, motor.a, outlet.a], volume: "0.5 l", initial: "10 bar"}',
                   '{ports: [inlet.b, motor.a, outlet.a], initial: "10 bar"}')
    path.write_text(path.read_text().replace("\nparameters:\n", '\ndefaults: {volume: "0.5 l"}\nparameters:\n'))
    circuit = load(path)
    assert circuit.flat.parameters.evaluate()["M.volume"] == pytest.approx(5e-4)


@pytest.mark.parametrize("section, words", [('{t_end: "-1 s"}', ["simulation.t_end", "must be after"]),
                                           ("{dt_out: .nan}", ["simulation.dt_out", "is not finite"]),
                                           ('{max_step: "0 s"}', ["simulation.max_step", "must be positive"])])
def test_a_subsystem_files_simulation_section_is_checked(tmp_path, capsys, section, words):
    """A subsystem file is also a netlist run on its own: its settings, unused where it is a part, are
    checked where it is used too (they were never checked there)."""
    (tmp_path / "inner.yaml").write_text(INNER + f"simulation: {section}\n")
    (tmp_path / "outer.yaml").write_text(OUTER)
    assert cli.main(["validate", str(tmp_path / "outer.yaml")]) == 2
    err = capsys.readouterr().err.strip()
    file, line, col, what = split_message(err[len("vphs: "):])
    needle = words[0].split(".")[1]
    assert file.endswith("inner.yaml") and (line, col) == position(INNER + f"simulation: {section}\n", needle)
    assert all(word in what for word in words), err


@pytest.mark.parametrize("value", ['"yes"', "1", "0", '"true"'])
def test_cavitation_takes_a_boolean_only(tmp_path, capsys, value):
    path = variant(tmp_path, "\nparameters:\n", f"\nfluid: {{cavitation: {value}}}\nparameters:\n")
    refused(path, capsys, "cavitation", "fluid.cavitation", "is not a boolean")


@pytest.mark.parametrize("value", ["true", "false", "yes", "no"])
def test_cavitation_takes_a_yaml_boolean(tmp_path, value):
    load(variant(tmp_path, "\nparameters:\n", f"\nfluid: {{cavitation: {value}}}\nparameters:\n"))
