"""Noise levels estimated from the data (blocks.calibrate.data): ``repeats`` (the pooled standard deviation
over repeated steady points) and ``diff`` (second differences of a time series), against their closed forms
and against the sigma that drew the noise; and the clear errors when the data cannot give them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.errors import VphsError

ROOT = Path(__file__).resolve().parents[2]
RIG = ROOT / "netlists" / "experiments" / "circuits" / "relief_rig.yaml"
DRIVE = ROOT / "netlists" / "experiments" / "circuits" / "drive_line_open.yaml"


def steady(tmp_path, rows: list[str], p1_noise="repeats", q_noise="0.5 l/min", repeats=None, header=None):
    (tmp_path / "data.csv").write_text((header or "setting,Q [l/min],p1 [bar]") + "\n" + "\n".join(rows) + "\n")
    spec = {"netlist": str(RIG), "data": "data.csv", "group": "setting",
            "inputs": {"Q": {"parameter": "Q_in", "noise": q_noise}},
            "outputs": {"p1": {"signal": "p1", "noise": p1_noise}},
            "groups": {"1": {"p_set": "30 bar"}, "2": {"p_set": "45 bar"}}}
    if repeats:
        spec["repeats"] = repeats
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec))
    return load_data(load_experiment(tmp_path / "exp.yaml"))


def test_repeats_at_exact_set_points_pool_the_squared_deviations(tmp_path):
    """Sets at exact set points: (1, 20): 40, 41, 43; (1, 40): 50, 50.5; (2, 20): 30 alone (no repeat).
    sigma^2 = (14/3 + 0.125) / (2 + 1) bar^2: the sums of squared deviations over the degrees of freedom."""
    rows = ["1,20,40", "1,20,41", "1,20,43", "1,40,50", "1,40,50.5", "2,20,30"]
    data = steady(tmp_path, rows)
    ss = np.sum((np.array([40, 41, 43]) - 124 / 3) ** 2) + 2 * 0.25 ** 2
    assert data.sigma["p1"] == pytest.approx(np.sqrt(ss / 3) * 1e5, rel=1e-12)
    assert data.noise_notes["p1"] == "estimated from repeated points (3 degrees of freedom)"
    assert data.sigma["Q"] == pytest.approx(0.5 / 60000)


def test_repeats_marked_by_a_column_when_the_input_readings_are_noisy(tmp_path):
    """400 operating points, each set up twice; every reading noisy (Q by 0.5 l/min, p1 by 0.2 bar), so no
    two Q readings agree: matched by the point column, the estimates come within 4 standard errors of the
    sigmas that drew them (the SE of a pooled SD on nu degrees of freedom is sigma / sqrt(2 nu))."""
    rng = np.random.default_rng(3)
    rows = []
    for k in range(400):
        q, p = rng.uniform(10, 90), rng.uniform(30, 60)
        for _ in range(2):
            rows.append(f"{1 + k % 2},{k},{q + 0.5 * rng.normal():.6f},{p + 0.2 * rng.normal():.6f}")
    header = "setting,point,Q [l/min],p1 [bar]"
    with pytest.raises(VphsError, match=r"no repeated points .* mark them with a column \(repeats: <column>\)"):
        steady(tmp_path, rows, header=header)
    data = steady(tmp_path, rows, q_noise="repeats", repeats="point", header=header)
    se = 1 / np.sqrt(2 * 400)
    assert abs(data.sigma["p1"] / 0.2e5 - 1) < 4 * se
    assert abs(data.sigma["Q"] / (0.5 / 60000) - 1) < 4 * se
    assert data.noise_notes["Q"] == "estimated from repeated points (400 degrees of freedom)"


def test_repeats_that_cannot_give_a_noise_are_clear_errors(tmp_path):
    with pytest.raises(VphsError, match=r"inputs\.Q\.noise: .*repeats of the imposed input 'Q' need a column"):
        steady(tmp_path, ["1,20,40", "1,20,41"], q_noise="repeats")
    with pytest.raises(VphsError, match=r"the 4 repeated readings of 'p1' agree exactly; give its noise"):
        steady(tmp_path, ["1,20,40", "1,20,40", "2,20,30", "2,20,30"])
    with pytest.raises(VphsError, match=r"exp\.yaml:\d+:1: repeats: no column 'run' in .*data\.csv \(its columns: "):
        steady(tmp_path, ["1,20,40", "1,20,41"], repeats="run")


def test_diff_recovers_white_noise_on_a_signal_with_steps(tmp_path):
    """A time series: a smooth ramp-and-sine signal with two steps plus white noise of 0.7 bar; the second
    differences (robust scale, steps as outliers) give sigma within 4 % (the MAD's SE at n = 4000 is ~2 %)."""
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 4.0, 4001)
    clean = 50 + 5 * t + 3 * np.sin(2 * np.pi * 0.5 * t) + 10 * (t > 1.0) - 15 * (t > 2.5)
    pA = clean + 0.7 * rng.normal(size=t.size)
    lines = [f"{a:.6f},0,{b:.6f}" for a, b in zip(t, pA)]
    (tmp_path / "data.csv").write_text("t [s],cmd [1],pA [bar]\n" + "\n".join(lines) + "\n")
    spec = {"netlist": str(DRIVE), "data": "data.csv",
            "inputs": {"cmd": {"signal": "cmd", "latent": ["u1"], "noise": 0.01}},
            "outputs": {"pA": {"signal": "pA", "noise": "diff"}}}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec))
    data = load_data(load_experiment(tmp_path / "exp.yaml"))
    assert data.sigma["pA"] / 0.7e5 == pytest.approx(1.0, abs=0.04)
    assert data.noise_notes["pA"] == "estimated from second differences"


