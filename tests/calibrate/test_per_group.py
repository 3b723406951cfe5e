"""A declared parameter fitted per group (``free: {name: {..., per: group}}``): one value per group of steady
points, or per run of a time series, ``<name>[<group>]`` (blocks.calibrate.run.per_group_globals).

Time series: the drive line (netlists/experiments/circuits/drive_line_open.yaml) with a Coulomb friction of
3 N*m on the shaft, recorded twice from mid-motion (the shaft already turning at +600 and -400 rpm when the
recording began), noise on every column. A shared free initial speed cannot start both runs; one per run
does, and the friction is found. Steady points: the relief rig's example data (flow force 0.3 planted, crack
settings 30, 45 and 60 bar) with the crack setting fitted per group instead of given."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

import cli
from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.model import Model
from blocks.calibrate.run import calibrate, per_group_globals
from blocks.circuit import Circuit

EXPERIMENTS = Path(__file__).resolve().parents[2] / "netlists" / "experiments"
NETLIST = EXPERIMENTS / "circuits" / "drive_line_open.yaml"
START_RPM = {"a": 600.0, "b": -400.0}  # the shaft speed when each recording began
SIGMA = {"cmd": 0.005, "speed": 5.0, "pA": 1.0, "pB": 1.0}  # in the data's units: 1, rpm, bar, bar
T_END = "1.2 s"


def _short(netlist: dict) -> dict:
    netlist["simulation"]["t_end"] = T_END
    return netlist


@pytest.fixture(scope="module")
def runs_dir(tmp_path_factory) -> Path:
    """Each run's data file, simulated by the truth (the declared netlist with the friction) from its own
    initial speed, and the declared netlist cut to the same span."""
    path = tmp_path_factory.mktemp("per_run")
    truth = _short(yaml.safe_load(NETLIST.read_text()))
    truth["components"]["friction"] = {"type": "rot_friction", "params": {"Tc": "3 N*m", "b": 0.0, "w_w": 0.1}}
    truth["nets"]["shaft"] = truth["nets"]["shaft"] + ["friction.port"]
    (path / "truth.yaml").write_text(yaml.safe_dump(truth, sort_keys=False))
    (path / "declared.yaml").write_text(yaml.safe_dump(_short(yaml.safe_load(NETLIST.read_text())), sort_keys=False))
    circuit = Circuit.from_file(path / "truth.yaml")
    rng = np.random.default_rng(7)
    scale = {"cmd": 1.0, "speed": 2 * np.pi / 60, "pA": 1e5, "pB": 1e5}
    for label, rpm in START_RPM.items():
        result = circuit.simulate({"shaft.initial": rpm * 2 * np.pi / 60})
        noisy = {name: result.values[:, result.names.index(name)] / scale[name]
                 + SIGMA[name] * rng.normal(size=result.t.size) for name in SIGMA}
        lines = ["t [s],cmd [1],speed [rpm],pA [bar],pB [bar]"] + [
            f"{t:.6f}," + ",".join(f"{noisy[name][k]:.6f}" for name in SIGMA) for k, t in enumerate(result.t)]
        (path / f"{label}.csv").write_text("\n".join(lines) + "\n")
    return path


def _experiment(folder: Path, per: str | None, **changes) -> Path:
    initial = {"initial": "0 rpm", "lower": "-3000 rpm", "upper": "3000 rpm"}
    if per is not None:
        initial["per"] = per
    spec = {"netlist": "declared.yaml", "data": ["a.csv", "b.csv"],
            "inputs": {"cmd": {"signal": "cmd", "latent": ["u1", "u2"], "noise": 0.005}},
            "outputs": {"speed": {"signal": "speed", "noise": "5 rpm"}, "pA": {"signal": "pA", "noise": "1 bar"},
                        "pB": {"signal": "pB", "noise": "1 bar"}},
            "free": {"m_load": {"initial": "6000 kg", "lower": "0 kg", "upper": "50000 kg"},
                     "shaft.initial": initial},
            "heldout": {"scheme": "leave_one_experiment_out"},
            "trace": {"rounds": 1, "only": ["coulomb_friction"]}}
    spec.update(changes)
    (folder / "exp.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    return folder / "exp.yaml"


def test_a_per_group_parameter_is_one_global_per_run(runs_dir):
    exp = load_experiment(_experiment(runs_dir, "group"))
    data = load_data(exp)
    names = [g.name for g in per_group_globals(exp, data)]
    assert names == ["m_load", "shaft.initial[a]", "shaft.initial[b]"]
    with pytest.raises(ValueError, match="unexpanded"):  # the model never reads one value for several groups
        Model(Circuit.from_file(exp.netlist, compile=False), exp, data, exp.free)


def test_each_group_may_start_apart_and_is_shown_in_the_unit_given(runs_dir):
    """initial: {a: ..., b: ...} starts each run's copy at its own value; a net's initial speed, which the
    netlist never wrote, is shown in the experiment's rpm (before: rad/s, its SI unit)."""
    spec = yaml.safe_load(_experiment(runs_dir, "group").read_text())
    spec["free"]["shaft.initial"]["initial"] = {"a": "500 rpm", "b": "-300 rpm"}
    (runs_dir / "starts.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    exp = load_experiment(runs_dir / "starts.yaml")
    copies = {g.name: g for g in per_group_globals(exp, load_data(exp))}
    assert copies["shaft.initial[a]"].initial == pytest.approx(500 * 2 * np.pi / 60)
    assert copies["shaft.initial[b]"].initial == pytest.approx(-300 * 2 * np.pi / 60)
    assert copies["shaft.initial[a]"].unit == "rpm" and copies["m_load"].unit == "kg"


def test_a_run_label_with_brackets_sets_the_parameter_itself(runs_dir, tmp_path):
    """A run is named by its file's stem, which may hold brackets (``run[1].csv``): its copy
    ``shaft.initial[run[1]]`` still sets ``shaft.initial`` (before: 'unknown parameter shaft.initial[run',
    every run of the model failing)."""
    for name, to in (("a.csv", "run[1].csv"), ("b.csv", "b.csv"), ("declared.yaml", "declared.yaml")):
        (tmp_path / to).write_text((runs_dir / name).read_text())
    exp = load_experiment(_experiment(tmp_path, "group", data=["run[1].csv", "b.csv"]))
    data = load_data(exp)
    globals_ = per_group_globals(exp, data)
    model = Model(Circuit.from_file(exp.netlist, compile=False), exp, data, globals_)
    x = model.initial()
    x[model.layout.index("shaft.initial[run[1]]")] = 12.5
    assert model._group_values(x, "run[1]") == {"shaft.initial": 12.5}


def test_each_run_starts_from_its_own_fitted_state_and_the_friction_is_found(runs_dir, tmp_path):
    shared = calibrate(_experiment(runs_dir, None), tmp_path / "shared", with_heldout=False)
    named = [line for line in shared.verdict if "starts off the data" in line]
    assert shared.unexplained and named, shared.verdict  # one initial speed cannot start both runs
    assert "(each run its own: per: group)" in named[0]

    cal = calibrate(_experiment(runs_dir, "group"), tmp_path / "per_run")
    assert [a[0] for a in cal.accepted] == ["coulomb_friction@shaft"] and not cal.unexplained, cal.verdict
    assert 0.8 < cal.final.lof.reduced < 1.25
    model, fit = cal.final.model, cal.final.fit
    for label, rpm in START_RPM.items():
        j = model.layout.index(f"shaft.initial[{label}]")
        assert abs(fit.x[j] - rpm * 2 * np.pi / 60) < 3 * fit.se[j], (label, fit.x[j] * 60 / (2 * np.pi), fit.se[j])
    tc = fit.x[model.layout.index(cal.accepted[0][3])]
    se = fit.se[model.layout.index(cal.accepted[0][3])]
    assert abs(tc - 3.0) < 3 * se, (tc, se)
    # each held-out run predicted from the other, its own start fitted to its own samples: near the noise,
    # where the run's start held at the other's (or at 0 rpm) would miss by hundreds of sigma at its start
    held = cal.final.heldout
    assert held.n == 3 * 601 * 2 and held.error < 1.5, held
    header = (tmp_path / "per_run" / "calibrated.yaml").read_text()
    assert "Fitted per group, so not set here (the report gives each): shaft.initial[a], shaft.initial[b]." \
        in header


def test_the_crack_setting_of_each_group_of_steady_points_is_fitted(tmp_path):
    """The relief rig's example data (flow force c_ff = 0.3 planted, settings 30, 45 and 60 bar), with the
    flow force free and the crack setting fitted per setting instead of given: each recovered within 3 SE,
    and each setting held out predicted from the others with its own crack setting fitted to it alone."""
    spec = yaml.safe_load((EXPERIMENTS / "relief_rig_steady.yaml").read_text())
    spec.update(netlist=str(EXPERIMENTS / spec["netlist"]), data=str(EXPERIMENTS / spec["data"]), drift=[],
                trace={"rounds": 1, "only": ["sensor_offset"]})
    del spec["groups"]
    spec["free"].update({"relief.c_ff": {"initial": 0.1, "lower": 0, "upper": 0.5},
                         "p_set": {"initial": "40 bar", "lower": "10 bar", "upper": "100 bar", "per": "group"}})
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    cal = calibrate(tmp_path / "exp.yaml", tmp_path / "out")
    assert cal.accepted == [] and not cal.unexplained, cal.verdict
    model, fit = cal.final.model, cal.final.fit
    for label, bar in {"1": 30.0, "2": 45.0, "3": 60.0}.items():
        j = model.layout.index(f"p_set[{label}]")
        assert abs(fit.x[j] - bar * 1e5) < 3 * fit.se[j], (label, fit.x[j] / 1e5, fit.se[j] / 1e5)
    j = model.layout.index("relief.c_ff")
    assert abs(fit.x[j] - 0.3) < 3 * fit.se[j], (fit.x[j], fit.se[j])
    held = cal.final.heldout
    assert held.scheme == "leave one group out" and held.error < 2.0, held


def _refused(capsys, file: Path) -> str:
    assert cli.main(["calibrate", str(file), "-o", str(file.parent / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    return err


def test_per_group_with_one_group_or_in_drift_is_refused(runs_dir, tmp_path, capsys):
    for name in ("a.csv", "b.csv", "declared.yaml"):
        (tmp_path / name).write_text((runs_dir / name).read_text())
    err = _refused(capsys, _experiment(tmp_path, "group", data="a.csv"))
    assert "exp.yaml" in err and "free.shaft.initial.per: group: the data have one group (no grouping column, one data file); " \
        "leave per: out to fit one value" in err, err
    err = _refused(capsys, _experiment(tmp_path, "group", drift=["shaft.initial"]))
    assert "drift: 'shaft.initial' is fitted per group already" in err, err
    err = _refused(capsys, _experiment(tmp_path, "run"))
    assert "free.shaft.initial.per: 'run' is not known; allowed: 'group'" in err, err
    for per, starts, said in ((None, {"a": "1 rpm", "b": "2 rpm"}, "free.shaft.initial.initial: a start per group "
                                                                  "(a mapping) needs per: group"),
                              ("group", {"a": "1 rpm", "c": "2 rpm"}, "free.shaft.initial.initial: no group 'c' in "
                                                                      "the data (groups: a, b)"),
                              ("group", {"a": "1 rpm", "b": "9000 rpm"}, "free.shaft.initial.initial.b: the start "
                                                                         "value 9000 rpm is outside")):
        file = _experiment(tmp_path, per)
        spec = yaml.safe_load(file.read_text())
        spec["free"]["shaft.initial"]["initial"] = starts
        file.write_text(yaml.safe_dump(spec, sort_keys=False))
        err = _refused(capsys, file)
        assert said in err and "exp.yaml:" in err, err
