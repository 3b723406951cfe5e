"""Steady points by equilibrium (``steady.method: equilibrium``, the default): a point's outputs are the
circuit's equilibrium, found by Newton from the state its first settling run reached, and later evaluations
start Newton from that reference without a run. Checked against the closed form of a first-order fill
(p = Q/G exactly, where the run ends at Q/G (1 - exp(-t/tau))), on the relief rig (whose Dahl friction
state rests anywhere: no isolated equilibrium, so runs are kept) and on the MCV rig (where a soft spring
makes some equilibria unstable: those evaluations fall back to the run)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.model import Model
from blocks.circuit import Circuit
from tests.calibrate.test_settling_runs import G, NETLIST, Q_LPM, TAU

ROOT = Path(__file__).resolve().parents[2]


def fill_model(tmp_path, method: str) -> Model:
    """The fill circuit of test_settling_runs with a settling run of 6 tau."""
    netlist = dict(NETLIST, simulation=dict(NETLIST["simulation"], t_end=f"{6 * TAU} s"))
    (tmp_path / "fill.yaml").write_text(yaml.safe_dump(netlist))
    (tmp_path / "data.csv").write_text(f"Q [l/min],p [bar]\n{Q_LPM},100\n")
    spec = {"netlist": "fill.yaml", "data": "data.csv",
            "inputs": {"Q": {"parameter": "Q_in", "noise": "0.01 l/min"}},
            "outputs": {"p": {"signal": "p", "noise": "20 bar"}},  # settled at 6 tau: moved 0.58 bar
            "free": {"G_res": {"initial": G, "lower": 1e-13, "upper": 1e-9}},
            "steady": {"method": method}}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec))
    exp = load_experiment(tmp_path / "exp.yaml")
    return Model(Circuit.from_file(exp.netlist), exp, load_data(exp), exp.free)


def predicted_p(model: Model, x) -> float:
    return float(model.predictions(x)[model.row_channel == 1][0])


def test_the_equilibrium_is_the_closed_form_where_the_run_is_not(tmp_path):
    settle = fill_model(tmp_path, "settle")
    p_run = predicted_p(settle, settle.initial())
    p_end = Q_LPM / 60000 / G
    assert p_run == pytest.approx(p_end * (1 - np.exp(-6.0)), rel=1e-6)  # 0.25 bar short: settled by the rule

    model = fill_model(tmp_path, "equilibrium")
    x = model.initial()
    assert predicted_p(model, x) == pytest.approx(p_end, rel=1e-10)
    assert model.simulations == 1 and 0 in model.reference and model.unsettled == set()
    runs, solves = model.simulations, model.equilibria
    y = x.copy()
    y[model.layout.index("G_res")] = 0.7 * G
    y[model.layout.latent_index(0, 0)] *= 1.01
    assert predicted_p(model, y) == pytest.approx(1.01 * Q_LPM / 60000 / (0.7 * G), rel=1e-10)
    assert model.simulations == runs and model.equilibria == solves + 1 and model.fallbacks == 0


def test_a_run_far_from_its_equilibrium_is_lengthened_instead(tmp_path):
    model = fill_model(tmp_path, "equilibrium")
    spec = yaml.safe_load((tmp_path / "exp.yaml").read_text())
    spec["steady"] = {"method": "equilibrium", "t_end": f"{0.5 * TAU} s", "t_max": f"{0.5 * TAU} s"}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec))
    exp = load_experiment(tmp_path / "exp.yaml")
    model = Model(Circuit.from_file(exp.netlist), exp, load_data(exp), exp.free)
    # the run ends at 39 bar, 61 bar short of the root: more than sigma (20 bar) plus its last motion (6 bar),
    # so the root is not taken as the place the run is heading for; the point stays a run, unsettled
    p = predicted_p(model, model.initial())
    assert p == pytest.approx(Q_LPM / 60000 / G * (1 - np.exp(-0.5)), rel=1e-6)
    assert model.reference == {} and model.unsettled == {0}


def relief_model(method: str, netlist: Path | None = None) -> Model:
    exp = load_experiment(ROOT / "netlists" / "experiments" / "relief_rig_steady.yaml")
    exp.spec.steady.method = method
    return Model(Circuit.from_file(netlist or exp.netlist), exp, load_data(exp), exp.free)


def test_a_friction_state_that_acts_on_nothing_does_not_stop_the_equilibria():
    """The declared relief valve has no spool friction (p_fric = 0): its Dahl state z moves no other state
    and, at rest, rests anywhere, which made the Jacobian singular. It is held and marked; every point gets
    its equilibrium, within 1e-4 sigma of the settling run's end."""
    eq, settle = relief_model("equilibrium"), relief_model("settle")
    a = eq.predictions(eq.initial())
    b = settle.predictions(settle.initial())
    assert sorted(eq.reference) == list(range(eq.data.n)) and eq.fallbacks == 0
    assert np.max(np.abs(a - b) / eq.row_sigma) < 1e-4
    z = eq.circuit.structure.block_states["relief"]["z"].index
    over = dict(eq.exp.overrides)
    over.update(eq.exp.groups.get(eq.data.labels[0], {}))
    solved = eq.circuit.equilibrium(over, guess=eq.reference[0])
    assert solved.stable and list(np.nonzero(solved.sinks)[0]) == [z]


