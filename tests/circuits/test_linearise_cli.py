"""`vphs linearise`: what it prints and writes (in the units asked for), and its refusals, one line each."""

from __future__ import annotations

import csv
import re
import math
from pathlib import Path

import numpy as np
import pytest

import cli

NETLISTS = Path(__file__).parent / "netlists"
MODES = NETLISTS / "linear_modes.yaml"
BETA, V, G = 8e8, 2e-3, 2e-11


def run(capsys, *args) -> tuple[int, str, str]:
    code = cli.main(["linearise", *map(str, args)])
    out, err = capsys.readouterr()
    return code, out, err


def read_csv(path: Path) -> tuple[list[str], np.ndarray]:
    rows = [r for r in csv.reader(line for line in path.read_text().splitlines() if not line.startswith("#"))]
    return rows[0], rows[1:]


def test_modes_table_and_files_in_the_units_asked_for(tmp_path, capsys):
    files = {"-o": tmp_path / "modes.csv", "--state-space": tmp_path / "ss.csv",
             "--response": tmp_path / "response.csv", "--plot": tmp_path / "bode.png"}
    args = [MODES, "--at", "0 s", "--input", "qcmd.value [l/min]", "--output", "p", "--output", "qi", "-q",
            "--f-min", "0.01", "--f-max", "100 Hz", "--points", "50"]
    for option, path in files.items():
        args += [option, path]
    code, out, err = run(capsys, *args)
    assert code == 0, err
    assert "linearised about the initial state (t = 0 s)" in out
    assert "steady-state gain p/qcmd.value: 8.33333 bar/(l/min)" in out  # 1/G: 5e10 Pa/(m^3/s)
    assert "steady-state gain qi/qcmd.value: none (it integrates the input)" in out
    header, rows = read_csv(files["--response"])
    assert header[:3] == ["f [Hz]", "|p/qcmd.value| [bar/(l/min)]", "phase p/qcmd.value [deg]"]
    f = np.array([float(r[0]) for r in rows])
    assert f[0] == pytest.approx(0.01) and f[-1] == pytest.approx(100.0) and len(f) == 50
    exact = 1.0 / (G + 2j * math.pi * f * V / BETA) / 60000 / 1e5  # bar per l/min
    np.testing.assert_allclose([float(r[1]) for r in rows], np.abs(exact), rtol=1e-7)
    np.testing.assert_allclose([float(r[2]) for r in rows], np.degrees(np.angle(exact)), atol=1e-5)
    header, rows = read_csv(files["-o"])
    assert header == ["mode", "real [1/s]", "imag [1/s]", "f_n [Hz]", "zeta [1]", "tau [s]", "states"]
    assert any(float(r[1]) == pytest.approx(-BETA * G / V, rel=1e-7) and r[6].startswith("P.p") for r in rows)
    header, rows = read_csv(files["--state-space"])
    assert header[0] == "row" and header[-1] == "qcmd.value [SI]"
    row = next(r for r in rows if r[0] == "d(P.p)/dt [Pa/s]")
    assert float(row[header.index("P.p [Pa]")]) == pytest.approx(-BETA * G / V, rel=1e-7)
    assert float(row[-1]) == pytest.approx(BETA / V, rel=1e-7)
    assert files["--plot"].stat().st_size > 10000


