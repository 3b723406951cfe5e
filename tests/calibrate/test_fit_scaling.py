"""The least-squares fit with parameters whose SI sizes differ by many orders of magnitude: a start next to
a bound is where the fit starts, and a fit reported converged is at the minimum (blocks/calibrate/fit.py).

The circuit: a pressure source p through a flow meter of laminar resistance R and a laminar conductance G
into the tank, the flow measured: q = c*p with c = G/(1 + R*G). With p imposed as a noisy reading (a latent
input of about 1e7 Pa) and G of about 1e-12 m^3/(s*Pa) the two differ by 19 orders of magnitude. Its
errors-in-variables chi^2 has the closed form

    chi^2 = sum (q_m - c*p_m)^2 / (sigma_q^2 + c^2*sigma_p^2)

(each point's latent pressure eliminated), minimised here over c by a bounded scalar search, and
G = c/(1 - R*c)."""

from __future__ import annotations

import numpy as np
import pytest
import yaml
from scipy.optimize import minimize_scalar

from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.fit import fit
from blocks.calibrate.model import Model
from blocks.circuit import Circuit

NETLIST = {
    "parameters": {"p_in": "100 bar", "G": 2e-12, "R_meter": 1e6},
    "components": {"tank": {"type": "tank"}, "source": {"type": "pressure_source", "params": {"p": "p_in"}},
                   "meter": {"type": "flow_sensor", "params": {"R": "R_meter"}},
                   "res": {"type": "laminar_orifice", "params": {"G": "G"}}},
    "nets": {"T": ["tank.port", "res.b"], "P": ["source.port", "meter.a"],
             "M": {"ports": ["meter.b", "res.a"], "volume": "0.01 l"}},
    "outputs": {"q": {"of": "meter.q", "unit": "l/min"}},
    "simulation": {"t_end": "0.5 s", "dt_out": "5 ms", "rtol": 1e-10, "atol": 1e-12},
}


def model_of(tmp_path, p_bar, q_lpm, sigma_p, sigma_q, free_g: dict, r_meter: float = 1e6) -> Model:
    netlist = dict(NETLIST, parameters=dict(NETLIST["parameters"], R_meter=r_meter))
    (tmp_path / "rig.yaml").write_text(yaml.safe_dump(netlist))
    rows = "\n".join(f"{p:.9f},{q:.9f}" for p, q in zip(p_bar, q_lpm))
    (tmp_path / "data.csv").write_text("p [bar],q [l/min]\n" + rows + "\n")
    exp = {"netlist": "rig.yaml", "data": "data.csv",
           "inputs": {"p": {"parameter": "p_in", "noise": f"{sigma_p} bar"}},
           "outputs": {"q": {"signal": "q", "noise": f"{sigma_q} l/min"}},
           "free": {"G": free_g}, "heldout": {"scheme": "kfold", "k": 3}}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(exp))
    e = load_experiment(tmp_path / "exp.yaml")
    return Model(Circuit.from_file(e.netlist), e, load_data(e), e.free)


def readings(g_true: float, sigma_p: float, sigma_q: float, seed: int, r_meter: float = 1e6):
    rng = np.random.default_rng(seed)
    p_true = np.linspace(50.0, 250.0, 9)  # bar
    q_true = g_true / (1 + r_meter * g_true) * p_true * 1e5 * 60000  # l/min
    return p_true + rng.normal(size=9) * sigma_p, q_true + rng.normal(size=9) * sigma_q


def closed_form(p_bar, q_lpm, sigma_p, sigma_q, r_meter: float = 1e6) -> tuple[float, float]:
    """(G, chi^2) of the errors-in-variables minimum, SI."""
    P, Q, sp, sq = p_bar * 1e5, q_lpm / 60000, sigma_p * 1e5, sigma_q / 60000

    def chi2(c):
        return float(np.sum((Q - c * P) ** 2 / (sq ** 2 + c ** 2 * sp ** 2)))

    c0 = float(np.sum(P * Q) / np.sum(P * P))
    best = minimize_scalar(chi2, bounds=(0.5 * c0, 2.0 * c0), method="bounded", options={"xatol": 1e-12 * c0})
    return float(best.x / (1 - r_meter * best.x)), chi2(best.x)


def evaluated_at(model: Model) -> list:
    """Wrap the model's residuals so that every x it is evaluated at is kept, in order."""
    seen, residuals = [], model.residuals

    def recorded(x, points=None):
        seen.append(np.array(x, dtype=float))
        return residuals(x, points)

    model.residuals = recorded
    return seen


def test_a_start_next_to_a_bound_is_where_the_fit_starts(tmp_path):
    """G = 2e-12 with its lower bound at 0: scipy's trust-region method moves a start closer than 1e-10 to a
    bound (absolutely, in the units it is given) to 1e-10 from it, 50 times G, unless it sees G in G's own
    size. The first evaluation must be the start, and the fit must end at the closed-form minimum."""
    sigma_p, sigma_q = 0.5, 0.02
    p, q = readings(2e-12, sigma_p, sigma_q, seed=3)
    g_hat, chi2 = closed_form(p, q, sigma_p, sigma_q)
    model = model_of(tmp_path, p, q, sigma_p, sigma_q, {"initial": 1.9e-12, "lower": 0.0, "upper": 1e-3})
    seen = evaluated_at(model)
    x0 = model.initial()
    res = fit(model, x0, np.ones(model.layout.size, dtype=bool))
    g = model.layout.index("G")
    assert seen[0][g] == pytest.approx(x0[g], rel=1e-9)
    assert res.converged
    assert res.x[g] == pytest.approx(g_hat, rel=1e-5)
    assert res.chi2 == pytest.approx(chi2, rel=1e-5)


def test_a_fit_reported_converged_is_at_the_minimum(tmp_path):
    """The latent pressures (1e7 Pa) dominate the norm of x; a step tolerance taken relative to that norm
    counts a step that still moves G by a large part of itself as negligible. With the meter's resistance
    of the order of 1/G, q is nonlinear in G and Gauss-Newton takes several steps from 0.3 x the minimum,
    while the nearly exact pressure readings leave the latent pressures all but still: the fit must end at
    the minimum or say it has not converged."""
    sigma_p, sigma_q, r_meter = 1e-4, 0.02, 2.5e11
    p, q = readings(2e-12, sigma_p, sigma_q, seed=4, r_meter=r_meter)
    g_hat, chi2 = closed_form(p, q, sigma_p, sigma_q, r_meter)
    model = model_of(tmp_path, p, q, sigma_p, sigma_q, {"initial": 0.3 * g_hat, "lower": 1e-14, "upper": 1e-9},
                     r_meter)
    res = fit(model, model.initial(), np.ones(model.layout.size, dtype=bool), max_nfev=60)
    assert res.converged
    assert res.x[model.layout.index("G")] == pytest.approx(g_hat, rel=1e-5)
    assert res.chi2 == pytest.approx(chi2, rel=1e-5)