def test_a_friction_state_that_rests_anywhere_keeps_the_runs(tmp_path):
    """With spool friction (p_fric = 2 bar) the spool sticks anywhere in a band: a family of equilibria, no
    isolated one. Every point keeps its settling run, and the values are the settle method's."""
    netlist = ROOT / "netlists" / "experiments" / "circuits" / "relief_rig.yaml"
    doc = yaml.safe_load(netlist.read_text())
    doc["components"]["relief"]["params"]["p_fric"] = "2 bar"
    (tmp_path / "relief_friction.yaml").write_text(yaml.safe_dump(doc))
    points = [0, 10, 20]
    eq, settle = (relief_model(m, tmp_path / "relief_friction.yaml") for m in ("equilibrium", "settle"))
    a = eq.predictions(eq.initial(), points)
    b = settle.predictions(settle.initial(), points)
    assert eq.reference == {} and eq.equilibria >= len(points)
    assert np.array_equal(a[np.isfinite(a)], b[np.isfinite(b)])


@pytest.mark.skipif(not (ROOT.parent / "shared" / "data" / "mcv_vf250_multistep.csv").exists(),
                    reason="needs ../shared/data beside the repository")
def test_an_unstable_equilibrium_falls_back_to_the_run():
    exp = load_experiment(ROOT / "netlists" / "experiments" / "mcv_vf250_multistep.yaml")
    circuit = Circuit.from_file(exp.netlist)
    data = load_data(exp)
    model = Model(circuit, exp, data, exp.free)
    k = 14  # setting 3, 12.8 l/min
    x = model.initial()
    model.predictions(x, [k])
    assert k in model.reference and model.fallbacks == 0  # kp = 895 bar: a stable equilibrium
    soft = x.copy()
    soft[model.layout.index("mcv.kp1")] = 260e5  # a soft spring: this point's equilibrium is unstable
    p = model.predictions(soft, [k])
    assert model.fallbacks == 1
    settle_exp = load_experiment(ROOT / "netlists" / "experiments" / "mcv_vf250_multistep.yaml")
    settle_exp.spec.steady.method = "settle"
    settle = Model(circuit, settle_exp, data, exp.free)
    settle.run_end = dict(model.run_end)
    settle._length_fixed = {k}  # the same run length as the fallback's (its first evaluation decided it)
    q = settle.predictions(soft, [k])
    assert np.array_equal(p[np.isfinite(p)], q[np.isfinite(q)])
