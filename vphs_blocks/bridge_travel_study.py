"""Thesis chapter 4 reproduced: the bridge-travel study's tables and plots, from the jobs' outputs (not a block).

    python -m vphs_blocks.bridge_travel_study report  [--out out/bridge_travel] [--img docs/img]
    python -m vphs_blocks.bridge_travel_study seeds   [--seeds 4] JOB ...
    python -m vphs_blocks.bridge_travel_study corners [--out out/bridge_travel] [--img docs/img]

``report`` reads what ``vphs optimise`` / ``vphs sweep`` wrote for the jobs
``netlists/jobs/bridge_travel_*.yaml`` (their ``best.json`` and ``sweep/sweep.csv`` under ``--out``). It
prints the study's tables in markdown, each beside the thesis's own (``../shared/data/thesis_*.csv``),
and draws the figures in ``--img``:
  - ``bridge_travel_controllers.png``: C_pos and the largest position error per load case, regular
    against modified controller (thesis figs. 4.10 and 4.12), and the 7.5 t position error, velocity
    error and motor inlet pressure of both best designs over time (figs. 4.10 and 4.11);
  - ``bridge_travel_spool.png``: C_pos and the largest position error against the spool frequency, per
    load case (fig. 4.15);
  - ``bridge_travel_mcv.png``: C_pos and C_vib over pilot ratio x spring stiffness (the C3 job's sweep),
    with the C1, C2 and C3 optima marked (fig. 4.16);
  - ``bridge_travel_robustness.png`` (if ``--out``/robustness.csv exists, from
    ``python -m vphs_blocks.complex_robustness -o ...``): table F.1's x and y, ours against the thesis's.
``seeds`` reruns optimisation jobs with seeds 1..N (into ``--out``/seeds/<job>_<seed>) and prints the best
cost and design of each run: how much the Complex method's answer depends on its seed.
``corners`` re-evaluates the table-4.4 designs' C_vib (eq. 4.2) with the high-pass corner at 30, 50, 100
and 200 rad/s: how much the vibration trend depends on the corner, which the thesis does not give; and
draws their motor pressures in ``--img``/bridge_travel_mcv_pressures.png (fig. 4.17).

Every cost is read as the jobs define it: C_pos = 50*pos + vel (eq. 4.1, mm and mm/s), C_vib = 3e-8*vib
(eq. 4.2, Pa), where pos, vel and vib are the jobs' logged terms (int e_pos^2 dt, int e_vel^2 dt,
int p_high^2 dt).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import shutil
import sys
from pathlib import Path

import numpy as np
import yaml

from vphs_blocks import thesis_data

ROOT = Path(__file__).resolve().parents[1]
JOBS = ROOT / "netlists" / "jobs"
DATA = thesis_data.DATA
LOADS = (("0t", 0.0), ("7t5", 7500.0), ("15t", 15000.0))
FRICTION = (("regular_7t5", 0.0), ("friction_cd0p01", 0.01), ("friction_cd0p1", 0.1), ("friction_cd1", 1.0))
C_VIB = 3e-8  # eq. 4.2
BAR = 1e5


# ---- reading the jobs' outputs ---------------------------------------------------------------------------
def c_pos(terms: dict) -> float:
    return 50.0 * terms["pos"] + terms["vel"]


def c_vib(terms: dict) -> float:
    return C_VIB * terms["vib"]


def read_best(out: Path, name: str) -> dict:
    """An optimisation job's best design: {"parameters", "terms", "cost", "evaluation"} (one load case)."""
    path = out / name / "best.json"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: run 'vphs optimise netlists/jobs/bridge_travel_{name}.yaml' first")
    best = json.loads(path.read_text())
    (case,) = best["cases"].values()
    return {"parameters": best["parameters"], "terms": case["terms"], "cost": best["cost"],
            "evaluation": best["evaluation"]}


