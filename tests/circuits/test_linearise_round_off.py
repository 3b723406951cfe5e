"""What is zero in a linear model is said as 0, and what is small but real is kept (blocks/linearise.py).

tests/circuits/netlists/linear_symmetric.yaml: a servo of a symmetric cylinder at rest, each chamber at p_s/2
with no net force on the load, and beside it two equal second-order low-passes in series. By symmetry a
supply pressure change raises both chambers by half of it and moves nothing else; a load mass with no net
force on it moves nothing to first order. The cascade's response is (wn^2/(s^2 + 2*zeta*wn*s + wn^2))^2:
its steady gain 1, and 1e-12 at 10 kHz. Every expected value here is one of those closed forms.
"""

from __future__ import annotations

import csv
import math
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

import cli
from blocks.circuit import Circuit
from blocks.linearise import (GAIN_INTEGRATES, GAIN_UNCOUPLED, frequency_response, linearise, operating_point,
                              steady_gain)

NETLIST = Path(__file__).parent / "netlists" / "linear_symmetric.yaml"
WN, ZETA = 2 * math.pi * 10.0, 0.7
INPUTS = ["m_load", "p_s", "u0"]


@lru_cache(maxsize=None)
def model():
    circuit = Circuit.from_file(NETLIST)
    point = operating_point(circuit, {}, circuit.settings, None, equilibrium=True)
    return linearise(circuit, point, INPUTS)


def index(name: str) -> int:
    return model().output_names.index(name)


def test_a_mass_with_no_net_force_on_it_moves_nothing_to_first_order():
    # d(F/m)/dm = -F/m^2 = 0 at F = 0: the differences gave 4.6e-37 (m/s^2)/kg, and 2e-37 bar/kg followed
    m = model()
    assert not m.B[:, INPUTS.index("m_load")].any()
    gain, why = steady_gain(m)
    assert (gain[:, INPUTS.index("m_load")] == 0.0).all()
    assert (why[:, INPUTS.index("m_load")] == GAIN_UNCOUPLED).all()


def test_the_supply_raises_both_chambers_by_half_and_moves_nothing_else():
    gain, why = steady_gain(model())
    p_s = INPUTS.index("p_s")
    assert gain[index("pA"), p_s] == pytest.approx(0.5, rel=1e-6)
    assert gain[index("pB"), p_s] == pytest.approx(0.5, rel=1e-6)
    for name in ("v", "x", "spool"):
        assert gain[index(name), p_s] == 0.0 and why[index(name), p_s] == ""
    response = frequency_response(model(), np.logspace(-1, 3, 60))
    for name in ("v", "x", "spool"):
        assert not response[:, index(name), p_s].any(), name  # 1e-25 mm/Pa at a random phase before
    assert np.abs(response[:, index("pA"), p_s]).min() > 0.0


def test_two_equal_filters_in_series_keep_their_gain_and_their_steep_roll_off():
    # the modal sum over their nearly parallel eigenvectors gave 0.77 for the gain of 1
    gain, why = steady_gain(model())
    assert gain[index("y"), INPUTS.index("u0")] == pytest.approx(1.0, rel=1e-7)
    freqs = np.logspace(-1, 4, 41)
    s = 2j * math.pi * freqs
    expected = (WN**2 / (s**2 + 2 * ZETA * WN * s + WN**2)) ** 2
    assert abs(expected[-1]) < 2e-12
    response = frequency_response(model(), freqs)[:, index("y"), INPUTS.index("u0")]
    np.testing.assert_allclose(response, expected, rtol=1e-6)


def test_the_response_file_leaves_the_phase_of_a_zero_blank(tmp_path, capsys):
    out = tmp_path / "response.csv"
    code = cli.main(["linearise", str(NETLIST), "--equilibrium", "--input", "p_s", "--input", "m_load",
                     "--output", "pA", "--output", "x", "--response", str(out), "--plot", str(tmp_path / "b.png"),
                     "--points", "20"])
    _, err = capsys.readouterr()
    assert code == 0, err
    assert "--input m_load moves nothing" in err and "a mass with no net force on it" in err
    rows = list(csv.reader(out.read_text().splitlines()))
    header, body = rows[0], rows[1:]
    columns = {name: [row[k] for row in body] for k, name in enumerate(header)}
    assert set(columns["|x/p_s| [mm/Pa]"]) == {"0"} and set(columns["phase x/p_s [deg]"]) == {""}
    assert all(math.isfinite(float(v)) for v in columns["phase pA/p_s [deg]"])
    assert all(float(v) == pytest.approx(-90.0, abs=60.0) for v in columns["phase pA/p_s [deg]"])


