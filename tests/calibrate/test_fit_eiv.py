"""Weighted least squares with errors-in-variables on a circuit whose steady state is known in closed form:
a flow source Q through a laminar resistance into the tank, p = Q/G. The estimate and its standard error are
compared with the closed-form linear regression; the latent true inputs with their closed form."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.fit import fit
from blocks.calibrate.model import Model
from blocks.circuit import Circuit

G_TRUE = 2e-10  # m^3/(s*Pa): 10 bar at 12 l/min
NETLIST = {
    "parameters": {"Q_in": "10 l/min", "G": G_TRUE},
    "components": {"tank": {"type": "tank"}, "pump": {"type": "flow_source", "params": {"q": "Q_in"}},
                   "res": {"type": "laminar_orifice", "params": {"G": "G"}}},
    "nets": {"T": ["tank.port", "pump.a", "res.b"], "P": {"ports": ["pump.b", "res.a"], "volume": "0.1 l"}},
    "outputs": {"p": {"of": "P", "unit": "bar"}},
    "simulation": {"t_end": "0.1 s", "dt_out": "1 ms", "rtol": 1e-9, "atol": 1e-9},
}


def make(tmp_path, q_lpm, p_bar, sigma_q, sigma_p, free=True):
    (tmp_path / "res.yaml").write_text(yaml.safe_dump(NETLIST))
    rows = "\n".join(f"{q:.9f},{p:.9f}" for q, p in zip(q_lpm, p_bar))
    (tmp_path / "data.csv").write_text("Q [l/min],p [bar]\n" + rows + "\n")
    exp = {"netlist": "res.yaml", "data": "data.csv",
           "inputs": {"Q": {"parameter": "Q_in", "noise": f"{sigma_q} l/min"}},
           "outputs": {"p": {"signal": "p", "noise": f"{sigma_p} bar"}},
           "free": {"G": {"initial": 1.5e-10, "lower": 1e-12, "upper": 1e-8}} if free else {},
           "heldout": {"scheme": "kfold", "k": 3}}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(exp))
    e = load_experiment(tmp_path / "exp.yaml")
    data = load_data(e)
    return Model(Circuit.from_file(e.netlist), e, data, e.free)


def test_estimate_and_standard_error_match_linear_regression(tmp_path):
    rng = np.random.default_rng(11)
    q = np.linspace(2.0, 20.0, 12)  # l/min
    sigma_p = 0.1
    p = q / 60000 / G_TRUE / 1e5 + rng.normal(size=q.size) * sigma_p
    model = make(tmp_path, q, p, 1e-6, sigma_p)  # inputs (nearly) exact: ordinary regression through 0
    res = fit(model, model.initial(), np.ones(model.layout.size, dtype=bool))
    Q = q / 60000
    P = p * 1e5
    R_hat = float(np.sum(P * Q) / np.sum(Q * Q))  # p = R*Q, R = 1/G
    se_R = sigma_p * 1e5 / np.sqrt(np.sum(Q * Q))
    chi2 = float(np.sum(((P - R_hat * Q) / (sigma_p * 1e5)) ** 2))
    se_R *= np.sqrt(max(1.0, chi2 / (q.size - 1)))  # the documented inflation
    g = model.layout.index("G")
    assert res.x[g] == pytest.approx(1 / R_hat, rel=1e-6)
    assert res.se[g] == pytest.approx(se_R / R_hat ** 2, rel=0.02)
    assert res.chi2 == pytest.approx(chi2, rel=1e-4, abs=1e-6)
    assert res.unsettled == 0


def test_latent_inputs_take_the_errors_in_variables_closed_form(tmp_path):
    rng = np.random.default_rng(12)
    q_true = np.linspace(4.0, 16.0, 5)
    sigma_q, sigma_p = 0.5, 0.2  # l/min, bar
    R = 1 / G_TRUE
    q_m = q_true + rng.normal(size=5) * sigma_q
    p_m = q_true / 60000 * R / 1e5 + rng.normal(size=5) * sigma_p
    model = make(tmp_path, q_m, p_m, sigma_q, sigma_p, free=False)  # G known: only the latent inputs are fitted
    res = fit(model, model.initial(), np.ones(model.layout.size, dtype=bool))
    sq, sp = sigma_q / 60000, sigma_p * 1e5
    Qm, Pm = q_m / 60000, p_m * 1e5
    expected = (Qm / sq ** 2 + R * Pm / sp ** 2) / (1 / sq ** 2 + R * R / sp ** 2)
    assert np.allclose(res.x, expected, rtol=1e-6)
    # each point: 2 residuals, 1 latent; chi^2 = sum (p_m - R q_m)^2 / (sp^2 + R^2 sq^2) in closed form
    chi2 = float(np.sum((Pm - R * Qm) ** 2 / (sp ** 2 + R * R * sq ** 2)))
    assert res.chi2 == pytest.approx(chi2, rel=1e-5)


def test_a_fit_stopped_at_its_evaluation_limit_says_so(tmp_path):
    q = np.linspace(2.0, 20.0, 6)
    p = q / 60000 / G_TRUE / 1e5
    model = make(tmp_path, q, p, 1e-6, 0.1)
    x0 = model.initial()
    x0[model.layout.index("G")] = 1e-11  # far off: one evaluation cannot get there
    stopped = fit(model, x0, np.ones(model.layout.size, dtype=bool), max_nfev=1)
    assert not stopped.converged and stopped.nfev == 1
    done = fit(model, x0, np.ones(model.layout.size, dtype=bool))
    assert done.converged and done.x[model.layout.index("G")] == pytest.approx(G_TRUE, rel=1e-4)
