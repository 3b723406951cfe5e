"""Steady points whose settling run is too short: at the point's first evaluation the run is lengthened
(doubled) until the point settles or ``steady.t_max`` is reached, and that length is then fixed for the
point (the residual stays a function of x alone). Checked on a first-order
circuit with a closed form: a flow source Q into a volume V drained by a laminar conductance G,
p(t) = Q/G (1 - exp(-t/tau)), tau = V/(beta G)."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

import cli
from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.model import Model
from blocks.circuit import Circuit

BETA, V, G = 1e9, 1e-3, 1e-11  # Pa, m^3, m^3/(s Pa)
TAU = V / (BETA * G)  # 0.1 s
Q_LPM = 6.0  # l/min: Q/G = 100 bar
P_END = Q_LPM / 60000 / G
NETLIST = {
    "fluid": {"rho": "850 kg/m^3", "nu": "3e-5 m^2/s", "beta": f"{BETA} Pa"},
    "parameters": {"Q_in": f"{Q_LPM} l/min", "G_res": G},
    "components": {"tank": {"type": "tank"}, "pump": {"type": "flow_source", "params": {"q": "Q_in"}},
                   "res": {"type": "laminar_orifice", "params": {"G": "G_res"}}},
    "nets": {"T": ["tank.port", "pump.a", "res.b"], "P": {"ports": ["pump.b", "res.a"], "volume": f"{V} m^3"}},
    "outputs": {"p": {"of": "P", "unit": "bar"}},
    "simulation": {"t_end": f"{0.5 * TAU} s", "dt_out": "1 ms", "rtol": 1e-9, "atol": 1e-9},
}


def experiment(tmp_path, steady: dict) -> Model:
    """The fill circuit's experiment; settling runs only unless ``steady`` names another method."""
    (tmp_path / "fill.yaml").write_text(yaml.safe_dump(NETLIST))
    (tmp_path / "data.csv").write_text(f"Q [l/min],p [bar]\n{Q_LPM},{P_END / 1e5}\n")
    spec = {"netlist": "fill.yaml", "data": "data.csv",
            "inputs": {"Q": {"parameter": "Q_in", "noise": "0.01 l/min"}},
            "outputs": {"p": {"signal": "p", "noise": "5 bar"}},  # settled: moved < 0.25 bar over the last 20 %
            "free": {"G_res": {"initial": G, "lower": 1e-13, "upper": 1e-9}},
            "steady": {"method": "settle", **steady}}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec))
    exp = load_experiment(tmp_path / "exp.yaml")
    return Model(Circuit.from_file(exp.netlist), exp, load_data(exp), exp.free)


def predicted_p(model: Model) -> float:
    return float(model.predictions(model.initial())[model.row_channel == 1][0])


def test_a_short_run_is_lengthened_until_the_point_settles(tmp_path):
    # 0.5 tau, 1, 2, 4 tau move by more than 0.25 bar over their last 20 %; 8 tau moves 0.13 bar
    model = experiment(tmp_path, {"t_max": f"{16 * 0.5 * TAU} s"})
    p = predicted_p(model)
    assert model.unsettled == set() and model.run_end == {0: pytest.approx(8 * TAU)}
    assert p == pytest.approx(P_END * (1 - np.exp(-8.0)), rel=1e-6)
    runs = model.simulations
    predicted_p(model)  # cached
    model.residuals(model.initial() * 1.001)  # new values: one run, at the fixed length
    assert model.simulations == runs + 1 and model.run_end == {0: pytest.approx(8 * TAU)}
    slow = model.initial()
    slow[model.layout.index("G_res")] = G / 4  # tau x 4: 8 tau is now 2 of its own: not settled, not lengthened
    p_slow = float(model.predictions(slow)[model.row_channel == 1][0])
    assert model.simulations == runs + 2 and model.run_end == {0: pytest.approx(8 * TAU)} and model.unsettled == {0}
    assert p_slow == pytest.approx(4 * P_END * (1 - np.exp(-2.0)), rel=1e-6)


def test_a_point_still_moving_at_t_max_is_reported_unsettled(tmp_path):
    model = experiment(tmp_path, {"t_max": f"{4 * TAU} s"})
    p = predicted_p(model)
    assert model.unsettled == {0} and model.run_end == {0: pytest.approx(4 * TAU)}
    assert p == pytest.approx(P_END * (1 - np.exp(-4.0)), rel=1e-6)
    model = experiment(tmp_path, {})  # default t_max = 8 x t_end = 4 tau
    predicted_p(model)
    assert model.unsettled == {0} and model.run_end == {0: pytest.approx(4 * TAU)}


def test_a_t_max_below_the_run_is_a_one_line_error(tmp_path, capsys):
    experiment(tmp_path, {})
    spec = yaml.safe_load((tmp_path / "exp.yaml").read_text())
    spec["steady"] = {"t_max": "10 ms"}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec))
    assert cli.main(["calibrate", str(tmp_path / "exp.yaml"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "steady.t_max = 0.01 s is shorter than the settling run" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("key, value, message", [
    ("t_max", "5 bar", "steady.t_max: wrong unit 'bar'"), ("t_max", "abc", "steady.t_max: 'abc' is not"),
    ("t_end", "-1 s", "steady.t_end must be positive")])
def test_bad_settling_times_are_located_one_line_errors(tmp_path, capsys, key, value, message):
    experiment(tmp_path, {})
    spec = yaml.safe_load((tmp_path / "exp.yaml").read_text())
    spec["steady"] = {key: value}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec))
    assert cli.main(["calibrate", str(tmp_path / "exp.yaml"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err and "exp.yaml" in err and "internal error" not in err
