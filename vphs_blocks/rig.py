"""The MCV test rig of thesis chapter 3: crack-pressure, multistep and step-response runs (not a block).

    python -m vphs_blocks.rig [-o out/rig_multistep.csv] [--flow-force 1]

runs the three tests on the netlists in ``netlists/rig/`` and prints what they show:

- multistep (section 3.4.2, table 3.4): the 21 measured steady points, each a steady-state run of
  ``mcv_rig_multistep.yaml`` with the point's measured Q and p2 and its setting's crack pressure as
  overrides; settling is checked (the run is lengthened until p1, p2 and p3 vary by less than ``tol`` over
  the last ``window`` of it, else :class:`NotSettled`). Written in the measured file's format (setting,
  p1 [bar], p2 [bar], p3 [bar], Q [l/min]) and compared point by point with the measurements (RMSE per
  curve, over all points and per setting). ``vphs diff`` cannot make this comparison: see the README's
  "The MCV test rig".
- crack pressure (section 3.4.1, table 3.2): ``mcv_rig_crack.yaml`` per setting; the pressures are averaged
  over the part of the slow ramp in which the flow through the valve rises from ``q_visible`` to 0.5 l/min
  (table 3.2 is "the average pressure from 0 to 0.5 l/min"), and eq. 3.2 gives the crack pressure:
        pcr = pc*(alpha + 2) - pv1 - pv2*(alpha + 1)                                 (eq. 3.2)
  with pv1 = the pressure after the flow meter, pv2 = p2, pc = p3 (section 3.5.1).
- step response (sections 3.4.3, 3.6): ``mcv_rig_step.yaml``, the PVG stepped 0 -> 100 % and 0 -> 50 %;
  rise time, first peak and settling of p3 (:func:`step_metrics`).

The crack settings are table 3.2's, read from ``mcv_vf250_crack.csv``; the measured steady points from
``mcv_vf250_multistep.csv`` (both in ``../shared/data``); the thesis's own Simulink results
(``thesis_sim_multistep.csv``) are compared too, for reference.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vphs_blocks import thesis_data

ROOT = Path(__file__).resolve().parents[1]
RIG = ROOT / "netlists" / "rig"
DATA = thesis_data.DATA
MULTISTEP_NETLIST = RIG / "mcv_rig_multistep.yaml"
CRACK_NETLIST = RIG / "mcv_rig_crack.yaml"
STEP_NETLIST = RIG / "mcv_rig_step.yaml"
MEASURED_MULTISTEP = DATA / "mcv_vf250_multistep.csv"
MEASURED_CRACK = DATA / "mcv_vf250_crack.csv"
THESIS_MULTISTEP = DATA / "thesis_sim_multistep.csv"

BAR = 1e5
LPM = 1e-3 / 60.0  # 1 l/min in m^3/s
HEADER = ["setting", "p1 [bar]", "p2 [bar]", "p3 [bar]", "Q [l/min]"]


class NotSettled(RuntimeError):
    """A steady-state run whose pressures still move at the longest allowed run."""


# ---- the data files ---------------------------------------------------------------------------------------
def crack_settings(path: str | Path = MEASURED_CRACK) -> dict[str, float]:
    """Table 3.2: setting label -> crack pressure pcr [Pa] (the column ``crack [bar]``)."""
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(line for line in handle if not line.lstrip().startswith("#")))
    return {row["setting"].strip(): float(row["crack [bar]"]) * BAR for row in rows}


def measured_points(path: str | Path = MEASURED_MULTISTEP):
    """The steady points of a multistep file: a :class:`blocks.datafile.Table` (SI, labels = setting)."""
    from blocks.datafile import read_table

    return read_table(path)


# ---- multistep ----------------------------------------------------------------------------------------------
@dataclass
class SteadyPoint:
    setting: str
    p1: float  # Pa
    p2: float
    p3: float
    Q: float  # m^3/s, the flow meter's reading
    t_end: float  # s, the run that settled
    spread: float  # Pa, the largest peak-to-peak of p1, p2, p3 over the last window


def steady_point(circuit, overrides: dict, setting: str = "", t_end: float = 3.0, window: float = 0.2,
                 tol: float = 1e-3 * BAR, t_max: float = 24.0) -> SteadyPoint:
    """Run until p1, p2 and p3 vary by less than ``tol`` [Pa] over the last ``window`` (fraction) of the run,
    doubling the run up to ``t_max`` [s]; the values at the end of the settled run."""
    while True:
        result = circuit.simulate(overrides, settings=circuit.settings.with_(t_end=t_end))
        n = len(result.t)
        tail = slice(int((1.0 - window) * n), n)
        spread = max(float(np.ptp(result[name][tail])) for name in ("p1", "p2", "p3"))
        if spread < tol:
            return SteadyPoint(setting, result["p1"][-1], result["p2"][-1], result["p3"][-1], result["Q"][-1],
                               t_end, spread)
        if t_end * 2 > t_max:
            raise NotSettled(f"setting {setting} ({', '.join(f'{k} = {v:.6g}' for k, v in overrides.items())}): "
                             f"p1, p2, p3 still vary by {spread / BAR:.3g} bar over the last {window:.0%} of a "
                             f"{t_end:g} s run")
        t_end *= 2


def run_multistep(flow_force: float = 1.0, netlist: str | Path = MULTISTEP_NETLIST,
                  measured: str | Path = MEASURED_MULTISTEP, crack: str | Path = MEASURED_CRACK,
                  **settle) -> list[SteadyPoint]:
    """Every measured point of ``measured`` as a steady-state run with its Q, p2 and setting's p_crack."""
    from blocks.circuit import Circuit

    circuit = Circuit.from_file(netlist)
    table = measured_points(measured)
    pcr = crack_settings(crack)
    points = []
    for k, setting in enumerate(table.labels):
        overrides = {"Q": float(table.columns["Q"][k]), "p2": float(table.columns["p2"][k]),
                     "p_crack": pcr[setting], "flow_force": float(flow_force)}
        points.append(steady_point(circuit, overrides, setting, **settle))
    return points