def read_sweep(out: Path, name: str) -> list[dict]:
    """A sweep job's points: the column names without their units, numbers as floats; the swept parameters
    in SI (sweep.csv gives them in the unit the job wrote), the cost terms in their columns' units as the
    jobs define them (mm, mm/s, Pa)."""
    from blocks.units import parse_unit

    path = out / name / "sweep" / "sweep.csv"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: run 'vphs sweep netlists/jobs/bridge_travel_{name}.yaml' first")
    swept = set(yaml.safe_load((JOBS / f"bridge_travel_{name}.yaml").read_text())["sweep"]["parameters"])
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    out_rows = []
    for row in rows:
        clean = {}
        for key, value in row.items():
            name_, _, unit = key.partition(" [")
            try:
                clean[name_] = float(value)
            except (TypeError, ValueError):
                clean[name_] = value
                continue
            if name_ in swept and unit:
                clean[name_] *= parse_unit(unit.rstrip("]")).factor
        out_rows.append(clean)
    return out_rows


def thesis_table(name: str) -> list[dict]:
    with open(DATA / name, newline="") as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


def _g(v: float, digits: int = 3) -> str:
    return f"{v:.{digits}g}"


# ---- the tables ------------------------------------------------------------------------------------------
def controller_table(out: Path) -> tuple[str, dict]:
    thesis = {(float(r["load_kg"]), r["controller"]): r for r in thesis_table("thesis_controller_opt.csv")}
    lines = ["| load | controller | Kv [s/m] | Kp [1/m] | Ki [1/(m*s)] | Kvp [s/m] | C_pos | max pos. error [mm] | "
             "C_vib | thesis C_pos | thesis max error [mm] |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    data = {}
    for key, load in LOADS:
        for ctrl in ("regular", "modified"):
            b = read_best(out, f"{ctrl}_{key}")
            p, t = b["parameters"], b["terms"]
            data[(key, ctrl)] = b
            th = thesis[(load, ctrl)]
            lines.append(f"| {load / 1000:g} t | {ctrl} | {_g(p['Kv'])} | {_g(p['Kp'])} | {_g(p['Ki'])} | "
                         f"{_g(p.get('Kvp', 0.0))} | {c_pos(t):.0f} | {t['max_pos']:.2f} | {c_vib(t):.0f} | "
                         f"{th['Cpos']} | {th['max_pos_error [mm]']} |")
    lines += ["", "| load | C_pos modified / regular | max error modified / regular | thesis C_pos ratio | "
                  "thesis max-error ratio |", "|---|---|---|---|---|"]
    for key, load in LOADS:
        r, m = data[(key, "regular")]["terms"], data[(key, "modified")]["terms"]
        tr, tm = thesis[(load, "regular")], thesis[(load, "modified")]
        lines.append(f"| {load / 1000:g} t | {c_pos(m) / c_pos(r):.2f} | {m['max_pos'] / r['max_pos']:.2f} | "
                     f"{float(tm['Cpos']) / float(tr['Cpos']):.2f} | "
                     f"{float(tm['max_pos_error [mm]']) / float(tr['max_pos_error [mm]']):.2f} |")
    return "\n".join(lines), data


def friction_table(out: Path) -> str:
    thesis = {float(r["Cd"]): r for r in thesis_table("thesis_friction_opt.csv")}
    lines = ["| case | Cd [N·m·s/rad] | Kv [s/m] | Kp [1/m] | Ki [1/(m*s)] | C_vib | C_pos | max pos. error [mm] | "
             "thesis Kv, Kp, Ki (x1000) | thesis C_vib | thesis C_pos |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for k, (name, cd) in enumerate(FRICTION, 1):
        b = read_best(out, name)
        p, t = b["parameters"], b["terms"]
        th = thesis[cd]
        lines.append(f"| {k} | {cd:g} | {_g(p['Kv'])} | {_g(p['Kp'])} | {_g(p['Ki'])} | {c_vib(t):.0f} | "
                     f"{c_pos(t):.0f} | {t['max_pos']:.2f} | {float(th['Kv']) * 1e3:.3g}, {float(th['Kp']) * 1e3:.3g}, "
                     f"{float(th['Ki']) * 1e3:.3g} | {th['Cvib']} | {th['Cpos']} |")
    return "\n".join(lines)


def spool_table(out: Path) -> tuple[str, dict]:
    sweeps = {key: read_sweep(out, f"spool_{key}") for key, _ in LOADS}
    wns = [row["wn_spool"] for row in sweeps["7t5"]]
    lines = ["| wn_spool [rad/s] | " + " | ".join(f"C_pos {load / 1000:g} t | max err. {load / 1000:g} t [mm]"
                                                   for _, load in LOADS) + " |",
             "|---|" + "---|---|" * len(LOADS)]
    for i, wn in enumerate(wns):
        cells = []
        for key, _ in LOADS:
            row = sweeps[key][i]
            cells.append(f"{c_pos(row):.0f} | {row['max_pos']:.2f}")
        lines.append(f"| {wn:g} | " + " | ".join(cells) + " |")
    lines += ["", "| load | C_pos: 52.6 -> 75 rad/s | max err.: 52.6 -> 75 | C_pos: 52.6 -> 100 | max err.: 52.6 -> 100 | "
                  "C_pos: 100 -> 200 | max err.: 100 -> 200 |", "|---|---|---|---|---|---|---|"]
    for key, load in LOADS:
        at = {row["wn_spool"]: row for row in sweeps[key]}

        def change(a, b, f):
            return f"{100 * (f(at[b]) / f(at[a]) - 1):+.0f} %"

        mx = lambda r: r["max_pos"]  # noqa: E731
        lines.append(f"| {load / 1000:g} t | {change(52.6, 75, c_pos)} | {change(52.6, 75, mx)} | {change(52.6, 100, c_pos)} | "
                     f"{change(52.6, 100, mx)} | {change(100, 200, c_pos)} | {change(100, 200, mx)} |")
    return "\n".join(lines), sweeps


def mcv_table(out: Path) -> tuple[str, dict]:
    thesis = {r["cost_function"]: r for r in thesis_table("thesis_mcv_opt.csv")}
    grid = read_sweep(out, "mcv_c3")
    base = next(r for r in grid if abs(r["alpha"] - 2.8) < 1e-9 and abs(r["Ks"] - 895 * BAR) < 1.0)
    rows = {"none": (2.8, 895 * BAR, base)}
    for key in ("c1", "c2", "c3"):
        b = read_best(out, f"mcv_{key}")
        rows[key] = (b["parameters"]["alpha"], b["parameters"]["Ks"], b["terms"])
    lines = ["| cost function | pilot ratio | Ks [bar/unit] | C_vib | C_pos | max pos. error [mm] | thesis P | thesis Ks | "
             "thesis C_vib | thesis C_pos |", "|---|---|---|---|---|---|---|---|---|---|"]
    for key, (alpha, ks, t) in rows.items():
        th = thesis["none" if key == "none" else key.upper()]
        label = "none (case 3)" if key == "none" else key.upper()
        lines.append(f"| {label} | {alpha:.2f} | {ks / BAR:.0f} | {c_vib(t):.0f} | {c_pos(t):.0f} | {t['max_pos']:.2f} | "
                     f"{th['P']} | {th['Ks']} | {th['Cvib']} | {th['Cpos']} |")
    return "\n".join(lines), {"grid": grid, "rows": rows}


# ---- the figures -----------------------------------------------------------------------------------------
def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path) -> None:
    from blocks.result import atomic_write_figure

    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_figure(fig, path)


def resimulate(job_name: str, parameters: dict):
    """The run of a design of a job (its single load case), with the job's fixed values."""
    from blocks.optimise.evaluate import case_overrides, circuit_for
    from blocks.optimise.job import load_job

    job = load_job(JOBS / f"bridge_travel_{job_name}.yaml")
    spec = job.spec()
    return circuit_for(job.netlist).simulate(case_overrides(spec, parameters, spec.cases[0]))


def controller_figure(data: dict, path: Path) -> None:
    plt = _plt()
    thesis = {(float(r["load_kg"]), r["controller"]): r for r in thesis_table("thesis_controller_opt.csv")}
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
    width = 0.2
    x = np.arange(len(LOADS))
    for k, ctrl in enumerate(("regular", "modified")):
        ours = [c_pos(data[(key, ctrl)]["terms"]) for key, _ in LOADS]
        theirs = [float(thesis[(load, ctrl)]["Cpos"]) for _, load in LOADS]
        axes[0, 0].bar(x + (2 * k - 1.5) * width, ours, width, color=f"C{k}", label=f"{ctrl} (this model)")
        axes[0, 0].bar(x + (2 * k - 0.5) * width, theirs, width, color=f"C{k}", alpha=0.4, hatch="//",
                       label=f"{ctrl} (thesis)")
        ours = [data[(key, ctrl)]["terms"]["max_pos"] for key, _ in LOADS]
        theirs = [float(thesis[(load, ctrl)]["max_pos_error [mm]"]) for _, load in LOADS]
        axes[0, 1].bar(x + (2 * k - 1.5) * width, ours, width, color=f"C{k}", label=f"{ctrl} (this model)")
        axes[0, 1].bar(x + (2 * k - 0.5) * width, theirs, width, color=f"C{k}", alpha=0.4, hatch="//",
                       label=f"{ctrl} (thesis)")
    for ax, title in ((axes[0, 0], "C_pos (eq. 4.1) of the optimal controller"),
                      (axes[0, 1], "largest position error [mm]")):
        ax.set_xticks(x, [f"{load / 1000:g} t" for _, load in LOADS])
        ax.set_title(title)
        ax.grid(True, axis="y", alpha=0.3)
        ax.legend(fontsize="small")
    for k, ctrl in enumerate(("regular", "modified")):
        r = resimulate(f"{ctrl}_7t5", data[("7t5", ctrl)]["parameters"])
        axes[1, 0].plot(r.t, (r["x"] - r["x_ref"]) * 1e3, color=f"C{k}", label=f"{ctrl}: x - x_ref [mm]")
        axes[1, 0].plot(r.t, (r["v"] - r["v_ref"]) * 1e3 / 20, color=f"C{k}", ls=":", label=f"{ctrl}: (v - v_ref)/20 [mm/s]")
        axes[1, 1].plot(r.t, r["pCA"] / BAR, color=f"C{k}", label=f"{ctrl}: motor inlet pCA")
    axes[1, 0].set_title("7.5 t: errors of the optimal controllers")
    axes[1, 1].set_title("7.5 t: motor inlet pressure [bar] (C_vib's signal)")
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
    fig.tight_layout()
    _save(fig, path)
    plt.close(fig)


def spool_figure(sweeps: dict, path: Path) -> None:
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for k, (key, load) in enumerate(LOADS):
        rows = sweeps[key]
        wn = [r["wn_spool"] for r in rows]
        axes[0].plot(wn, [c_pos(r) for r in rows], "o-", ms=3, color=f"C{k}", label=f"{load / 1000:g} t")
        axes[1].plot(wn, [r["max_pos"] for r in rows], "o-", ms=3, color=f"C{k}", label=f"{load / 1000:g} t")
    for ax, title in ((axes[0], "C_pos (eq. 4.1)"), (axes[1], "largest position error [mm]")):
        ax.axvline(52.6, color="0.5", ls=":", lw=1)
        ax.set_xlabel("servo-valve spool natural frequency [rad/s]")
        ax.set_title(title + ", regular controller", fontsize="medium")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
        ax.set_ylim(bottom=0)
    fig.tight_layout()
    _save(fig, path)
    plt.close(fig)


def mcv_figure(mcv: dict, path: Path) -> None:
    plt = _plt()
    grid = mcv["grid"]
    alphas = sorted({r["alpha"] for r in grid})
    kss = sorted({r["Ks"] for r in grid})
    at = {(r["alpha"], r["Ks"]): r for r in grid}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, (title, f) in zip(axes, (("log10 C_pos", c_pos), ("log10 C_vib", c_vib))):
        z = np.log10(np.array([[f(at[(a, k)]) for a in alphas] for k in kss]))
        mesh = ax.pcolormesh(alphas, [k / BAR for k in kss], z, shading="nearest", cmap="viridis")
        fig.colorbar(mesh, ax=ax)
        for key, (alpha, ks, _) in mcv["rows"].items():
            ax.plot(alpha, ks / BAR, "o" if key == "none" else "*", ms=9, mec="k",
                    mfc="w" if key == "none" else "C3")
            ax.annotate("case 3" if key == "none" else key.upper(), (alpha, ks / BAR),
                        xytext=(6, -12) if key == "c3" else (6, 4),
                        textcoords="offset points", color="w", fontsize="small")
        ax.set_xlabel("pilot ratio alpha")
        ax.set_ylabel("Ks [bar/unit]")
        ax.set_title(f"{title} over the C3 job's sweep grid")
    fig.tight_layout()
    _save(fig, path)
    plt.close(fig)


def robustness_figure(rows: list[dict], path: Path) -> None:
    plt = _plt()
    fig, ax = plt.subplots(figsize=(11, 4))
    tests = np.array([int(r["test"]) for r in rows])
    w = 0.38
    ax.bar(tests - w / 2, [float(r["x"]) for r in rows], w, color="C0", label="x (< 0.4 %), this study")
    ax.bar(tests - w / 2, [float(r["y"]) for r in rows], w, bottom=[float(r["x"]) for r in rows], color="C1",
           label="y (0.4 ... 2 %), this study")
    ax.bar(tests + w / 2, [float(r["thesis x"]) for r in rows], w, color="C0", alpha=0.4, hatch="//",
           label="x, thesis")
    ax.bar(tests + w / 2, [float(r["thesis y"]) for r in rows], w, bottom=[float(r["thesis x"]) for r in rows],
           color="C1", alpha=0.4, hatch="//", label="y, thesis")
    ax.set_xticks(tests, [f"{r['test']}\nC{r['C']} K{r['K']}\n±{r['B [%]']}%" for r in rows], fontsize=7)
    ax.set_ylabel("runs of 100")
    ax.set_title("Table F.1: Complex runs ending within 0.4 % (x) and 0.4-2 % (y) of the best error")
    ax.set_ylim(0, 125)
    ax.set_yticks([0, 20, 40, 60, 80, 100])
    ax.legend(fontsize="small", ncol=4, loc="upper center")
    ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    _save(fig, path)
    plt.close(fig)


# ---- commands --------------------------------------------------------------------------------------------
def cmd_report(out: Path, img: Path) -> int:
    text, data = controller_table(out)
    print("## Controllers per load case (table 4.2)\n\n" + text + "\n")
    print("## Viscous friction, 7.5 t (table 4.3)\n\n" + friction_table(out) + "\n")
    text, sweeps = spool_table(out)
    print("## Spool frequency (fig. 4.15)\n\n" + text + "\n")
    text, mcv = mcv_table(out)
    print("## MCV pilot ratio and spring (table 4.4)\n\n" + text + "\n")
    controller_figure(data, img / "bridge_travel_controllers.png")
    spool_figure(sweeps, img / "bridge_travel_spool.png")
    mcv_figure(mcv, img / "bridge_travel_mcv.png")
    written = ["bridge_travel_controllers.png", "bridge_travel_spool.png", "bridge_travel_mcv.png"]
    robustness = out / "robustness.csv"
    if robustness.is_file():
        with open(robustness, newline="") as handle:
            robustness_figure(list(csv.DictReader(handle)), img / "bridge_travel_robustness.png")
        written.append("bridge_travel_robustness.png")
    print(f"figures: {', '.join(str(img / w) for w in written)}", file=sys.stderr)
    return 0


def cmd_seeds(jobs: list[str], seeds: int, out: Path) -> int:
    from blocks.optimise.job import load_job
    from blocks.optimise.runner import run_optimise

    print("| job | seed | best cost | C_pos | max error [mm] | design | stopped | evaluations |")
    print("|---|---|---|---|---|---|---|---|")
    for name in jobs:
        path = Path(name)
        if not path.is_file():
            path = JOBS / f"{name}.yaml"
        for seed in range(1, seeds + 1):
            job = load_job(path)
            folder = out / "seeds" / f"{job.name}_{seed}"
            shutil.rmtree(folder, ignore_errors=True)
            job = dataclasses.replace(job, seed=seed, output=folder)
            s = run_optimise(job, workers=None, quiet=True, report=False)
            (case,) = s.best["cases"].values()
            design = ", ".join(f"{k} {v / BAR:.4g} bar" if k == "Ks" else f"{k} {v:.4g}"
                               for k, v in s.best["parameters"].items())
            print(f"| {job.name} | {seed} | {s.best['cost']:.1f} | {c_pos(case['terms']):.0f} | "
                  f"{case['terms']['max_pos']:.2f} | {design} | {s.reason} | {len(s.records)} |", flush=True)
    return 0


def cmd_corners(out: Path, img: Path, corners=(30.0, 50.0, 100.0, 200.0)) -> int:
    from blocks.optimise.costs import Term, evaluate_term, highpass

    _, mcv = mcv_table(out)
    plt = _plt()
    fig, axes = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
    print("| design | pilot ratio | Ks [bar/unit] | " + " | ".join(f"C_vib, corner {c:g} rad/s" for c in corners) + " |")
    print("|---|---|---|" + "---|" * len(corners))
    for k, (key, (alpha, ks, _)) in enumerate(mcv["rows"].items()):
        r = resimulate("mcv_c3", {"alpha": alpha, "Ks": ks})
        values = [C_VIB * evaluate_term(Term("vib", "hp_ise", "pCA", wn=c, zeta=0.7071), r.t, r) for c in corners]
        label = "none (case 3)" if key == "none" else key.upper()
        print(f"| {label} | {alpha:.2f} | {ks / BAR:.0f} | " + " | ".join(f"{v:.0f}" for v in values) + " |")
        name = f"{label}: alpha {alpha:.2f}, Ks {ks / BAR:.0f} bar"
        axes[0].plot(r.t, r["pCA"] / BAR, color=f"C{k}", lw=1, label=name)
        axes[1].plot(r.t, r["pCB"] / BAR, color=f"C{k}", lw=1, label=name)
        axes[2].plot(r.t, highpass(r.t, r["pCA"], 100.0, 0.7071) / BAR, color=f"C{k}", lw=1, label=name)
    for ax, title in zip(axes, ("motor inlet pCA [bar]", "motor outlet pCB [bar] (held by the MCV)",
                                "pCA through the 100 rad/s high-pass of C_vib [bar]")):
        ax.set_title(title, fontsize="medium")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize="small")
    axes[2].set_xlabel("t [s]")
    fig.tight_layout()
    _save(fig, img / "bridge_travel_mcv_pressures.png")
    plt.close(fig)
    print(f"figure: {img / 'bridge_travel_mcv_pressures.png'}", file=sys.stderr)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m vphs_blocks.bridge_travel_study", description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("report", help="tables (markdown, stdout) and figures from the jobs' outputs")
    p.add_argument("--out", type=Path, default=Path("out/bridge_travel"))
    p.add_argument("--img", type=Path, default=ROOT / "docs" / "img")
    p = sub.add_parser("seeds", help="rerun optimisation jobs with seeds 1..N")
    p.add_argument("jobs", nargs="+", help="job files, or names under netlists/jobs (without .yaml)")
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--out", type=Path, default=Path("out/bridge_travel"))
    p = sub.add_parser("corners", help="C_vib of the table-4.4 designs at other high-pass corners, their pressures")
    p.add_argument("--out", type=Path, default=Path("out/bridge_travel"))
    p.add_argument("--img", type=Path, default=ROOT / "docs" / "img")
    args = ap.parse_args(argv)
    try:
        if args.command == "report":
            return cmd_report(args.out, args.img)
        if args.command == "seeds":
            return cmd_seeds(args.jobs, args.seeds, args.out)
        return cmd_corners(args.out, args.img)
    except FileNotFoundError as exc:
        print(f"vphs_blocks.bridge_travel_study: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(thesis_data.run(main))