@pytest.mark.parametrize("args, message", [
    (["--input", "qcmd.valu"], "--input 'qcmd.valu': unknown parameter 'qcmd.valu' (did you mean qcmd.value"),
    (["--input", "m [bar]"], "--input 'm [bar]': m is in kg, not in a unit like bar"),
    (["--input", "m [furlong]"], "--input 'm [furlong]': unknown unit 'furlong'"),
    (["--input", "m", "--input", "m"], "'m' is named twice"),
    (["--output", "pp"], "--output 'pp': not a logged signal"),
    (["--plot", "{tmp}/b.png"], "--response and --plot show the response to an input: name one with --input"),
    (["--input", "m", "--f-min", "10", "--f-max", "1"], "need 0 < f-min < f-max"),
    (["--input", "m", "--f-min", "2 bar"], "--f-min '2 bar'"),
    (["--at", "-1 s"], "--at '-1 s': before the simulation's start, t_start = 0 s in"),
    (["--output", "p", "--output", "pA", "--output", "p"], "--output 'p': named twice"),
    (["--at", "2 bar"], "--at '2 bar'"),
    (["--at", "nan"], "--at 'nan': not a finite time"),
    (["--at", "inf"], "--at 'inf': not a finite time"),
    (["--at", "1e9"], "--at '1e9': gives more than"),
    (["--input", "m", "--f-max", "inf"], "need 0 < f-min < f-max, both finite"),
    (["-o", "{tmp}/m.csv", "--state-space", "{tmp}/m.csv"], "-o and --state-space name one file"),
    (["-o", str(MODES)], "is an input of this command"),
    (["--set", "V=-1 l"], "must be positive"),
    (["--at", "0", "--set", "m=0"], "the value or the rate of rod.v is not finite: nothing to linearise"),
    (["--equilibrium"], "no equilibrium found"),
    (["--input", "m", "--points", "1000000000"], "--points 1000000000: need 2 to 100000"),
    (["--response", ""], "--response '': name a file"),
    (["--state-space", "{tmp}/folder/"], "name a file"),
])
def test_refusals_are_one_line_and_write_nothing(tmp_path, capsys, args, message):
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    code, out, err = run(capsys, MODES, "-q", *args)
    assert code in (1, 2)
    assert message in err, err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_an_array_parameter_is_not_an_input(tmp_path, capsys):
    code, _, err = run(capsys, NETLISTS / "second_order_step.yaml", "-q", "--input", "tf.num")
    assert code == 2 and "'tf.num' is an array (a table); name a single value" in err


def test_what_is_said_of_the_operating_point(capsys):
    rest = NETLISTS / "linear_rest.yaml"
    code, out, err = run(capsys, rest, "-q", "--equilibrium")
    assert code == 0, err
    assert "# in steady motion: acc.x keeps integrating" in out and "not at rest" not in out
    assert "# there: p = 50 bar," in out  # q/G = 1e-4 m^3/s / 2e-11 m^3/(s*Pa)
    code, out, err = run(capsys, rest, "-q", "--at", "50 ms")
    assert code == 0, err
    q, tau = 1e-4, V / (BETA * G)
    p = q / G + (1e5 - q / G) * math.exp(-0.05 / tau)
    rate = BETA / V * (q - G * p) / 1e5  # bar/s
    assert f"# not at rest: P.p changes at {rate:.3g} bar/s" in out


UNSTABLE = """
description: dx/dt = 2*x, a state that doubles in ln(2)/2 = 0.347 s; its equilibrium is x = 0
components:
  grow: {type: integrator, initial: {x: 1e-6}}
  back: {type: gain, params: {k: 2}}
nets:
  x: [grow.y, back.u]
  u: [back.y, grow.u]
outputs: {x: {of: grow.y}}
simulation: {t_end: "0.1 s"}
"""


def test_an_unstable_point_is_said_to_be_one(tmp_path, capsys):
    """Found by a user review: about an unstable equilibrium the gains were printed as if it held."""
    (tmp_path / "grow.yaml").write_text(UNSTABLE)
    code, out, err = run(capsys, tmp_path / "grow.yaml", "-q", "--equilibrium", "--input", "back.k")
    assert code == 0, err
    assert "# UNSTABLE: 1 mode grows (fastest: lambda = 2, doubling in 0.347 s): the circuit leaves this " \
           "point" in out
    code, out, err = run(capsys, NETLISTS / "linear_rest.yaml", "-q", "--equilibrium")
    assert code == 0 and "UNSTABLE" not in out