def multistep_csv_text(points: list[SteadyPoint], note: str = "") -> str:
    lines = ["# Simulated steady points of the MCV test rig (netlists/rig/mcv_rig_multistep.yaml, "
             "python -m vphs_blocks.rig)."]
    if note:
        lines.append(f"# {note}")
    lines.append(",".join(HEADER))
    for p in points:
        lines.append(f"{p.setting},{p.p1 / BAR:.6f},{p.p2 / BAR:.6f},{p.p3 / BAR:.6f},{p.Q / LPM:.6f}")
    return "\n".join(lines) + "\n"


def write_multistep_csv(points: list[SteadyPoint], path: str | Path, note: str = "") -> None:
    from blocks.result import atomic_write_text

    atomic_write_text(Path(path), multistep_csv_text(points, note))


def point_errors(points: list[SteadyPoint], reference: str | Path = MEASURED_MULTISTEP) -> dict[str, np.ndarray]:
    """Simulated minus reference [bar] of p1, p2, p3 and Q, point by point (the files' rows must match:
    same settings in the same order)."""
    table = measured_points(reference)
    if list(table.labels) != [p.setting for p in points]:
        raise ValueError(f"{reference}: its settings {table.labels} do not match the simulated points")
    sim = {"p1": [p.p1 for p in points], "p2": [p.p2 for p in points], "p3": [p.p3 for p in points],
           "Q": [p.Q for p in points]}
    scale = {"p1": BAR, "p2": BAR, "p3": BAR, "Q": LPM}
    return {name: (np.array(values) - table.columns[name]) / scale[name] for name, values in sim.items()}


def rmse(errors: np.ndarray) -> float:
    return math.sqrt(float(np.mean(np.square(errors))))


# ---- crack pressure -----------------------------------------------------------------------------------------
def crack_pressure_eq_3_2(pv1: float, pv2: float, pc: float, alpha: float) -> float:
    """Eq. 3.2: pcr = pc*(alpha + 2) - pv1 - pv2*(alpha + 1) (u = 0, spool pieces in contact, equal drops
    over the two check valves, pt - pv2 = pv1 - pc)."""
    return pc * (alpha + 2.0) - pv1 - pv2 * (alpha + 1.0)


