"""A short input between long steps is not stepped over (Circuit.breakpoints, blocks/solve/rosenbrock.py).

tests/circuits/netlists/flow_pulse.yaml: a volume at rest, drained by a laminar leak, takes a flow pulse of
width w: p rises as (q/G)*(1 - exp(-s/tau)) over the pulse and decays as exp(-s/tau) after it,
tau = V/(beta*G). Every solver, in a short and a long run, against that closed form.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit

NETLIST = Path(__file__).parent / "netlists" / "flow_pulse.yaml"
BETA, V, G, Q = 8e8, 1e-3, 1e-11, 10.0 / 60000
TAU = V / (BETA * G)


def closed_form(t: np.ndarray, t_p: float, w: float) -> np.ndarray:
    """p [Pa]: 0 before the pulse, rising during it, decaying after it."""
    peak = Q / G * (1.0 - math.exp(-w / TAU))
    rising = Q / G * (1.0 - np.exp(-np.clip(t - t_p, 0.0, None) / TAU))
    decaying = peak * np.exp(-np.clip(t - t_p - w, 0.0, None) / TAU)
    return np.where(t < t_p + w, np.where(t < t_p, 0.0, rising), decaying)


@pytest.mark.parametrize("solver", ["rodas", "lsoda", "bdf", "radau"])
@pytest.mark.parametrize("t_p, w, t_end", [(2.23, 0.005, 5.0), (20.3, 0.6, 60.0), (300.0, 3.0, 600.0),
                                           (0.02, 0.005, 5.0), (4.97, 0.005, 5.0)])  # near the start, the end
def test_a_flow_pulse_between_long_steps_is_integrated(solver, t_p, w, t_end):
    circuit = Circuit.from_file(NETLIST)
    settings = circuit.settings.with_(solver=solver, t_end=t_end, dt_out=min(0.001, w / 5))
    result = circuit.simulate({"t_p": t_p, "w": w}, settings=settings)
    p = result.values[:, result.names.index("pA")]
    expected = closed_form(result.t, t_p, w)
    assert expected.max() > 6e5  # 6.5 bar for the 5 ms pulse: the run at rest before it grows its steps
    assert np.max(np.abs(p - expected)) < 1e-3 * expected.max(), solver


def test_two_stops_one_rounding_apart_leave_every_solver_a_span_it_can_step():
    # 0.1 + 0.2 s and 0.3 s: lsoda, restarted on the 5.6e-17 s between them, failed ("step size fell below
    # its minimum"); a pulse that short carries no oil
    circuit = Circuit.from_file(NETLIST)
    for solver in ("rodas", "lsoda", "bdf", "radau"):
        result = circuit.simulate({"t_p": 0.3, "w": (0.1 + 0.2) - 0.3}, settings=circuit.settings.with_(solver=solver))
        assert np.abs(result.values[:, result.names.index("pA")]).max() < 1.0, solver


def test_a_pulse_on_the_edges_of_the_runs_slices_costs_no_rejections():
    # a run is integrated in 10 slices (blocks/solve/run.py); a slice ending on a stop evaluates its last
    # stages just before it, as any step ending on a stop does (18 to 43 rejected steps before, 0 off the edges)
    circuit = Circuit.from_file(NETLIST)
    for t_p, w in ((2.0, 0.5), (2.5, 0.5), (2.0, 0.3)):
        result = circuit.simulate({"t_p": t_p, "w": w})
        p = result.values[:, result.names.index("pA")]
        expected = closed_form(result.t, t_p, w)
        assert np.max(np.abs(p - expected)) < 1e-4 * expected.max()
        assert result.stats["rejected"] <= 3, (t_p, w, result.stats)


def test_a_pulse_made_of_a_profiles_points_is_integrated():
    # a trapezoid of 0.1 ms edges from a profile: its points are kinks, not jumps; the response is the
    # convolution p(t) = (beta/V) * int q(s) exp(-(t - s)/tau) ds, evaluated by quadrature
    from scipy.integrate import quad

    t_p, w, edge = 2.23, 0.005, 1e-4
    times = [0.0, t_p, t_p + edge, t_p + w, t_p + w + edge]
    flows = [0.0, 0.0, Q, Q, 0.0]
    text = NETLIST.read_text()
    text = text.replace('  rise:  {type: step, params: {t_step: t_p, y0: 0, y1: q}}\n', "")
    text = text.replace('  fall:  {type: step, params: {t_step: "t_p + w", y0: 0, y1: q}}\n', "")
    text = text.replace("  flow:  {type: sum, params: {k1: 1, k2: -1}}",
                        f"  flow:  {{type: profile, params: {{times: {times}, values: {flows}}}}}")
    text = text.replace("  s_rise: [rise.y, flow.u1]\n", "").replace("  s_fall: [fall.y, flow.u2]\n", "")
    path = Path(__file__).parent / "netlists" / "flow_pulse.yaml"
    tmp = path.with_name("_flow_pulse_profile.yaml")
    try:
        tmp.write_text(text)
        circuit = Circuit.from_file(tmp)
    finally:
        tmp.unlink()

    def p_exact(t):
        q = lambda s: float(np.interp(s, times, flows))  # noqa: E731
        return BETA / V * quad(lambda s: q(s) * math.exp(-(t - s) / TAU), 0.0, t, points=[x for x in times if x < t],
                               limit=200)[0]

    for solver in ("rodas", "lsoda", "bdf", "radau"):
        result = circuit.simulate(settings=circuit.settings.with_(solver=solver))
        p = result.values[:, result.names.index("pA")]
        peak = p_exact(t_p + w + edge)
        assert peak > 6e5
        for t in (t_p + w, t_p + w + 0.1, 2.6, 4.0):
            k = int(round(t / 0.001))
            assert abs(p[k] - p_exact(result.t[k])) < 1e-4 * peak, (solver, t)
