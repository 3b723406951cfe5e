"""A recorded command trace that the netlist reads itself (a profile block with ``{csv:, column:}``).

Imposed exactly, the experiment names the column, the report says so, and a remaining discrepancy points at
it. Listed under ``inputs:`` with ``latent: trace``, the recording is a noisy reading of a latent spline
whose knots are fitted (blocks/calibrate/latent_trace.py): on the drive line's example data (Coulomb
friction 3 N*m planted, the command's noise 0.005 on levels of 0.1 to 0.2), the exact trace biases the
friction by over 3 SE and the latent one does not."""

from __future__ import annotations

import shutil
from pathlib import Path

from types import SimpleNamespace

import numpy as np
import pytest
import yaml

from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.model import Model
from blocks.calibrate.report import write
from blocks.calibrate.run import calibrate, latent_globals
from blocks.calibrate.verdict import verdict

EXPERIMENTS = Path(__file__).resolve().parents[2] / "netlists" / "experiments"


def _trace_experiment(tmp_path: Path, data_name: str, latent: bool = False, trace: dict | None = None) -> Path:
    """The drive-line experiment with its command profile reading the columns t and cmd of ``data_name``, and
    the command no longer listed as an input (``latent``: listed, as a latent trace)."""
    (tmp_path / "circuits").mkdir()
    (tmp_path / "data").mkdir()
    shutil.copy(EXPERIMENTS / "data" / "drive_line_series.csv", tmp_path / "data" / "drive_line_series.csv")
    shutil.copy(EXPERIMENTS / "data" / "drive_line_series.csv", tmp_path / "data" / "other.csv")
    netlist = yaml.safe_load((EXPERIMENTS / "circuits" / "drive_line_open.yaml").read_text())
    netlist["components"]["cmd"]["params"] = {"times": {"csv": f"../data/{data_name}", "column": "t"},
                                              "values": {"csv": f"../data/{data_name}", "column": "cmd"}}
    (tmp_path / "circuits" / "trace.yaml").write_text(yaml.safe_dump(netlist, sort_keys=False))
    exp = yaml.safe_load((EXPERIMENTS / "drive_line_series.yaml").read_text())
    exp["netlist"] = "circuits/trace.yaml"
    if latent:
        exp["inputs"] = {"cmd": {"signal": "cmd", "latent": "trace", "noise": 0.005}}
    else:
        del exp["inputs"]
    if trace is not None:
        exp["trace"] = trace
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(exp, sort_keys=False))
    return tmp_path / "exp.yaml"


def test_a_column_the_netlist_reads_from_the_data_is_named(tmp_path):
    exp = load_experiment(_trace_experiment(tmp_path, "drive_line_series.csv"))
    assert exp.exact_columns == [("cmd", "cmd.values")]  # the sample times (t) are exact in the model anyway


def test_a_column_read_from_another_file_is_not_the_datas(tmp_path):
    assert load_experiment(_trace_experiment(tmp_path, "other.csv")).exact_columns == []


def test_a_remaining_discrepancy_points_at_the_exact_column():
    final = SimpleNamespace(fit=SimpleNamespace(converged=True, inflation=2.26, failed_rows=0, n=6804,
                                                run_failure=lambda: ""),
                            model=SimpleNamespace(layout=SimpleNamespace(globals=[]),  # no run starts off
                                                  data=SimpleNamespace(kind="steady")),
                            lof=SimpleNamespace(significant=lambda: ["chi^2/nu = 2.26 (p = 0)"], overstated_noise=list))
    cal = SimpleNamespace(rounds=[], final=final, exchanges=[], removals=[], accepted=[],
                          exp=SimpleNamespace(exact_columns=[("cmd", "cmd.values")]))
    lines, unexplained = verdict(cal)
    assert unexplained and lines[0] == "unexplained discrepancy remains: chi^2/nu = 2.26 (p = 0)"
    assert lines[1].startswith("  the netlist imposes the column cmd (cmd.values) exactly as read from the data: "
                               "its measurement noise is not accounted for")
    cal.exp.exact_columns = []
    assert verdict(cal)[0] == ["unexplained discrepancy remains: chi^2/nu = 2.26 (p = 0)"]


