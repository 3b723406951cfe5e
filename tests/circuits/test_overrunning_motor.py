"""A motor overrun by its load draws its inlet line down; once that line is at the vapour pressure its
chambers fill with vapour and it passes no more oil than the line lets in, so its outlet's braking pressure
drains away (blocks/library/hydraulic/displacement.py, chamber_fill).
Found by a physics audit of the pumps (a pump kept delivering full flow from a closed suction net, a cavity
growing without end); the motors shared the flaw, and a crane's load braked on oil its line did not hold."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit
from blocks.library.hydraulic.cavitation import cavity_volume

OVERRUN = """
description: a flywheel at 1000 rpm drives a motor whose inlet a is shut in 0.1 l of oil at 0 bar; its
  outlet b drains to the tank through a laminar orifice G (a load braked meter-out with no make-up oil)
fluid: {rho: "850 kg/m^3", nu: "1.8e-5 m^2/s", beta: "8e8 Pa", vapour_pressure: "-0.9 bar"}
components:
  tank:  {type: tank}
  motor: {type: MOTOR}
  wheel: {type: inertia, params: {J: "0.5 kg*m^2"}}
  drain: {type: laminar_orifice, params: {G: "1e-10 m^3/(s*Pa)"}}
nets:
  A: {ports: [motor.a], volume: "0.1 l", initial: "0 bar"}
  B: {ports: [motor.b, drain.a], volume: "0.1 l", initial: "0 bar"}
  T: [tank.port, drain.b, DRAIN]
  shaft: {ports: [motor.shaft, wheel.port], initial: "1000 rpm"}
