"""A growing mode that doubles over far more than the netlist's run is said as a slow growth, not as
UNSTABLE (cli.SLOW_GROWTH). Found by a user review: a boom held on its counterbalance valve, creeping
through the valve's leak, was headlined "# UNSTABLE: 1 mode grows (... doubling in 2.48e+04 s)", 4000 times
its 6 s run. The mode was the stroke's integrator turned positive by the linear model's terms that carry the
point's own rates: a chamber whose pressure falls at dp/dt while the stroke sets its volume V has
d(dp/dt)/dx = -(dV/dx)/V * dp/dt, 0 at rest.

dx/dt = a*x (an integrator fed back through a gain a) has its equilibrium at 0 and doubles in ln(2)/a: over
a run of 0.1 s, a = 2 (3.5 runs) and a = ln(2)/(50*0.1) (50 runs) are unstable within a time that matters, a
= ln(2)/(200*0.1) (200 runs) and 1e-4 (69000 runs) grow slowly.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import cli
from blocks.circuit import Circuit
from blocks.linearise import linearise, modes, operating_point

RUN = 0.1


def grow(a: float) -> str:
    return f"""
description: dx/dt = a*x, doubling in ln(2)/a; its equilibrium is x = 0
components:
  grow: {{type: integrator, initial: {{x: 1e-6}}}}
  back: {{type: gain, params: {{k: {a!r}}}}}
nets:
  x: [grow.y, back.u]
  u: [back.y, grow.u]
outputs: {{x: {{of: grow.y}}}}
simulation: {{t_end: "{RUN} s"}}
"""


def run(capsys, netlist, *args) -> tuple[str, str]:
    modes_file = netlist.parent / "modes.csv"
    code = cli.main(["linearise", str(netlist), "-q", "-o", str(modes_file), *args])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out, modes_file.read_text()


@pytest.mark.parametrize("runs", [3.5, 50.0])
def test_growth_within_a_hundred_runs_is_unstable(tmp_path, capsys, runs):
    a = math.log(2) / (runs * RUN)
    (tmp_path / "grow.yaml").write_text(grow(a))
    out, table = run(capsys, tmp_path / "grow.yaml", "--equilibrium")
    line = f"# UNSTABLE: 1 mode grows (fastest: lambda = {a:.4g}, doubling in {runs * RUN:.3g} s): the circuit leaves"
    assert line in out and line in table  # the modes CSV says what the console said
    assert "SLOW GROWTH" not in out


@pytest.mark.parametrize("runs", [200.0, math.log(2) / (1e-4 * RUN)])
def test_growth_over_more_than_a_hundred_runs_is_slow(tmp_path, capsys, runs):
    a = math.log(2) / (runs * RUN)
    (tmp_path / "grow.yaml").write_text(grow(a))
    out, table = run(capsys, tmp_path / "grow.yaml", "--equilibrium")
    line = (f"# SLOW GROWTH: 1 mode grows, mainly in grow.x (fastest: lambda = {a:.4g}, doubling in "
            f"{runs * RUN:.3g} s, {runs:.2g} x the netlist's run of {RUN:g} s): the point is unstable, but the "
            f"circuit leaves it far more slowly than the run lasts")
    assert line in out and line in table
    assert "UNSTABLE" not in out + table


LEAKING = """
description: >
  A load held on a cylinder's piston side, whose oil leaks through a laminar orifice into a closed line
  (a counterbalance valve's leak into the line to a closed directional valve), its rod side closed too: the
  load creeps down, both chambers' pressures fall as the line's rises.
fluid: {rho: "850 kg/m^3", nu: "3e-5 m^2/s", beta: "8e8 Pa", vapour_pressure: "-1 bar"}
components:
  cyl:  {type: cylinder, params: {A_A: "1e-3 m^2", A_B: "5e-4 m^2", stroke: "1 m", V0_A: "0.1 l", V0_B: "0.1 l"},
         initial: {x: "0.2 m"}}
  load: {type: mass, params: {m: "1000 kg", g_x: "-9.81 m/s^2"}}
  fric: {type: trans_damper, params: {b: "5e4 N*s/m"}}
  leak: {type: laminar_orifice, params: {G: "2e-14 m^3/(s*Pa)"}}
nets:
  B: {ports: [cyl.B], volume: "0.3 l", initial: "20 bar"}
  C: {ports: [cyl.A, leak.a], volume: "0.05 l", initial: "108.1 bar"}
  L: {ports: [leak.b], volume: "0.3 l", initial: "0 bar"}
  rod: [cyl.rod, load.port, fric.port]
outputs:
  pC: {of: C, unit: bar}
  x: {of: cyl.position, unit: mm}
simulation: {t_end: "6 s", solver: rodas, rtol: 1e-9, atol: 1e-12}
"""


def test_a_load_creeping_through_a_leak_is_a_slow_drift_not_an_instability(tmp_path, capsys):
    netlist = tmp_path / "leaking.yaml"
    netlist.write_text(LEAKING)
    out, table = run(capsys, netlist, "--at", "2 s")
    assert "UNSTABLE" not in out + table, out
    assert "# SLOW GROWTH: 1 mode grows, mainly in cyl.x" in out and "x the netlist's run of 6 s): about a point " \
        "not at rest this is likely the drift of the motion under way" in out
    assert "# not at rest:" in out and "# SLOW GROWTH" in table
    # what the mode is: the stroke's column of A is the chambers' volume terms, -(dV/dx)/V * dp/dt, only
    circuit = Circuit.from_file(netlist)
    point = operating_point(circuit, {}, circuit.settings, 2.0)
    model = linearise(circuit, point)
    names = model.state_names
    x, c, b = names.index("cyl.x"), names.index("C.p"), names.index("B.p")
    assert point.rates[c] < 0 and point.rates[b] < 0 and point.rates[x] < 0  # creeping down, both falling
    v_c, v_b = 0.05e-3 + 0.1e-3 + 1e-3 * point.x[x], 0.3e-3 + 0.1e-3 + 5e-4 * (1.0 - point.x[x])
    assert model.A[c, x] == pytest.approx(-1e-3 / v_c * point.rates[c], rel=1e-5)
    assert model.A[b, x] == pytest.approx(5e-4 / v_b * point.rates[b], rel=1e-5)
    assert np.count_nonzero(model.A[:, x]) == 2
    growing = max(modes(model), key=lambda m: m.eigenvalue.real)
    assert growing.eigenvalue.real > 0 and growing.participation[0][0] == "cyl.x"
    model.A[:, x] = 0.0  # without them the stroke is the integrator it is at rest
    assert max(m.eigenvalue.real for m in modes(model)) <= 0.0
