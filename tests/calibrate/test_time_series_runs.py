"""A time series of several runs (a grouping column): each run simulated with its group's values and its
own latent command levels, held out one run at a time, a declared parameter's drift tested run by run.

The truth: the drive line (netlists/experiments/circuits/drive_line_open.yaml) with a Coulomb friction of
3 N*m on the motor shaft, run twice: at 207 bar supply with the netlist's command levels (0.1, 0.2, -0.15)
and at 150 bar with levels 0.15, 0.25, -0.1; noise on every column (the command's included)."""

from __future__ import annotations

import re
from types import SimpleNamespace
from pathlib import Path

import numpy as np
import pytest
import yaml

import cli
from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.run import calibrate, latent_globals
from blocks.calibrate.verdict import verdict

EXPERIMENTS = Path(__file__).resolve().parents[2] / "netlists" / "experiments"
NETLIST = EXPERIMENTS / "circuits" / "drive_line_open.yaml"
RUNS = {"a": {"supply.p": 207e5, "u1": 0.1, "u2": 0.2, "u3": -0.15},
        "b": {"supply.p": 150e5, "u1": 0.15, "u2": 0.25, "u3": -0.1}}
SIGMA = {"cmd": 0.005, "speed": 5.0, "pA": 1.0, "pB": 1.0}  # in the data's units: 1, rpm, bar, bar


def _write_runs(tmp_path: Path, seed: int = 4) -> Path:
    """The two runs' data, simulated by the truth netlist (the declared one with the friction added)."""
    from blocks.circuit import Circuit

    truth = yaml.safe_load(NETLIST.read_text())
    truth["components"]["friction"] = {"type": "rot_friction", "params": {"Tc": "3 N*m", "b": 0.0, "w_w": 0.1}}
    truth["nets"]["shaft"] = truth["nets"]["shaft"] + ["friction.port"]
    (tmp_path / "truth.yaml").write_text(yaml.safe_dump(truth, sort_keys=False))
    circuit = Circuit.from_file(tmp_path / "truth.yaml")
    rng = np.random.default_rng(seed)
    lines = ["run,t [s],cmd [1],speed [rpm],pA [bar],pB [bar]"]
    scale = {"cmd": 1.0, "speed": 2 * np.pi / 60, "pA": 1e5, "pB": 1e5}
    for label, values in RUNS.items():
        result = circuit.simulate(values)
        columns = {name: result.values[:, result.names.index(name)] / scale[name] for name in SIGMA}
        noisy = {name: y + SIGMA[name] * rng.normal(size=y.size) for name, y in columns.items()}
        for k, t in enumerate(result.t):
            lines.append(f"{label},{t:.6f}," + ",".join(f"{noisy[name][k]:.6f}" for name in SIGMA))
    (tmp_path / "runs.csv").write_text("\n".join(lines) + "\n")
    return tmp_path / "runs.csv"


def _experiment(tmp_path: Path, **changes) -> Path:
    spec = {"netlist": str(NETLIST), "data": "runs.csv", "group": "run",
            "inputs": {"cmd": {"signal": "cmd", "latent": ["u1", "u2", "u3"], "noise": 0.005}},
            "outputs": {"speed": {"signal": "speed", "noise": "5 rpm"}, "pA": {"signal": "pA", "noise": "1 bar"},
                        "pB": {"signal": "pB", "noise": "1 bar"}},
            "groups": {"a": {"supply.p": "207 bar"}, "b": {"supply.p": "150 bar"}},
            "free": {"m_load": {"initial": "6000 kg", "lower": "0 kg", "upper": "50000 kg"},
                     "valve.A_max": {"initial": "110 mm^2", "lower": "10 mm^2", "upper": "1000 mm^2"}},
            "drift": ["m_load"], "heldout": {"scheme": "leave_one_group_out"},
            "trace": {"rounds": 1, "only": ["coulomb_friction", "viscous_friction"]}}
    spec.update(changes)
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    return tmp_path / "exp.yaml"


@pytest.fixture(scope="module")
def runs_dir(tmp_path_factory):
    path = tmp_path_factory.mktemp("runs")
    _write_runs(path)
    return path