def test_a_small_command_is_a_coupling_of_its_own_size():
    # the rounding is judged against the row's own terms, not a nominal size: at a command of 1e-9 the
    # filters' gain is still 1 (it was 0, "uncoupled", when the terms were taken at the states' nominals)
    circuit = Circuit.from_file(NETLIST)
    for u0 in (1e-9, 1e-12, 0.0):
        m = linearise(circuit, operating_point(circuit, {"u0": u0}, circuit.settings, None, equilibrium=True), ["u0"])
        y = m.output_names.index("y")
        gain, why = steady_gain(m)
        assert gain[y, 0] == pytest.approx(1.0, rel=1e-9) and why[y, 0] == ""
        s = 2j * math.pi
        expected = (WN**2 / (s**2 + 2 * ZETA * WN * s + WN**2)) ** 2
        assert frequency_response(m, np.array([1.0]))[0, y, 0] == pytest.approx(expected, rel=1e-6)


def _netlist(tmp_path, name: str, text: str) -> Circuit:
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    return Circuit.from_file(path)


def test_eight_filters_in_series_keep_their_roll_off_to_1e_32(tmp_path):
    # the response falls as (10 Hz/f)^16: accurate to full precision at every frequency; a floor relative to
    # the largest state's response cut it to 0 from 100 Hz
    n = 8
    components = "".join(f"  f{i}: {{type: lowpass2, params: {{wn: wn, zeta: 0.7}}}}\n" for i in range(n))
    nets = "".join(f"  s{i + 1}: [f{i}.y, f{i + 1}.u]\n" for i in range(n - 1))
    circuit = _netlist(tmp_path, "chain", f"""
parameters: {{u0: 1.0, wn: "{WN} rad/s"}}
components:
  u: {{type: constant, params: {{value: u0}}}}
{components}nets:
  s0: [u.y, f0.u]
{nets}  y: [f{n - 1}.y]
outputs: {{y: f{n - 1}.y}}
simulation: {{t_end: "1 s", dt_out: "10 ms"}}
""")
    m = linearise(circuit, operating_point(circuit, {}, circuit.settings, None, equilibrium=True), ["u0"])
    assert steady_gain(m)[0][0, 0] == pytest.approx(1.0, rel=1e-9)
    freqs = np.array([1.0, 30.0, 100.0, 300.0, 1000.0])
    s = 2j * math.pi * freqs
    expected = (WN**2 / (s**2 + 2 * ZETA * WN * s + WN**2)) ** n
    assert abs(expected[-1]) < 2e-32
    np.testing.assert_allclose(frequency_response(m, freqs)[:, 0, 0], expected, rtol=1e-6)


def test_two_integrators_of_one_input_subtracted_integrate_nothing(tmp_path):
    # modes at 0 are judged together (C P0 B): y = x1 - x2 has the gain 0, x1 integrates
    circuit = _netlist(tmp_path, "two_integrators", """
parameters: {u0: 1.0}
components:
  u:  {type: constant, params: {value: u0}}
  i1: {type: integrator}
  i2: {type: integrator}
  d:  {type: sum, params: {k1: 1, k2: -1}}
nets:
  s0: [u.y, i1.u, i2.u]
  s1: [i1.y, d.u1]
  s2: [i2.y, d.u2]
  s3: [d.y]
outputs: {y: d.y, x1: i1.y}
simulation: {t_end: "1 s", dt_out: "10 ms"}
""")
    m = linearise(circuit, operating_point(circuit, {}, circuit.settings, 0.0), ["u0"], ["y", "x1"])
    gain, why = steady_gain(m)
    assert gain[0, 0] == 0.0 and why[0, 0] == ""
    assert math.isnan(gain[1, 0]) and why[1, 0] == GAIN_INTEGRATES
    response = frequency_response(m, np.array([0.01, 1.0]))
    assert not response[:, 0, 0].any()
    np.testing.assert_allclose(response[:, 1, 0], 1.0 / (2j * math.pi * np.array([0.01, 1.0])), rtol=1e-9)


def test_an_output_the_input_does_not_reach_reads_0_at_every_frequency():
    # x_ref integrates the reference profile alone; its response to the pinion's radius was the solve's
    # rounding, 5e-12 mm/m at random phases at 28 of 300 frequencies
    circuit = Circuit.from_file(Path(__file__).parents[2] / "netlists" / "examples" / "drive_line.yaml")
    point = operating_point(circuit, {}, circuit.settings)
    m = linearise(circuit, point, ["r_pinion", "V_line"], ["x_ref", "x"])
    response = frequency_response(m, np.logspace(-2, 5, 300))
    assert not response[:, 0, :].any()
    assert np.abs(response[:, 1, :]).min() > 0.0


def test_a_rest_point_at_zero_pressure_has_no_gains_of_1e_37():
    # every pressure of the MCV demo at rest is about 1e-37 bar: the terms of a row are then those at the
    # differences' steps, and an outlet area's gain on pV1 of 1e-37 bar/m^2 is their rounding
    circuit = Circuit.from_file(Path(__file__).parents[2] / "netlists" / "components" / "mcv_demo_with.yaml")
    m = linearise(circuit, operating_point(circuit, {}, circuit.settings, None, equilibrium=True), ["A_out"])
    gain, why = steady_gain(m)
    assert gain[m.output_names.index("pV1"), 0] == 0.0
