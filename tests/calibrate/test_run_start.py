"""A time series whose run starts off the data (the machine already moving when the recording began) is named
in the verdict with what to do about it (blocks/calibrate/run_start.py); a model wrong throughout is not."""

from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import yaml

from blocks.calibrate.model import FAILED_RESIDUAL
from blocks.calibrate.run import calibrate
from blocks.calibrate.run_start import M, start_misfits

EXPERIMENTS = Path(__file__).resolve().parents[2] / "netlists" / "experiments"


def _stage(r_speed: np.ndarray, t0: float = 0.0, t_start: float = 0.0):
    """A one-run fit of two channels (the command imposed, the speed compared) with the given normalised
    residuals of the speed (the command's are 50 sigma: an input's misfit is not the start's)."""
    n = r_speed.size
    channels = [SimpleNamespace(name="cmd", role="input", unit="1"),
                SimpleNamespace(name="speed", role="output", unit="rpm")]
    data = SimpleNamespace(kind="time", n=n, t=t0 + 0.01 * np.arange(n))
    model = SimpleNamespace(data=data, runs={"a": np.arange(n)}, channels=channels,
                            measured=np.full(2 * n, 2 * np.pi * 1000 / 60), row_sigma=np.full(2 * n, 0.5),
                            settings=SimpleNamespace(t_start=t_start))
    return SimpleNamespace(model=model, fit=SimpleNamespace(r=np.concatenate([np.full(n, 50.0), r_speed])))


def test_a_start_that_misses_worse_than_the_run_is_named():
    r = np.random.default_rng(1).normal(size=200)
    assert start_misfits(_stage(r)) == []  # at the noise
    r[:M] = [40.0, 30.0, 20.0]
    (found,) = start_misfits(_stage(r))
    assert (found.channel, found.z_start) == ("speed", 30.0) and 2 * found.z_run < 30.0
    assert abs(found.simulated - found.measured - 40.0 * 0.5) < 1e-9  # r = (simulated - measured)/sigma
    line = found.line(["shaft.initial"])
    assert line.startswith("the run starts off the data: at its first sample (t = 0 s) speed is 1000 rpm measured "
                           "and 1191 rpm simulated (30 sigma over 3 samples from the first")
    assert line.endswith("give the netlist's initial values or free them: shaft.initial")


def test_a_misfit_that_builds_over_the_first_samples_is_found_where_it_is_worst():
    """A position freed at the start matches the first sample; a wrong start speed shows a few samples
    later (a reviewer's cylinder: the first 50 ms missed by about 80 sigma, the first 3 samples not over 5)."""
    r = np.random.default_rng(2).normal(size=400)
    r[:12] = np.linspace(0.0, 80.0, 12)  # 0 at the first sample, 80 sigma at the 12th
    (found,) = start_misfits(_stage(r))
    assert found.z_start > 70 and found.t_worst == 0.11  # the 12th sample (0.01 s apart), the worst
    assert "at t = 0.11 s, soon after its first sample (t = 0 s)" in found.line([])
    r[:12] = 0.0
    r[30:42] = 80.0  # the same, but beyond the first 5 % of the run (20 samples): a misfit of the run
    assert start_misfits(_stage(r)) == []


def test_a_model_wrong_throughout_or_a_small_start_misfit_is_not_a_start_misfit():
    r = np.full(200, 30.0)
    r[:M] = 55.0  # over 5 sigma, but not twice the run's RMS (about 30.4)
    assert start_misfits(_stage(r)) == []
    r[:M] = 65.0
    assert len(start_misfits(_stage(r))) == 1
    r = np.zeros(200)
    r[:M] = 4.9  # worse than the run, but within the threshold
    assert start_misfits(_stage(r)) == []
    r[:M] = 5.1
    assert len(start_misfits(_stage(r))) == 1
    r[-1] = FAILED_RESIDUAL  # a run that failed holds a penalty, not a misfit
    assert start_misfits(_stage(r)) == []


def test_a_run_that_begins_after_the_simulation_start_is_told_to_start_the_netlist_there():
    r = np.zeros(200)
    r[:M] = 50.0
    (found,) = start_misfits(_stage(r, t0=1.7, t_start=0.0))
    assert "The simulation starts at 0 s, before the run's first sample" in found.line([])
    assert "(simulation: t_start: 1.7 s)" in found.line([])


def test_the_drive_line_recorded_from_mid_motion_is_named_and_freeing_its_initial_values_fits(tmp_path):
    """The shipped drive-line data (friction 3 N*m planted) from 1 s on, the netlist started there at rest
    (its initial values: 0 rpm, 20 bar): chi^2/nu 874, and before this check the verdict only said to check
    the experiment. With the initial values free the friction is found and the model fits to the noise."""
    netlist = yaml.safe_load((EXPERIMENTS / "circuits" / "drive_line_open.yaml").read_text())
    netlist["simulation"]["t_start"] = "1 s"
    (tmp_path / "net.yaml").write_text(yaml.safe_dump(netlist, sort_keys=False))
    lines = (EXPERIMENTS / "data" / "drive_line_series.csv").read_text().splitlines()
    rows = [line for line in lines if line and not line.startswith("#")]
    (tmp_path / "late.csv").write_text("\n".join(rows[:1] + [line for line in rows[1:]
                                                           if float(line.split(",")[0]) >= 1.0]) + "\n")
    spec = yaml.safe_load((EXPERIMENTS / "drive_line_series.yaml").read_text())
    spec.update(netlist="net.yaml", data="late.csv", trace={"rounds": 1, "only": ["coulomb_friction"]})
    (tmp_path / "late.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    cal = calibrate(tmp_path / "late.yaml", tmp_path / "out", with_heldout=False)
    named = [line for line in cal.verdict if "starts off the data" in line]
    assert cal.unexplained and len(named) == 1, cal.verdict
    # the worst 3 samples of the first 25 (at rest when the recording began at 1463 rpm, the model has
    # reached 9 rpm 8 samples later, where the machine turns at 1509 rpm)
    found = re.search(r"at t = 1\.016 s, soon after its first sample \(t = 1 s\), speed is 1509 rpm measured and "
                      r"(\S+) rpm simulated", named[0])
    assert found, named[0]
    # the simulated speed is the declared model's at its fitted parameters, 16 ms after starting at rest: its
    # 4th digit follows the fit's end point (9.192 with one numba/scipy, 9.191 with the next), so it is read as
    # "started at rest and still near it", far below the machine's 1509 rpm
    assert 5.0 < float(found.group(1)) < 15.0, named[0]
    assert named[0].endswith("free them: spool.initial.x, spool.initial.dx, A.initial, B.initial, shaft.initial")

    spec["free"] = {"spool.initial.x": {"initial": 0, "lower": -1, "upper": 1},
                    "shaft.initial": {"initial": "0 rpm", "lower": "-3000 rpm", "upper": "3000 rpm"},
                    "A.initial": {"initial": "20 bar", "lower": "0 bar", "upper": "300 bar"},
                    "B.initial": {"initial": "20 bar", "lower": "0 bar", "upper": "300 bar"}, **spec["free"]}
    (tmp_path / "free.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    cal = calibrate(tmp_path / "free.yaml", tmp_path / "out_free", with_heldout=False)
    assert [a[0] for a in cal.accepted] == ["coulomb_friction@shaft"] and not cal.unexplained, cal.verdict
    assert not [line for line in cal.verdict if "starts off the data" in line]
