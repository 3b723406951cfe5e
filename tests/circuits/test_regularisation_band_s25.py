"""A linearisation inside a friction's smoothing band says so (blocks/regularisation.py). Found by a user
review: a held boom with Coulomb friction, linearised at standstill, showed two real modes, "overdamped",
whose damping was the tanh smoothing's slope Fc/v_w (3e5 N*s/m), not the machine's, and nothing said so.

The circuit: a load m on a cylinder's piston side, a closed volume holding it (p_A*A_A = m*g exactly, so the
initial state is at rest), and a trans_friction Fc, v_w on the rod. About v = 0 the linear model is
    dp_A/dt = -beta*A_A/V_A * v,    m*dv/dt = A_A*p_A - m*g - (Fc/v_w)*v
(the stroke an integrator): s^2 + (Fc/(v_w*m))*s + beta*A_A^2/(V_A*m) = 0, the smoothing's slope as a
damper. Fed at 6 l/min the piston slides at q/A_A = 0.1 m/s, 33 times the band (3*v_w), where the smoothed
law is the Coulomb one (slope Fc/v_w*sech(100)^2 = 0): no note.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import cli

M, G, A_A, BETA, FC, V_W = 1000.0, 9.81, 1e-3, 8e8, 300.0, 1e-3
V_A = 1e-3 + 1e-3 + A_A * 0.5  # the net's volume, the dead volume and the stroke's, at x = 0.5 m
HELD = f"""
description: a load held on a closed chamber, with Coulomb friction on the rod
fluid: {{rho: "850 kg/m^3", nu: "3e-5 m^2/s", beta: "{BETA} Pa", vapour_pressure: "-1 bar"}}
components:
  tank: {{type: tank}}
  feed: {{type: flow_source, params: {{q: "0 l/min"}}}}
  cyl:  {{type: cylinder, params: {{A_A: "{A_A} m^2", A_B: "5e-4 m^2", stroke: "1 m", V0_A: "1 l", V0_B: "1 l"}},
          initial: {{x: "0.5 m"}}}}
  load: {{type: mass, params: {{m: "{M} kg", g_x: "-{G} m/s^2"}}}}
  fric: {{type: trans_friction, params: {{Fc: "{FC} N", v_w: "{V_W} m/s"}}}}
nets:
  T: [tank.port, cyl.B, feed.a]
  A: {{ports: [cyl.A, feed.b], volume: "1 l", initial: "{M * G / A_A} Pa"}}
  rod: [cyl.rod, load.port, fric.port]
outputs:
  pA: {{of: A, unit: bar}}
  v: {{of: rod, unit: m/s}}
simulation: {{t_end: "1 s", solver: rodas, rtol: 1e-9, atol: 1e-9}}
"""


def linearise(tmp_path, capsys, *args) -> tuple[str, str, list[complex]]:
    """What is printed, the modes CSV (-o) and its eigenvalues (a pair once, its positive member)."""
    netlist, modes = tmp_path / "held.yaml", tmp_path / "modes.csv"
    netlist.write_text(HELD)
    code = cli.main(["linearise", str(netlist), "-q", "-o", str(modes), *args])
    out, err = capsys.readouterr()
    assert code == 0, err
    text = modes.read_text()
    rows = list(csv.reader(line for line in text.splitlines() if not line.startswith("#")))
    return out, text, [complex(float(r[1]), float(r[2])) for r in rows[1:]]


def test_at_rest_the_friction_s_smoothing_is_said_to_set_the_damping(tmp_path, capsys):
    out, modes, found = linearise(tmp_path, capsys, "--at", "0")
    note = ("fric: the point lies inside the Coulomb friction's smoothing band (|v| = 0 m/s < 3*v_w = 0.003 m/s): "
            "there its slope, 3e+05 N*s/m (Fc/v_w = 3e+05 N*s/m at v = 0), is the regularisation's, not physics: "
            "a mode that moves v takes it for a damper")
    assert f"# {note}" in out and "(a real Coulomb friction at rest sticks" in out
    assert f"# {note}" in modes  # the modes CSV says it too
    # the model's modes are those of the smoothing's damper: s^2 + c/m*s + k/m = 0, c = Fc/v_w
    c, k = FC / V_W, BETA * A_A ** 2 / V_A
    roots = np.roots([M, c, k])
    shown = [e.real for e in found if e != 0]
    assert shown == pytest.approx(sorted(roots, key=abs), rel=1e-3)


def test_without_the_friction_or_sliding_outside_the_band_nothing_is_said(tmp_path, capsys):
    out, modes, found = linearise(tmp_path, capsys, "--at", "0", "--set", "fric.Fc=0")
    assert "smoothing band" not in out + modes
    pair = next(e for e in found if e.imag > 0)
    assert pair.imag == pytest.approx(math.sqrt(BETA * A_A ** 2 / (V_A * M)), rel=1e-6)  # 2.85 Hz, undamped
    out, modes, _ = linearise(tmp_path, capsys, "--equilibrium", "--set", "feed.q=6 l/min")
    assert "the steady motion" in out and "v = 0.1 m/s" in out  # q/A_A, 33 times the band's 3 mm/s
    assert "smoothing band" not in out + modes