def crack_reading(result, alpha: float, q_visible: float = 0.05 * LPM, q_upper: float = 0.5 * LPM) -> dict:
    """Pressures averaged over the samples in which the flow through the valve (``q_out``) lies in
    [q_visible, q_upper], and eq. 3.2 applied to them (SI)."""
    q = result["q_out"]
    chosen = (q >= q_visible) & (q <= q_upper)
    if chosen.sum() < 10:
        raise ValueError(f"only {int(chosen.sum())} samples with {q_visible / LPM:g} <= q_out <= "
                         f"{q_upper / LPM:g} l/min: ramp more slowly or log more often")
    mean = {name: float(np.mean(result[name][chosen])) for name in ("p1", "pv1", "p2", "p3")}
    return mean | {"pcr": crack_pressure_eq_3_2(mean["pv1"], mean["p2"], mean["p3"], alpha),
                   "samples": int(chosen.sum())}


def run_crack(netlist: str | Path = CRACK_NETLIST, crack: str | Path = MEASURED_CRACK, **overrides) -> dict:
    """Setting -> crack reading (SI) of the crack-pressure rig at table 3.2's settings."""
    from blocks.circuit import Circuit

    circuit = Circuit.from_file(netlist)
    readings = {}
    for setting, pcr in crack_settings(crack).items():
        values = {"p_crack": pcr} | overrides
        result = circuit.simulate(values)
        alpha = circuit.vectors(values).values["alpha"]
        readings[setting] = crack_reading(result, alpha) | {"p_crack": pcr, "warnings": result.warnings}
    return readings


# ---- step response ------------------------------------------------------------------------------------------
def step_metrics(t: np.ndarray, p: np.ndarray, t_step: float, band: float = 0.02, tail: float = 0.1) -> dict:
    """Rise time, first peak and settling of a pressure response to a step at ``t_step``.

    p_end   the settled value: the mean over the last ``tail`` (fraction) of the run
    p0      the value at the step
    rise    the time from the first crossing of p0 + 10 % to the first crossing of p0 + 90 % of (p_end - p0)
    peak    the first local maximum after the first crossing of p_end: its value and time after the step
    settle  the time after the step from which |p - p_end| stays within band*|p_end - p0| to the end
    """
    after = t >= t_step
    t, p = t[after], p[after]
    p0 = float(p[0])
    n_tail = max(2, int(tail * len(t)))
    p_end = float(np.mean(p[-n_tail:]))
    span = p_end - p0
    if span <= 0:
        raise ValueError(f"the response does not rise: settled value {p_end:g} <= value at the step {p0:g}")

    def first(mask):
        idx = np.flatnonzero(mask)
        return int(idx[0]) if idx.size else None

    k10, k90, k_cross = first(p >= p0 + 0.1 * span), first(p >= p0 + 0.9 * span), first(p >= p_end)
    if k10 is None or k90 is None or k_cross is None:
        raise ValueError("the response never reaches 90 % of its settled value")
    rise = float(t[k90] - t[k10])
    k_peak = None
    for k in range(k_cross, len(p) - 1):
        if p[k + 1] < p[k]:
            k_peak = k
            break
    outside = np.flatnonzero(np.abs(p - p_end) > band * abs(span))
    settled_from = int(outside[-1]) + 1 if outside.size else 0
    return {
        "p0": p0, "p_end": p_end, "rise": rise,
        "t_peak": float(t[k_peak] - t_step) if k_peak is not None else math.nan,
        "p_peak": float(p[k_peak]) if k_peak is not None else math.nan,
        "settle": float(t[settled_from] - t_step) if settled_from < len(t) else math.nan,
        "t_run": float(t[-1] - t_step),
    }