def test_each_run_has_its_own_latent_levels_and_group_values(runs_dir, tmp_path):
    (tmp_path / "runs.csv").write_text((runs_dir / "runs.csv").read_text())
    exp = load_experiment(_experiment(tmp_path))
    data = load_data(exp)
    assert list(data.groups) == ["a", "b"] and data.n == 2 * 1701
    levels = latent_globals(exp, data)
    assert [g.name for g in levels] == ["u1[a]", "u1[b]", "u2[a]", "u2[b]", "u3[a]", "u3[b]"]
    assert {g.run for g in levels} == {"a", "b"}


def test_the_runs_calibrate_together_and_are_held_out_one_at_a_time(runs_dir, tmp_path):
    (tmp_path / "runs.csv").write_text((runs_dir / "runs.csv").read_text())
    cal = calibrate(_experiment(tmp_path), tmp_path / "out")
    assert [a[0] for a in cal.accepted] == ["coulomb_friction@shaft"]
    final = cal.final
    x, se = final.fit.x, final.fit.se
    for name, truth in (("cal_Tc_shaft", 3.0), ("m_load", 7500.0), ("u1[b]", 0.15), ("u2[b]", 0.25),
                        ("u3[b]", -0.1), ("u1[a]", 0.1)):
        k = final.model.layout.index(name)
        assert abs(x[k] - truth) < 3.0 * se[k], f"{name} = {x[k]} +- {se[k]}, truth {truth}"
    assert final.heldout.scheme == "leave one run out" and [f[0] for f in final.heldout.folds] == ["a", "b"]
    assert final.heldout.error < 1.2 < cal.initial.heldout.error
    drift = final.lof.drift["m_load"]
    assert drift["groups"] == ["a", "b"] and drift["p_value"] > 1e-3
    assert not verdict(cal)[1]


def _run_cli(tmp_path, capsys, data: str, **changes):
    (tmp_path / "runs.csv").write_text(data)
    code = cli.main(["calibrate", str(_experiment(tmp_path, **changes)), "-o", str(tmp_path / "out")])
    return code, capsys.readouterr().err.strip()


def test_a_run_must_be_one_block_of_rows(tmp_path, capsys):
    code, err = _run_cli(tmp_path, capsys, "run,t [s],cmd [1],speed [rpm],pA [bar],pB [bar]\n"
                                           "a,0,0,0,20,20\na,0.1,0,0,20,20\nb,0,0,0,20,20\na,0.2,0,0,20,20\n")
    assert code == 2 and re.search(r"runs\.csv:5:1: column 'run': the rows of group 'a' are not together", err), err


def test_times_increase_within_a_run(tmp_path, capsys):
    code, err = _run_cli(tmp_path, capsys, "run,t [s],cmd [1],speed [rpm],pA [bar],pB [bar]\n"
                                           "a,0,0,0,20,20\na,0.1,0,0,20,20\nb,0,0,0,20,20\nb,0,0,0,20,20\n")
    assert code == 2 and re.search(r"runs\.csv:5:2: column 't \[s\]': time repeats the previous row's \(times "
                                   r"must increase strictly within a run\)", err), err


def test_a_latent_level_cannot_also_be_set_by_a_group(tmp_path, capsys):
    code, err = _run_cli(tmp_path, capsys, "run,t [s],cmd [1],speed [rpm],pA [bar],pB [bar]\na,0,0,0,20,20\n",
                         groups={"a": {"supply.p": "207 bar", "u2": 0.3}})
    assert code == 2 and "inputs.cmd.latent: u2 is also set by groups.a" in err, err


def _split_files(runs_dir: Path, tmp_path: Path) -> None:
    """The two runs as two files (a.csv, b.csv) without the run column."""
    rows = (runs_dir / "runs.csv").read_text().splitlines()
    header = rows[0].split(",", 1)[1]
    for label in RUNS:
        body = [row.split(",", 1)[1] for row in rows[1:] if row.startswith(label + ",")]
        (tmp_path / f"{label}.csv").write_text("\n".join([header] + body) + "\n")


