"""Benchmark: a 300-evaluation Complex job on the bridge-travel drive line, 1 worker against every core.

    python bench/optimise.py [--repeats 3] [--evaluations 300]

The job is netlists/jobs/drive_line_controller.yaml (3 s of the drive line per evaluation, netlists/opt/)
with its stops switched off so that exactly N evaluations run on the method's path (the budget counts the
path; candidates evaluated ahead and discarded come on top). Printed, all measured in this one run:

1. Per evaluation: Circuit.simulate (and the solver's part of it), the cost terms, the log's
   append (write + flush; the fsync runs in a background thread, its time is shown too).
2. The same job -- the same designs, since ``candidates`` is fixed at the number of cores, so the
   batching does not depend on the workers -- with 1 worker (in this process) and with every core (this
   process and one worker process per further core, each pinned to its core; blocks/optimise/executors.py):
   the job's wall time (executor start and the evaluations; the report is not included), evaluations per
   second, the speed-up.
3. What the parallelism buys the Complex method: with ``candidates = 1`` (one evaluation at a time, the
   method as stated) and with ``candidates = cores`` (the reflection and the next retractions at once,
   Complex-RFP task prediction; same path of the complex, so the same iterations within the same N
   evaluations on the path) the wall time per iteration. The candidates evaluated ahead and not needed
   are extra simulations, so the speed-up in iterations per second is below the one in evaluations.
   Also the bound the evaluations' own times put on the speed-up (a batch lasts as long as its slowest
   design), computed from the 1-worker run's log.
4. The method as stated (candidates = 1) on a job with three load cases: the cases of a design run in
   parallel, 1 worker against every core.
Repeats alternate the configurations and the median is printed (the machine may be shared).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from blocks.optimise.costs import evaluate_term  # noqa: E402
from blocks.optimise.evaluate import case_overrides, circuit_for  # noqa: E402
from blocks.optimise.executors import cores  # noqa: E402
from blocks.optimise.job import load_job  # noqa: E402
from blocks.optimise.log import EvaluationLog  # noqa: E402
from blocks.optimise.runner import run_optimise  # noqa: E402

JOB = ROOT / "netlists" / "jobs" / "drive_line_controller.yaml"
CASES_JOB = ROOT / "netlists" / "jobs" / "drive_line_load_cases.yaml"


def _spin(n: int = 4_000_000) -> float:
    t0 = time.perf_counter()
    x = 0
    for i in range(n):
        x += i & 7
    return time.perf_counter() - t0


def machine_capacity(p: int) -> float:
    """How much faster p processes get through p copies of a pure compute loop than one process gets
    through one, right now: p on an idle machine, less when other programs share the cores."""
    import multiprocessing

    one = min(_spin() for _ in range(2))
    with multiprocessing.get_context("fork").Pool(p) as pool:
        pool.map(_spin, [1000] * p)
        t0 = time.perf_counter()
        pool.map(_spin, [4_000_000] * p)
        many = time.perf_counter() - t0
    return p * one / many


def per_evaluation(job, n: int = 100) -> dict:
    spec = job.spec()
    circuit = circuit_for(job.netlist)
    case = spec.cases[0]
    design = job.values([0.5] * len(job.free))
    overrides = case_overrides(spec, design, case)
    circuit.simulate(overrides)
    sim, solver, cost = [], [], []
    for _ in range(n):
        t0 = time.perf_counter()
        r = circuit.simulate(overrides)
        t1 = time.perf_counter()
        for term in spec.terms:
            evaluate_term(term, r.t, r)
        t2 = time.perf_counter()
        sim.append(t1 - t0), solver.append(r.seconds), cost.append(t2 - t1)
    with tempfile.TemporaryDirectory() as tmp:
        log = EvaluationLog(Path(tmp), {"type": "job", "fingerprint": "bench"})
        record = {"type": "evaluation", "index": 0, "x": [0.5] * 3, "parameters": design, "cost": 1.0,
                  "status": "ok", "cases": {"c": {"terms": {"a": 1.0, "b": 2.0}, "cost": 3.0}}}
        t0 = time.perf_counter()
        for i in range(n):
            log.append({**record, "index": i})
        append = (time.perf_counter() - t0) / n
        syncs = []
        for _ in range(20):
            t0 = time.perf_counter()
            os.fsync(log.handle.fileno())
            syncs.append(time.perf_counter() - t0)
        log.close()
    return {"simulate": statistics.median(sim), "solver": statistics.median(solver),
            "cost": statistics.median(cost), "log": append, "fsync": statistics.median(syncs), "steps": r.stats["steps"]}


def run(job, workers: int, candidates: int, evaluations: int, folder: Path):
    job = dataclasses.replace(job, output=folder, settings=dataclasses.replace(
        job.settings, max_evaluations=evaluations, tol_x=0.0, tol_f=0.0, candidates=candidates))
    shutil.rmtree(folder, ignore_errors=True)
    t0 = time.perf_counter()
    s = run_optimise(job, workers=workers, quiet=True, report=False)
    wall = time.perf_counter() - t0
    assert len(s.records) == evaluations, len(s.records)
    return wall, s


def ideal_time(records: list[dict], candidates: int, workers: int) -> float:
    """The shortest time ``workers`` could take for these evaluations, given each load case's own time (as
    measured one at a time) and the batches the method asks for (a batch ends when its slowest task does):
    tasks go to the first free worker, no overhead."""
    batches: dict[tuple, list[float]] = {}
    for r in sorted(records, key=lambda r: r["index"]):
        chunk = 0 if r["step"] == "initial" else r["n_rep"] // candidates
        batches.setdefault((r["iteration"], chunk), []).extend(c["seconds"] for c in r["cases"].values())
    total = 0.0
    for tasks in batches.values():
        free = [0.0] * workers
        for d in tasks:
            free[free.index(min(free))] += d
        total += max(free)
    return total


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--evaluations", type=int, default=300)
    args = parser.parse_args()
    n, p = args.evaluations, cores()
    job = load_job(JOB)
    print(f"machine: {p} cores, load average {', '.join(f'{x:.2f}' for x in os.getloadavg())} (before); "
          f"{p} processes on a pure compute loop run {machine_capacity(p):.2f}x as fast as one, now")
    e = per_evaluation(job)
    print(f"one evaluation of the 3 s drive line ({e['steps']} steps): simulate {e['simulate'] * 1e3:.2f} ms "
          f"(solver {e['solver'] * 1e3:.2f} ms, the rest Python in Circuit.simulate), cost terms "
          f"{e['cost'] * 1e3:.2f} ms, log append {e['log'] * 1e3:.3f} ms (its fsync, in a background thread: "
          f"{e['fsync'] * 1e3:.2f} ms)")

    tmp = Path(tempfile.mkdtemp(prefix="vphs-bench-"))
    try:
        walls, serial_summary = {1: [], p: []}, None
        phases = {1: [], p: []}
        iters = {1: [], p: []}
        for _ in range(args.repeats):
            for workers in (1, p):
                wall, s = run(job, workers, p, n, tmp / f"w{workers}")
                walls[workers].append(wall)
                phases[workers].append(s.seconds)
                if workers == 1:
                    serial_summary = s
        total = serial_summary.total  # on the path and discarded: the same for both
        print(f"\n{n}-evaluation Complex job, candidates = {p} (the same {total} designs for both, {n} on the path):")
        for workers in (1, p):
            w, ph = statistics.median(walls[workers]), statistics.median(phases[workers])
            print(f"  {workers} worker{'s' if workers > 1 else ' '}: wall {w:6.2f} s (evaluations {ph:5.2f} s), "
                  f"{total / w:6.1f} evaluations/s over the wall time, {total / ph:6.1f} over the evaluations")
        w1, wp = statistics.median(walls[1]), statistics.median(walls[p])
        ph1, php = statistics.median(phases[1]), statistics.median(phases[p])
        print(f"  speed-up with {p} workers: {w1 / wp:.2f}x over the wall time, {ph1 / php:.2f}x over the evaluations "
              f"(target >= 1.8x); {total / wp:.1f} evaluations/s (target >= 30)")
        serial_records = serial_summary.records + serial_summary.discarded
        busy = sum(r["seconds"] for r in serial_records)
        bound = ideal_time(serial_records, p, p)
        print(f"  bound from the evaluations' own times (1-worker run): {busy:.2f} s of simulation, at best "
              f"{bound:.2f} s on {p} workers in batches of {p} -> at most {busy / bound:.2f}x (a batch waits for its "
              f"slowest design; designs differ up to {max(r['seconds'] for r in serial_records) / min(r['seconds'] for r in serial_records):.0f}x "
              f"in cost)")

        for _ in range(args.repeats):
            for workers, c in ((1, 1), (p, p)):
                wall, s = run(job, workers, c, n, tmp / f"c{c}")
                iters[workers].append((wall, s.seconds, s.iterations, s.best["cost"], s.total))
        print(f"\nwhat the batching buys the method (same seed, {n} evaluations on the path each):")
        rows = {}
        for workers, c in ((1, 1), (p, p)):
            wall = statistics.median(x[0] for x in iters[workers])
            phase = statistics.median(x[1] for x in iters[workers])
            it, best, done = iters[workers][0][2:]
            rows[workers] = (wall, phase, it, done)
            print(f"  candidates {c}, {workers} worker{'s' if workers > 1 else ' '}: {it:4d} iterations, "
                  f"best cost {best:.6g}, wall {wall:5.2f} s, {1e3 * phase / it:5.2f} ms per iteration")
        (w1, ph1, it1, n1), (wp, php, itp, np_) = rows[1], rows[p]
        print(f"  iterations per second: {it1 / ph1:.1f} (one at a time) -> {itp / php:.1f} ({p} candidates on {p} "
              f"workers): {(itp / php) / (it1 / ph1):.2f}x; evaluations per iteration {n1 / it1:.2f} -> {np_ / itp:.2f}")
        cases_job = load_job(CASES_JOB)
        m = max(cases_job.settings.points or 0, 2 * len(cases_job.free), 3) * 25
        times = {1: [], p: []}
        for _ in range(args.repeats):
            for workers in (1, p):
                wall, s = run(cases_job, workers, 1, m, tmp / f"cases{workers}")
                times[workers].append((wall, s.seconds))
        print(f"\nthe method as stated (candidates 1: one design at a time), {m} evaluations of a job with "
              f"{len(cases_job.cases)} load cases ({CASES_JOB.name}): each case a task of its own")
        for workers in (1, p):
            wall, phase = (statistics.median(x[k] for x in times[workers]) for k in (0, 1))
            print(f"  {workers} worker{'s' if workers > 1 else ' '}: wall {wall:5.2f} s, {m / wall:6.1f} evaluations/s")
        w1, wp = (statistics.median(x[0] for x in times[w]) for w in (1, p))
        print(f"  speed-up: {w1 / wp:.2f}x")
        print(f"\nmachine load average after: {', '.join(f'{x:.2f}' for x in os.getloadavg())}; {p} processes on a "
              f"pure compute loop run {machine_capacity(p):.2f}x as fast as one, now (the speed-ups above cannot "
              f"exceed what the machine gives)")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