def _diff_series(tmp_path, pA: list[float], files: int = 1):
    """A time series of ``pA`` (bar) at 10 ms, noise: diff, as one file or the same rows in several files."""
    lines = [f"{0.01 * k:.2f},0,{p}" for k, p in enumerate(pA)]
    names = [f"run{j}.csv" for j in range(files)]
    for name in names:
        (tmp_path / name).write_text("t [s],cmd [1],pA [bar]\n" + "\n".join(lines) + "\n")
    spec = {"netlist": str(DRIVE), "data": names[0] if files == 1 else names,
            "inputs": {"cmd": {"signal": "cmd", "latent": ["u1"], "noise": 0.01}},
            "outputs": {"pA": {"signal": "pA", "noise": "diff"}}}
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec))
    return load_data(load_experiment(tmp_path / "exp.yaml"))


def test_diff_that_cannot_give_a_noise_says_why(tmp_path):
    """Too few samples used to be reported as second differences that 'are all zero'; and runs of several files
    pooled to a zero noise went on to divide by it."""
    noisy = list(20 + np.random.default_rng(2).normal(size=7))
    assert _diff_series(tmp_path, noisy).sigma["pA"] > 0  # 7 samples: 5 second differences
    with pytest.raises(VphsError, match=r"exp\.yaml:\d+:\d+: noise: diff estimates the noise of 'pA' from its second "
                                        r"differences, which needs at least 5 of them \(7 samples in one run\); the "
                                        r"data give 4: give the noise"):
        _diff_series(tmp_path, noisy[:6])
    with pytest.raises(VphsError, match=r"noise: the second differences of 'pA' are the same in over half the samples"):
        _diff_series(tmp_path, [20.0] * 6 + [21.0] * 4)  # a quantised step: one difference of 1, one of -1
    with pytest.raises(VphsError, match=r"noise: the second differences of 'pA' are the same in over half"):
        _diff_series(tmp_path, [20.0] * 10, files=2)  # pooled over the files, and still nothing
    # a short run among several is pooled with the others, not refused on its own (a review's find)
    data = _diff_series(tmp_path, noisy * 20, files=2)
    (tmp_path / "run1.csv").write_text("t [s],cmd [1],pA [bar]\n0,0,20\n0.01,0,21\n0.02,0,20\n")
    data = load_data(load_experiment(tmp_path / "exp.yaml"))
    assert data.sigma["pA"] > 0 and data.noise_notes["pA"] == "estimated from second differences, pooled over 2 files"