def test_one_file_per_run_is_the_same_experiment_as_a_grouping_column(runs_dir, tmp_path):
    from blocks.calibrate.heldout import make_folds
    from blocks.calibrate.model import Model
    from blocks.circuit import Circuit

    (tmp_path / "runs.csv").write_text((runs_dir / "runs.csv").read_text())
    grouped = load_data(load_experiment(_experiment(tmp_path)))
    _split_files(runs_dir, tmp_path)
    exp = load_experiment(_experiment(tmp_path, data=["a.csv", "b.csv"], group=None,
                                      heldout={"scheme": "leave_one_experiment_out"}))
    files = load_data(exp)
    assert files.labels == grouped.labels and np.array_equal(files.t, grouped.t)
    for name in SIGMA:
        assert np.array_equal(files.measured[name], grouped.measured[name])
    model = Model(Circuit.from_file(exp.netlist), exp, files, exp.free + latent_globals(exp, files))
    scheme, folds = make_folds(model, exp.spec.heldout)
    assert scheme == "leave one run out" and [label for label, _ in folds] == ["a", "b"]


def test_the_runs_of_several_files_are_named_by_their_files(runs_dir, tmp_path, capsys):
    _split_files(runs_dir, tmp_path)
    path = _experiment(tmp_path, data=["a.csv", "b.csv"], group=None,
                       groups={"a": {"supply.p": "207 bar"}, "c": {"supply.p": "150 bar"}})
    code = cli.main(["calibrate", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "groups.c: no run of that name; the runs are the data files, named without extension: a, b" \
        in err, err


def test_a_sample_outside_the_simulated_span_is_located_by_its_file_and_line(runs_dir, tmp_path, capsys):
    """The netlist simulates 0 ... 3.4 s. A sample past it used to be reported as "the data's times 0 ... 3.402
    s (run 'b') lie outside the simulated span", naming neither file nor line."""
    rows = (runs_dir / "runs.csv").read_text().splitlines()
    (tmp_path / "runs.csv").write_text("\n".join(rows + ["b,3.402000,0,0,20,20"]) + "\n")
    code = cli.main(["calibrate", str(_experiment(tmp_path)), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err == (f"vphs: {tmp_path / 'runs.csv'}:{len(rows) + 1}:2: column 't [s]': t = 3.402 s lies "
                                 f"outside the simulated span 0 ... 3.4 s of {NETLIST} (the run's times: 0 ... 3.402 "
                                 f"s); set the netlist's simulation: t_start and t_end to cover the data, or cut the "
                                 f"data to the span"), err
    _split_files(runs_dir, tmp_path)
    lines = (tmp_path / "b.csv").read_text().splitlines()
    (tmp_path / "b.csv").write_text("\n".join(lines[:1] + ["-0.002,0,0,20,20"] + lines[1:]) + "\n")
    code = cli.main(["calibrate", str(_experiment(tmp_path, data=["a.csv", "b.csv"], group=None)),
                     "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.startswith(f"vphs: {tmp_path / 'b.csv'}:2:1: column 't [s]': t = -0.002 s lies outside "
                                        f"the simulated span 0 ... 3.4 s"), err
    assert not (tmp_path / "out").exists()


def test_time_series_and_steady_points_do_not_mix(runs_dir, tmp_path, capsys):
    _split_files(runs_dir, tmp_path)
    (tmp_path / "steady.csv").write_text("speed [rpm],pA [bar],pB [bar]\n100,20,20\n")
    path = _experiment(tmp_path, data=["a.csv", "steady.csv"], group=None, inputs={}, groups={}, drift=[])
    code = cli.main(["calibrate", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and re.search(r"exp\.yaml:\d+:\d+: data: a\.csv is a time series, other files are steady "
                                   r"points", err), err
    path = _experiment(tmp_path, data=["steady.csv", "a.csv"], group=None, groups={}, drift=[])  # cmd a signal
    code = cli.main(["calibrate", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.endswith("inputs.cmd: steady data (no t column in steady.csv) impose inputs through "
                                      "'parameter', not 'signal' (the files of one experiment are all time series "
                                      "or all steady points)"), err


def _recorded_runs(runs_dir: Path, tmp_path: Path, **changes) -> Path:
    """The two runs as two files, the netlist's command profile reading run a's recording (its breakpoints
    are replaced by each run's knots), the command a latent trace."""
    _split_files(runs_dir, tmp_path)
    netlist = yaml.safe_load(NETLIST.read_text())
    netlist["components"]["cmd"]["params"] = {"times": {"csv": "a.csv", "column": "t"},
                                              "values": {"csv": "a.csv", "column": "cmd"}}
    (tmp_path / "recorded.yaml").write_text(yaml.safe_dump(netlist, sort_keys=False))
    spec = dict(netlist="recorded.yaml", data=["a.csv", "b.csv"], group=None,
                inputs={"cmd": {"signal": "cmd", "latent": "trace", "noise": 0.005}})
    spec.update(changes)
    return _experiment(tmp_path, **spec)


def _recorded_model(runs_dir, tmp_path, **changes):
    from blocks.calibrate.model import Model
    from blocks.circuit import Circuit

    exp = load_experiment(_recorded_runs(runs_dir, tmp_path, **changes))
    data = load_data(exp)
    return exp, data, Model(Circuit.from_file(exp.netlist), exp, data, exp.free + latent_globals(exp, data))


def test_each_run_has_its_own_latent_trace(runs_dir, tmp_path):
    """Each run's knots are chosen from its own recording, and that run alone is simulated with them."""
    exp, data, model = _recorded_model(runs_dir, tmp_path)
    knots = [g for g in model.layout.globals if g.kind in ("trace", "trace_time")]
    assert {g.run for g in knots} == {"a", "b"}
    assert all(g.name.endswith(f"[{g.run}]") for g in knots)
    x = model.initial()
    n = data.n // 2
    for label, idx in data.groups.items():
        mine = [g for g in knots if g.run == label and g.kind == "trace"]
        over = model._run_overrides(label, model._net_overrides(x), x)
        m = len(mine)
        assert over["cmd.values"][:m] == pytest.approx([g.initial for g in mine])
        assert over["cmd.times"][0] == data.t[idx[0]] and over["cmd.times"][m - 1] == data.t[idx[-1]]
        # the input's rows of this run: its own spline, within its noise of its own recording
        spline = np.interp(data.t[idx], over["cmd.times"][:m], over["cmd.values"][:m])
        assert model.predictions(x)[idx] == pytest.approx(spline, abs=1e-9)
        assert np.std(spline - data.measured["cmd"][idx]) < 1.2 * 0.005
    # the two runs' levels differ (0.1/0.2/-0.15 and 0.15/0.25/-0.1): each spline follows its own run
    a, b = (model.predictions(x)[idx] for idx in data.groups.values())
    assert np.max(np.abs(a[:n] - b[:n])) > 0.04


def test_a_held_out_run_restarts_its_own_knots_only(runs_dir, tmp_path, monkeypatch):
    """Leave one run out: the held-out run's knots start from its recording alone, the other run's stay
    where the full fit put them; contiguous blocks: only the knots of the block's run within its span."""
    from types import SimpleNamespace

    import blocks.calibrate.heldout as heldout_module

    for scheme in ({"scheme": "leave_one_experiment_out"}, {"scheme": "kfold", "k": 4}):
        (tmp_path / scheme["scheme"]).mkdir()
        exp, data, model = _recorded_model(runs_dir, tmp_path / scheme["scheme"], heldout=scheme)
        moved = model.initial() + 1e-4
        starts = []
        monkeypatch.setattr(heldout_module, "fit", lambda m, x0, active, rows, max_nfev: starts.append(x0.copy())
                            or SimpleNamespace(x=x0, r=np.zeros(m.n_rows), converged=True,
                                               active=np.zeros(x0.size, dtype=bool)))
        full = SimpleNamespace(x=moved, active=np.ones(moved.size, dtype=bool),
                               rows=np.ones(model.n_rows, dtype=bool))
        heldout_module.heldout(model, full, exp.spec.heldout)
        _, folds = heldout_module.make_folds(model, exp.spec.heldout)
        assert len(folds) == (2 if scheme["scheme"] != "kfold" else 4)
        for (_, idx), x0 in zip(folds, starts):
            restarted = set()
            for j, g in enumerate(model.layout.globals):
                if g.kind not in ("trace", "trace_time"):
                    continue
                mine = np.intersect1d(idx, data.groups[g.run])
                start = g.initial if g.at is None else g.at
                inside = mine.size > 0 and data.t[mine[0]] <= start <= data.t[mine[-1]]
                assert x0[j] == (g.initial if inside else moved[j]), g.name
                if inside:
                    restarted.add(g.run)
            assert restarted == {label for label, rows in data.groups.items() if np.isin(idx, rows).any()}


def test_two_recorded_runs_calibrate_together(runs_dir, tmp_path):
    cal = calibrate(_recorded_runs(runs_dir, tmp_path, trace={"rounds": 1, "only": ["coulomb_friction"]}),
                    tmp_path / "out", with_heldout=False)
    assert [a[0] for a in cal.accepted] == ["coulomb_friction@shaft"]
    final = cal.final
    x, se = final.fit.x, final.fit.se
    for name, truth in (("cal_Tc_shaft", 3.0), ("m_load", 7500.0)):
        k = final.model.layout.index(name)
        assert abs(x[k] - truth) < 3.0 * se[k], f"{name} = {x[k]} +- {se[k]}, truth {truth}"
    assert final.lof.reduced < 1.1 and not verdict(cal)[1]
    from blocks.calibrate.report import write

    paths = write(cal, tmp_path / "out")
    text = paths["markdown"].read_text()
    assert "latent trace of cmd in run a" in text and "latent trace of cmd in run b" in text
    assert paths["traces"].stat().st_size > 0


def test_a_latent_trace_of_several_runs_needs_a_file_per_run(runs_dir, tmp_path, capsys):
    """The netlist's profile must read a recording whose times increase: with one file of several runs
    they go back at each run's start (the error comes before any fitting)."""
    (tmp_path / "runs.csv").write_text((runs_dir / "runs.csv").read_text())
    netlist = yaml.safe_load(NETLIST.read_text())
    netlist["components"]["cmd"]["params"] = {"times": {"csv": "runs.csv", "column": "t"},
                                              "values": {"csv": "runs.csv", "column": "cmd"}}
    (tmp_path / "recorded.yaml").write_text(yaml.safe_dump(netlist, sort_keys=False))
    path = _experiment(tmp_path, netlist="recorded.yaml",
                       inputs={"cmd": {"signal": "cmd", "latent": "trace", "noise": 0.005}})
    code = cli.main(["calibrate", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and re.search(r"exp\.yaml:\d+:\d+: inputs\.cmd\.latent: trace: the netlist's profile reads "
                                   r"the times of a file of several runs", err), err
    assert not (tmp_path / "out").exists()


def test_the_screening_netlist_reproduces_every_run(runs_dir, tmp_path):
    """Every candidate at every place, parameters at zero, is the declared model in each run, run b's
    supply at 150 bar included: a node a line loss adds beside the supply starts at ``supply.p`` as the run
    sets it (frozen at the netlist's 207 bar, run b failed at t = 0)."""
    from blocks.calibrate.candidates import registered
    from blocks.calibrate.experiment import TraceSpec
    from blocks.calibrate.model import Model
    from blocks.calibrate.patch import NetlistDoc
    from blocks.calibrate.run import Stage, all_places, context, free_of
    from blocks.circuit import Circuit

    (tmp_path / "runs.csv").write_text((runs_dir / "runs.csv").read_text())
    exp = load_experiment(_experiment(tmp_path))
    data = load_data(exp)
    globals_ = exp.free + latent_globals(exp, data)
    model = Model(Circuit.from_file(exp.netlist), exp, data, globals_)
    doc = NetlistDoc.read(exp.netlist)
    places = all_places(context(Stage(Path(exp.netlist), model, None, None), exp, data, doc), TraceSpec(),
                        set(model.circuit.flat.parameters.entries))
    assert any(p.key.endswith("@valve.P") for p in places)
    for place in places:
        if place.kind == "netlist":
            doc.add_parameter(place.param, place.zero)
            registered()[place.candidate].patch(doc, place)
    screening = Model(Circuit.from_file(doc.write(tmp_path / "screening.yaml", header="test")), exp, data,
                      globals_ + [free_of(p, p.zero) for p in places])
    x = model.initial()
    r = screening.residuals(model.extend(x, screening))
    assert not screening.failures, screening.failures[0]
    assert np.max(np.abs(r - model.residuals(x))) < 0.05


def test_a_column_imposed_exactly_cannot_drive_several_runs(runs_dir, tmp_path, capsys):
    """The netlist reads run a's recorded command and imposes it as it is: with two runs that would drive
    run b with run a's command, silently."""
    path = _recorded_runs(runs_dir, tmp_path, inputs={})
    code = cli.main(["calibrate", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and re.search(r"exp\.yaml:\d+:\d+: data: the netlist reads the column cmd \(cmd\.values\) "
                                   r"from one data file and imposes it exactly, which would drive all 2 runs", err), err
    assert not (tmp_path / "out").exists()


def test_a_level_no_sample_of_its_run_reads_is_not_fitted(runs_dir, tmp_path):
    """Run a cut at 2.0 s (u3 is in force from 2.0 s on) and run b starting at 1.7 s (u1 and u2 were in force
    before): no sample of its run reads those levels. u3[a] acts on none either: fitted, it drifted (to -6e9
    on one run cut at 2 s; found by a usability review); now it keeps the netlist's value and the verdict
    names it. u1[b] and u2[b] act on the state run b's samples start from, and are fitted."""
    from blocks.calibrate.levels import level_read
    from blocks.circuit import Circuit

    lines = (runs_dir / "runs.csv").read_text().splitlines()
    kept = [line for line in lines[1:] if (line.startswith("a,") and float(line.split(",")[1]) <= 2.0)
            or (line.startswith("b,") and float(line.split(",")[1]) >= 1.7)]
    (tmp_path / "runs.csv").write_text("\n".join([lines[0]] + kept) + "\n")
    exp = load_experiment(_experiment(tmp_path))
    data = load_data(exp)
    held = []
    levels = [g.name for g in latent_globals(exp, data, held) if g.kind == "latent"]
    # u3[a] acts on no sample; u1[b] and u2[b] act on the state run b's samples start from: fitted
    assert held == ["u3[a]"] and sorted(levels) == ["u1[a]", "u1[b]", "u2[a]", "u2[b]", "u3[b]"]
    table = Circuit.from_file(NETLIST, compile=False).flat.parameters
    t = np.linspace(0.0, 3.4, 1701)
    assert all(level_read(table, {}, name, t) for name in ("u1", "u2", "u3"))  # the whole series reads each
    assert not level_read(table, {}, "u3", t[t <= 2.0], until=2.0) and level_read(table, {}, "u3", t[t <= 2.1])
    assert not level_read(table, {}, "u1", t[t >= 1.7]) and level_read(table, {}, "u1", t[t >= 1.7], until=3.4)
    cal = SimpleNamespace(accepted=[], exchanges=[], removals=[], rounds=[], final=None, held_levels=held)
    assert verdict(cal)[0][0].startswith("not fitted: u3[a], command level(s) in force only after the last")


def test_a_run_that_starts_after_some_levels_still_finds_the_friction(tmp_path):
    """The shipped drive-line data (friction 3 N*m planted) split at 1.7 s into two runs, held out one at a
    time. Run b's samples read neither u1 nor u2 (in force before 1.7 s): in its held-out refit, with its
    outputs out, nothing fixed them, u1[b] drifted to -1872 and the friction was refused ('held-out error
    2962 is not below 16.85'; found by a usability review). They are held at their start there now."""
    lines = (EXPERIMENTS / "data" / "drive_line_series.csv").read_text().splitlines()
    rows = [line for line in lines if line and not line.startswith("#")]
    (tmp_path / "runs.csv").write_text("\n".join(["run," + rows[0]] + [
        ("a," if float(line.split(",")[0]) <= 1.7 else "b,") + line for line in rows[1:]]) + "\n")
    exp = _experiment(tmp_path, groups={"a": {"supply.p": "207 bar"}, "b": {"supply.p": "207 bar"}},
                      trace={"rounds": 1, "only": ["coulomb_friction"]})
    cal = calibrate(exp, tmp_path / "out")
    assert [a[0] for a in cal.accepted] == ["coulomb_friction@shaft"], cal.verdict
    _key, _title, _where, _param, value, se, _unit = cal.accepted[0]
    assert abs(value - 3.0) < 3 * se