def test_a_cylinder_in_steady_motion_is_linearised_about_that_motion(capsys):
    """Found by a user review: a cylinder's stroke sets its chambers' volumes, so it is no state that "acts
    on nothing", and --equilibrium found no rest point. The steady motion (blocks/steady_motion.py) holds
    the stroke and solves the rest: v = Q/A_A, p_B = A_B*Q/(A_A*G), p_A = (b*v + p_B*A_B)/A_A, and their
    gains per l/min; the stroke integrates Q."""
    code, out, err = run(capsys, NETLISTS / "linear_motion.yaml", "-q", "--equilibrium", "--input", "Q [l/min]")
    assert code == 0, err
    assert "the steady motion with the inputs held at their values at t = 1 s (cyl.x moving" in out
    a_a, a_b, g, b, per = 20e-4, 10e-4, 2e-10, 2000.0, 1e-3 / 60  # per: one l/min in m^3/s
    gains = {name: float(value) for name, value in
             re.findall(r"steady-state gain (\w+)/Q: ([-0-9.e+]+) ", out)}
    printed = 5e-6  # the gains are printed to 6 significant digits
    assert gains["v"] == pytest.approx(per / a_a * 1e3, rel=printed)                          # mm/s per l/min
    assert gains["pB"] == pytest.approx(a_b * per / (a_a * g) / 1e5, rel=printed)             # bar per l/min
    assert gains["pA"] == pytest.approx((b * per / a_a + a_b * a_b * per / (a_a * g)) / a_a / 1e5, rel=printed)
    assert "steady-state gain x/Q: none (it integrates the input)" in out
    q = 10 * per
    assert f"v = {q / a_a * 1e3:.6g} mm/s" in out and f"pB = {a_b * q / (a_a * g) / 1e5:.6g} bar" in out


def test_a_servo_tracking_a_ramp_is_a_steady_motion_once_its_error_has_settled(capsys):
    """The drive line cruising: the reference and the bridge both move (held), the rest is solved for rest.
    At 2 s the error has settled (the two positions' pulls on the spool cancel to 3e-5), at 0.6 s it is
    still settling (to 0.07): that point is said to be a snapshot."""
    drive = Path(__file__).resolve().parents[2] / "netlists" / "examples" / "drive_line.yaml"
    code, out, err = run(capsys, drive, "-q", "--equilibrium", "--at", "2")
    assert code == 0, err
    assert "(x_ref.x, angle.theta moving, held at their values there" in out and "snapshot" not in out
    code, out, err = run(capsys, drive, "-q", "--equilibrium", "--at", "0.6")
    assert code == 0, err
    assert "# a snapshot: as x_ref.x, angle.theta move, the others' rest changes" in out


SHUT_IN_MOVING = """
description: a cylinder with oil shut in both chambers, set moving at 0.1 m/s; it rings and comes to rest
fluid: {rho: "850 kg/m^3", beta: "1.4e9 Pa"}
components:
  cyl:   {type: cylinder, params: {A_A: "20 cm^2", A_B: "10 cm^2", stroke: "2 m", V0_A: "0.2 l", V0_B: "0.2 l"},
          initial: {x: "0.2 m"}}
  load:  {type: mass, params: {m: "200 kg"}}
  damp:  {type: trans_damper, params: {b: "2000 N*s/m"}}
nets:
  A: {ports: [cyl.A], volume: "0.3 l", initial: "10 bar"}
  B: {ports: [cyl.B], volume: "0.3 l", initial: "20 bar"}
  rod: {ports: [cyl.rod, load.port, damp.port], initial: "0.1 m/s"}
outputs: {pA: {of: A, unit: bar}, v: {of: rod, unit: mm/s}}
simulation: {t_end: "0.05 s", dt_out: "1 ms"}
"""


def test_a_rest_point_newton_cannot_isolate_is_not_called_a_steady_motion(tmp_path, capsys):
    """Found by the diff review: oil shut in both chambers has rest points at any pressure level, and the
    steady-motion search returned one (v = 4e-29 mm/s, 12837 bar) as 'the steady motion'."""
    (tmp_path / "shut.yaml").write_text(SHUT_IN_MOVING)
    code, out, err = run(capsys, tmp_path / "shut.yaml", "-q", "--equilibrium")
    assert code == 1 and "no equilibrium found" in err and "the Jacobian is singular there" in err
    assert "steady motion" not in out