def run_step(netlist: str | Path = STEP_NETLIST, crack: str | Path = MEASURED_CRACK,
             steps: tuple[float, ...] = (1.0, 0.5), signal: str = "p3", **overrides) -> dict:
    """(setting, u_step) -> step metrics of ``signal`` (SI) at table 3.2's settings."""
    from blocks.circuit import Circuit

    circuit = Circuit.from_file(netlist)
    metrics = {}
    for setting, pcr in crack_settings(crack).items():
        for u in steps:
            values = {"p_crack": pcr, "u_step": u} | overrides
            result = circuit.simulate(values)
            t_step = circuit.vectors(values).values["t_step"]
            metrics[(setting, u)] = step_metrics(result.t, result[signal], t_step) | {"warnings": result.warnings}
    return metrics


# ---- the command --------------------------------------------------------------------------------------------
def _rmse_lines(errors: dict[str, np.ndarray], labels: list[str], names=("p1", "p3")) -> list[str]:
    groups = list(dict.fromkeys(labels))
    lines = []
    for name in names:
        e = errors[name]
        per = ", ".join(f"setting {g} {rmse(e[[i for i, lab in enumerate(labels) if lab == g]]):.2f}"
                        for g in groups)
        lines.append(f"  {name}: RMSE {rmse(e):.2f} bar, mean {np.mean(e):+.2f}, max |e| "
                     f"{np.max(np.abs(e)):.2f}  ({per})")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m vphs_blocks.rig", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default="out/rig_multistep.csv", help="the multistep results CSV")
    parser.add_argument("--flow-force", type=float, default=1.0, help="the MCV's flow_force (1: eq. 3.13 on)")
    parser.add_argument("--skip-crack", action="store_true")
    parser.add_argument("--skip-step", action="store_true")
    args = parser.parse_args(argv)

    thesis_data.require(MEASURED_MULTISTEP, MEASURED_CRACK, THESIS_MULTISTEP)
    points = run_multistep(args.flow_force)
    write_multistep_csv(points, args.output, note=f"flow_force = {args.flow_force:g}")
    labels = [p.setting for p in points]
    print(f"multistep: {len(points)} steady points (flow_force = {args.flow_force:g}), wrote {args.output}; "
          f"longest run {max(p.t_end for p in points):g} s, largest final spread "
          f"{max(p.spread for p in points) / BAR:.2g} bar")
    print(" against the measurements (simulated - measured):")
    for line in _rmse_lines(point_errors(points), labels, ("p1", "p2", "p3")):
        print(line)
    thesis = measured_points(THESIS_MULTISTEP)
    table = measured_points(MEASURED_MULTISTEP)
    print(" the thesis's Simulink model against the same measurements:")
    for name in ("p1", "p3"):
        print(f"  {name}: RMSE {rmse((thesis.columns[name] - table.columns[name]) / BAR):.2f} bar")

    if not args.skip_crack:
        print("crack pressure (eq. 3.2 on the pressures averaged from 0.05 to 0.5 l/min through the valve):")
        for setting, r in run_crack(flow_force=args.flow_force).items():
            print(f"  setting {setting}: p1 {r['p1'] / BAR:.2f}, pv1 {r['pv1'] / BAR:.2f}, pv2 {r['p2'] / BAR:.2f}, "
                  f"pc {r['p3'] / BAR:.2f} bar -> pcr {r['pcr'] / BAR:.2f} bar (table 3.2: "
                  f"{r['p_crack'] / BAR:.1f}, error {(r['pcr'] - r['p_crack']) / BAR:+.2f})")
    if not args.skip_step:
        print("step response of p3 (PVG 0 -> 100 % and 0 -> 50 %):")
        for (setting, u), m in run_step(flow_force=args.flow_force).items():
            print(f"  setting {setting}, {u:.0%}: settles at {m['p_end'] / BAR:.1f} bar; rise (10-90 %) "
                  f"{m['rise'] * 1e3:.1f} ms; first peak {m['p_peak'] / BAR:.1f} bar at {m['t_peak'] * 1e3:.1f} ms; "
                  f"settled (2 %) after {m['settle'] * 1e3:.0f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(thesis_data.run(main))