outputs: {pA: {of: A}, pB: {of: B}, w: {of: shaft}}
simulation: {t_end: "0.2 s", dt_out: "0.05 ms", rtol: 1e-9, atol: 1e-9}
"""
MOTORS = {  # the type line, the case drain's port, the motor's inertia [kg*m^2] and eta_hm
    "hydraulic_motor": ('hydraulic_motor, params: {D: "30 cm^3/rev", J_m: "0.002 kg*m^2"}', "", 0.002, 1.0),
    "parker_motor": ("parker_motor, preset: F12-030", "motor.drain", 1.7e-3, 0.9),
}


@pytest.mark.parametrize("motor", MOTORS)
def test_a_motor_brakes_only_on_the_oil_its_inlet_line_holds(tmp_path, motor):
    """The motor passes only the oil line a holds, so line b gets no more: its braking pressure drains away
    (time constant V/(beta*G) = 1.25 ms) and the wheel keeps over 99 % of its speed. (With a full D*w of
    oil through the motor, p_b = D*w/G = 50 bar and 24 N*m would stop it in about 2 s.) What still brakes
    it is the vacuum at the inlet: J*dw/dt = k*D*(p_a - p_b), k = 2 - eta_hm (the friction adding
    (1 - eta_hm) of it), the full torque on D though the chambers fill with vapour. And the oil is
    conserved: what left line a (its decompression and its vapour cavity) is what line b holds and its
    orifice let out, int G*p_b dt."""
    netlist = OVERRUN.replace("type: MOTOR}", f"type: {MOTORS[motor][0]}}}")
    netlist = netlist.replace(", DRAIN]", f", {MOTORS[motor][1]}]" if MOTORS[motor][1] else "]")
    (tmp_path / "overrun.yaml").write_text(netlist)
    r = Circuit.from_file(tmp_path / "overrun.yaml").simulate()
    beta, volume, g, p_vap = 8e8, 1e-4, 1e-10, -0.9e5
    displacement, inertia, eta_hm = 30e-6 / (2 * np.pi), 0.5 + MOTORS[motor][2], MOTORS[motor][3]
    w0 = 1000 * 2 * np.pi / 60
    assert 0.99 * w0 < r["w"][-1] < w0
    assert p_vap - 500.0 <= r["pA"][-1] <= p_vap
    late = r.t > 0.1  # line b drained
    slope = np.polyfit(r.t[late], r["w"][late], 1)[0]
    torque = (2 - eta_hm) * displacement * np.mean(r["pA"][late] - r["pB"][late])
    assert slope == pytest.approx(torque / inertia, rel=2e-3)
    drawn = volume * (0.0 - r["pA"][-1]) / beta + cavity_volume(r["pA"][-1], p_vap)
    drained = volume * (r["pB"][-1] - 0.0) / beta + np.trapezoid(g * r["pB"], r.t)
    if motor == "hydraulic_motor":
        assert drained == pytest.approx(drawn, rel=1e-2)
    else:  # the Parker motor's case drains let a little oil from the tank into line a too
        assert drained <= drawn * 1.01
    assert drawn < 1e-6  # under a cm^3: the line's own oil and the vapour band's, not D*w


def test_with_the_liquid_at_every_pressure_the_motor_brakes_on_as_in_the_thesis_model(tmp_path):
    """`fluid: {cavitation: false}` (the thesis's Simulink model) keeps the oil a liquid at every pressure,
    in the machines' chambers too (their p_vap is then fluid.cavitation_pressure = -1e30 Pa): the motor
    stretches line a into a tension and brakes on, which the run warns of."""
    netlist = OVERRUN.replace('vapour_pressure: "-0.9 bar"}', 'vapour_pressure: "-0.9 bar", cavitation: false}')
    netlist = netlist.replace("type: MOTOR}", f"type: {MOTORS['hydraulic_motor'][0]}}}").replace(", DRAIN]", "]")
    (tmp_path / "liquid.yaml").write_text(netlist)
    circuit = Circuit.from_file(tmp_path / "liquid.yaml")
    assert circuit.vectors().values["fluid.cavitation_pressure"] == -1e30
    r = circuit.simulate()
    assert r["pA"].min() < -100e5 and r["w"][-1] < 0.999 * 1000 * 2 * np.pi / 60
    assert any("cavitation: false" in w for w in r.warnings)


def test_the_derived_cavitation_pressure_is_not_set_on_its_own(tmp_path, capsys):
    """fluid.cavitation_pressure follows the vapour pressure and the cavitation switch: set alone it would
    part the machines' vapour pressure from the nets' (found by the diff review)."""
    import cli

    netlist = OVERRUN.replace("type: MOTOR}", f"type: {MOTORS['hydraulic_motor'][0]}}}").replace(", DRAIN]", "]")
    (tmp_path / "overrun.yaml").write_text(netlist)
    base = ["run", str(tmp_path / "overrun.yaml"), "-q", "-o", str(tmp_path / "r.csv"), "--set"]
    assert cli.main(base + ["fluid.cavitation_pressure=-2 bar"]) == 2
    assert "is derived from fluid.vapour_pressure" in capsys.readouterr().err
    assert cli.main(base + ["fluid.cavitation=false"]) == 2
    assert "a switch of the netlist's fluid: section" in capsys.readouterr().err
    assert not (tmp_path / "r.csv").exists()


def test_nor_is_it_an_optimiser_s_parameter(tmp_path):
    from blocks.errors import NetlistError
    from blocks.optimise.job import load_job

    netlist = Path(__file__).resolve().parents[2] / "netlists" / "opt" / "drive_line.yaml"
    (tmp_path / "job.yaml").write_text(
        f"netlist: {netlist}\nparameters:\n  fluid.cavitation_pressure: {{min: -1e5, max: 0}}\n"
        f"cost:\n  terms:\n    pos: {{kind: ise, signal: x, reference: x_ref, unit: mm}}\n"
        f"algorithm: {{method: complex, max_evaluations: 10}}\noutput: {tmp_path / 'out'}\n")
    with pytest.raises(NetlistError, match="'fluid.cavitation_pressure' is derived from fluid.vapour_pressure"):
        load_job(tmp_path / "job.yaml")
