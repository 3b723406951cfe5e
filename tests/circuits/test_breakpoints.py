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
@pytest.mark.parametrize("t_p, w, t_end", [(2.23, 0.005, 5.0), (20.3, 0.6, 60.0), (300.0, 3.0, 600.0)])
def test_a_flow_pulse_between_long_steps_is_integrated(solver, t_p, w, t_end):
    circuit = Circuit.from_file(NETLIST)
    settings = circuit.settings.with_(solver=solver, t_end=t_end, dt_out=min(0.001, w / 5))
    result = circuit.simulate({"t_p": t_p, "w": w}, settings=settings)
    p = result.values[:, result.names.index("pA")]
    expected = closed_form(result.t, t_p, w)
    assert expected.max() > 6e5  # 6.5 bar for the 5 ms pulse: the run at rest before it grows its steps
    assert np.max(np.abs(p - expected)) < 1e-3 * expected.max(), solver
