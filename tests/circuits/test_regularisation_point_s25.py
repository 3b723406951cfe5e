"""The smoothing-band note of `vphs linearise` gives the slope the linear model takes at the point, and none
where the smoothed law is flat there (a review of session 25's note: a motor with no pressure across it was
said to be damped by its friction's smoothing, and a friction sliding at 2 rad/s in a 3 rad/s band was quoted
its slope through 0, 10 N*m*s/rad, where the model takes 10*sech(2)^2 = 0.707)."""

from __future__ import annotations

import math

import pytest

import cli

MOTOR = """
components:
  m: {type: hydraulic_motor, params: {D: "60 cm^3/rev", J_m: "0.01 kg*m^2", eta_hm: 0.9, w_w: "0.1 rad/s"}}
  j: {type: inertia, params: {J: "1 kg*m^2"}}
nets:
  A: {ports: [m.a], volume: "1 l", initial: "20 bar"}
  B: {ports: [m.b], volume: "1 l", initial: "20 bar"}
  s: [m.shaft, j.port]
outputs: {pA: {of: A, unit: bar}}
simulation: {t_end: "1 s"}
"""

SLIDING = """
components:
  fr: {type: rot_friction, params: {Tc: "10 N*m", w_w: "1 rad/s"}}
  j: {type: inertia, params: {J: "1 kg*m^2"}}
nets:
  s: {ports: [fr.port, j.port], initial: "2 rad/s"}
outputs: {w: {of: s, unit: rad/s}}
simulation: {t_end: "0.1 s"}
"""


def notes(tmp_path, capsys, text: str, *args) -> list[str]:
    netlist = tmp_path / "circuit.yaml"
    netlist.write_text(text)
    code = cli.main(["linearise", str(netlist), "-q", "--at", "0", *args])
    out, err = capsys.readouterr()
    assert code == 0, err
    return [line for line in out.splitlines() if "smoothing band" in line]


def test_a_motor_with_no_pressure_across_it_has_no_note(tmp_path, capsys):
    assert notes(tmp_path, capsys, MOTOR) == []


def test_a_motor_s_note_gives_the_slope_its_pressures_make(tmp_path, capsys):
    """(1 - eta_hm)*D*|p_a - p_b|/w_w = 0.1 * 60e-6/(2*pi) m^3/rad * 100e5 Pa / 0.1 rad/s = 95.5 N*m*s/rad."""
    found = notes(tmp_path, capsys, MOTOR, "--set", "A.initial=120 bar")
    slope = 0.1 * 60e-6 / (2 * math.pi) * 100e5 / 0.1
    assert len(found) == 1 and f"there its slope, {slope:.3g} N*m*s/rad ((1 - eta_hm)*D*|p_a - p_b|/w_w = " \
                               f"{slope:.3g} N*m*s/rad at w = 0)" in found[0], found


def test_a_note_away_from_zero_gives_the_slope_there(tmp_path, capsys):
    found = notes(tmp_path, capsys, SLIDING)
    here = 10.0 / math.cosh(2.0) ** 2
    assert len(found) == 1 and f"there its slope, {here:.3g} N*m*s/rad (Tc/w_w = 10 N*m*s/rad at w = 0)" \
        in found[0], found
    assert here == pytest.approx(0.7065, abs=1e-4)


def test_a_motor_with_a_rounding_s_pressure_across_it_has_no_note(tmp_path, capsys):
    """50 Pa across (a locked motor's two lines equal but for rounding) is under the millibar: no note; 1 bar
    across is over it."""
    assert notes(tmp_path, capsys, MOTOR, "--set", "A.initial=20.0005 bar") == []
    assert len(notes(tmp_path, capsys, MOTOR, "--set", "A.initial=21 bar")) == 1


def test_only_a_circuit_built_to_be_linearised_observes_the_regularised_signals():
    """A run or an optimiser's evaluation does not carry them at every sample (the drive line's motor: its
    speed and both port pressures would be 3 columns more than its 6 outputs)."""
    from pathlib import Path

    from blocks.circuit import Circuit

    netlist = Path(__file__).resolve().parents[2] / "netlists" / "examples" / "drive_line.yaml"
    plain = Circuit.from_file(netlist, compile=False)
    linear = Circuit.from_file(netlist, compile=False, regularised=True)
    assert plain.n_observed == len(plain.outputs) + sum(len(s.cls.checked) for s in plain.flat.components.values())
    assert linear.n_observed - plain.n_observed == 3
    assert {(m.comp, m.ref) for m in linear.monitors[len(plain.monitors):]} == {("motors", r) for r in ("shaft", "a", "b")}
