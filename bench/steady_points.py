"""Benchmark: one steady point as a settling run and as an equilibrium (Newton), on two rigs.

    python bench/steady_points.py

MCV rig. For each of the thesis's 21 multistep points (netlists/rig/mcv_rig_multistep.yaml with its measured Q and
p2, the chapter-2 valve without flow force, kp = 895 bar): the time of a 1 s settling run from the
netlist's initial state (what ``steady.method: settle`` does at every evaluation) and of a Newton solve
started from the end of that run (what ``steady.method: equilibrium`` does at every later evaluation), both
warm (compiled), each the best of 5; and how far the run's end is from the equilibrium in p1 and p3. Prints
the per-point ratio and the median.

Relief rig (netlists/experiments/relief_rig_steady.yaml, its 21 points at the declared start): the same,
with the experiment's own settling run (its netlist's 0.15 s). Its valve's Dahl friction state acts on no
other state when the friction is zero; Newton holds it (blocks/solve/equilibrium.py), so the points have
equilibria.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def best_of(fn, repeat: int = 5) -> float:
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        fn()
        times.append(time.perf_counter() - started)
    return min(times)


def compare(title: str, circuit, points: list[dict], settle) -> None:
    """Per point: the warm settling run, the warm Newton solve from its end, and the gap in p1 and p3."""
    t_end = settle.t_end
    ratios = []
    print(f"{title}\npoint | run [ms] | Newton [ms] | ratio | run end - equilibrium: p1, p3 [bar]")
    for k, over in enumerate(points):
        run = circuit.simulate(over, settings=settle)
        t_run = best_of(lambda: circuit.simulate(over, settings=settle))
        eq = circuit.equilibrium(over, guess=run.states[-1], t=t_end)
        t_eq = best_of(lambda: circuit.equilibrium(over, guess=run.states[-1], t=t_end))
        gap = [(run[name][-1] - eq[name]) / 1e5 for name in ("p1", "p3")] if eq.stable else [np.nan, np.nan]
        ratios.append(t_run / t_eq)
        print(f"{k + 1:5d} | {1e3 * t_run:8.2f} | {1e3 * t_eq:11.3f} | {t_run / t_eq:5.0f} | "
              f"{gap[0]:+.2e}, {gap[1]:+.2e}{'' if eq.stable else ' (no stable equilibrium)'}")
    print(f"median ratio run / Newton: {np.median(ratios):.0f} (min {min(ratios):.0f}, max {max(ratios):.0f})\n")


def main() -> int:
    from blocks.calibrate.data import load_data
    from blocks.calibrate.experiment import load_experiment
    from blocks.circuit import Circuit
    from blocks.datafile import read_table

    circuit = Circuit.from_file(ROOT / "netlists" / "rig" / "mcv_rig_multistep.yaml")
    table = read_table(ROOT.parent / "shared" / "data" / "mcv_vf250_multistep.csv", group="setting")
    crack = {"1": 95.4e5, "2": 152.0e5, "3": 211.5e5}  # table 3.2
    points = [{"flow_force": 0.0, "mcv.kp2": 0.0, "mcv.kp1": 895e5, "p_crack": crack[label],
               "Q": float(table.columns["Q"][k]), "p2": float(table.columns["p2"][k])}
              for k, label in enumerate(table.labels)]
    compare("MCV rig (1 s settling runs)", circuit, points, circuit.settings.with_(t_end=1.0, dt_out=0.1))

    exp = load_experiment(ROOT / "netlists" / "experiments" / "relief_rig_steady.yaml")
    data = load_data(exp)
    relief = Circuit.from_file(exp.netlist)
    points = []
    for k, label in enumerate(data.labels):
        over = dict(exp.overrides)
        over.update(exp.groups.get(label, {}))
        over["Q_in"] = float(data.measured["Q"][k])
        points.append(over)
    compare(f"Relief rig ({relief.settings.t_end:g} s settling runs)", relief, points, relief.settings)
    return 0


if __name__ == "__main__":
    sys.exit(main())