def test_a_latent_trace_is_not_imposed_exactly_and_its_knots_are_the_profiles_breakpoints(tmp_path):
    exp = load_experiment(_trace_experiment(tmp_path, "drive_line_series.csv", latent=True))
    assert exp.exact_columns == [] and exp.inputs[0].trace == "cmd.values"
    data = load_data(exp)
    knots = latent_globals(exp, data)
    values = [g for g in knots if g.kind == "trace"]
    times = [g for g in knots if g.kind == "trace_time"]
    assert len(times) == len(values) - 2  # the first and last knot keep the data's ends
    from blocks.circuit import Circuit

    model = Model(Circuit.from_file(exp.netlist), exp, data, exp.free + knots)
    x = model.initial()
    over = model._net_overrides(x)
    n = len(values)
    assert len(over["cmd.times"]) == len(over["cmd.values"]) == data.n  # the arrays keep the recording's length
    assert over["cmd.times"][:n] == pytest.approx([values[0].at] + [g.initial for g in times] + [values[-1].at])
    assert over["cmd.values"][:n] == pytest.approx([g.initial for g in values])
    assert np.all(np.diff(over["cmd.times"]) > 0) and set(over["cmd.values"][n:]) == {values[-1].initial}
    # the input's rows: the spline through the knots, sampled at the data's times
    spline = np.interp(data.t, over["cmd.times"][:n], over["cmd.values"][:n])
    assert model.predictions(x)[:data.n] == pytest.approx(spline, abs=1e-9)


def test_a_held_out_blocks_knots_start_from_the_recording_alone(tmp_path, monkeypatch):
    """The fold's outputs must not have placed the knots that predict it (a knot time between two samples is
    set by the outputs only): the held-out refit starts the block's knots where the recording put them."""
    import blocks.calibrate.heldout as heldout_module
    from blocks.circuit import Circuit

    exp = load_experiment(_trace_experiment(tmp_path, "drive_line_series.csv", latent=True))
    data = load_data(exp)
    model = Model(Circuit.from_file(exp.netlist), exp, data, exp.free + latent_globals(exp, data))
    moved = model.initial() + 1e-4  # as if the full fit had moved every parameter
    starts = []
    monkeypatch.setattr(heldout_module, "fit", lambda m, x0, active, rows, max_nfev: starts.append(x0.copy())
                        or SimpleNamespace(x=x0, r=np.zeros(m.n_rows), converged=True,
                                           active=np.zeros(x0.size, dtype=bool)))
    full = SimpleNamespace(x=moved, active=np.ones(moved.size, dtype=bool), rows=np.ones(model.n_rows, dtype=bool))
    heldout_module.heldout(model, full, exp.spec.heldout)
    _, folds = heldout_module.make_folds(model, exp.spec.heldout)
    for (_, idx), x0 in zip(folds, starts):
        for j, g in enumerate(model.layout.globals):
            start = g.initial if g.at is None else g.at
            inside = g.kind in ("trace", "trace_time") and data.t[idx[0]] <= start <= data.t[idx[-1]]
            assert x0[j] == (g.initial if inside else moved[j]), g.name


@pytest.mark.parametrize("latent", [False, True], ids=["imposed exactly", "latent trace"])
def test_the_recordings_noise_biases_the_friction_unless_the_trace_is_latent(tmp_path, latent):
    exp = _trace_experiment(tmp_path, "drive_line_series.csv", latent=latent,
                            trace={"rounds": 1, "only": ["coulomb_friction"]})
    cal = calibrate(exp, tmp_path / "out", with_heldout=False)
    assert [a[0] for a in cal.accepted] == ["coulomb_friction@shaft"]
    k = cal.final.model.layout.index("cal_Tc_shaft")
    value, se = cal.final.fit.x[k], cal.final.fit.se[k]
    paths = write(cal, tmp_path / "out")
    if latent:
        assert abs(value - 3.0) < 3.0 * se, f"{value} +- {se}"
        assert cal.final.lof.reduced < 1.1 and not verdict(cal)[1]
        assert paths["traces"].stat().st_size > 0 and "latent trace of cmd" in paths["markdown"].read_text()
        # calibrated.yaml drives the profile through the fitted knots, not the recording: run, it gives the
        # final fit's prediction of the speed
        from blocks.circuit import Circuit

        model, fit = cal.final.model, cal.final.fit
        rows = model.row_channel == [c.name for c in model.channels].index("speed")
        predicted = cal.data.measured["speed"] + fit.r[rows] * cal.data.sigma["speed"]
        run = Circuit.from_file(cal.calibrated).simulate()  # its values rounded to a hundredth of their SE or finer
        assert np.allclose(np.interp(cal.data.t, run.t, run["speed"]), predicted, atol=0.02 * cal.data.sigma["speed"])
    else:  # the premise: the recording imposed exactly biases the friction and leaves a misfit
        assert abs(value - 3.0) > 3.0 * se, f"{value} +- {se}"
        assert verdict(cal)[1] and "traces" not in paths
