"""Benchmark: memory over an optimisation, a long run, a sweep and a Dask batch, measured in one run.

    python bench/memory.py [--evaluations 500] [--t-end 300] [--points 2000] [--dask-points 400]

Resident memory (RSS, /proc/self/statm) and its peak (VmHWM of /proc/self/status, reset before each
measurement by writing 5 to /proc/self/clear_refs; Linux) of this one process. RSS hides what malloc
reuses from memory freed earlier, so two more measures: "heap", what glibc's malloc has handed out and
not had back (mallinfo2), and "traced peak", the most memory allocated during a measurement and not yet
freed (tracemalloc, which numpy's and numba's arrays report to). Everything runs in this process, on
the drive line: the job netlists/jobs/drive_line_controller.yaml (3 s per evaluation) and, for the long
run, netlists/examples/drive_line.yaml (6 logged signals, 7 states).

1. A worker: the optimiser's own evaluation (blocks.optimise.evaluate.evaluate_design: the circuit is
   loaded once per process, each design's parameter vector swapped in) of N random designs (warm-up),
   then of 10 N more. RSS and heap after each and the growth per 1000 evaluations; a leak is a steady
   growth. "ratio" = RSS after the 11 N / after the N: 1.00 is no growth.
   Then the job's own process: ``vphs optimise`` in this process (run_optimise, one worker, the report
   written) with its stops off, at N/5 and N evaluations on the path: peak RSS and traced peak, and the
   bytes per evaluation the job keeps (the difference of the two traced peaks over the difference of
   the evaluations: its records, which the report and --resume need) beside the bytes of an evaluation's
   line in the log. A ratio of a few is Python dicts against JSON text; a growing one would be a leak.
2. A long run: the drive line simulated for --t-end seconds (dt_out 1 ms): the peak RSS increase and
   the traced peak of Circuit.simulate, of ``vphs run -o CSV`` and of ``vphs run -o CSV --plot PNG``, each
   over the bare size of the output arrays (samples x logged signals x 8 bytes). The result holds the
   states too (the CSV is written a block of rows at a time), so a ratio of a few is expected; 50 would
   be a finding.
3. A sweep (``vphs sweep``, one worker, report written) of P/10 and of P points: peak RSS increase,
   traced peak and the bytes per point (the difference of the two traced peaks over the difference of
   the points) beside the bytes of a point's line in the log. Only the points' records are kept: the
   bytes per point must not grow with P, nor be more than a small multiple of the line.
4. A Dask batch: D designs through the Dask executor on an in-process LocalCluster (one worker thread):
   the tasks the scheduler still holds when the last result has been read, and those held in the middle
   of the batch. A finished task whose result has been read is released at once; what is held is the
   spec and the tasks not yet read, not the batch's results (a sweep is one batch of all its points).
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import dataclasses
import gc
import io
import os
import shutil
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import cli  # noqa: E402
from blocks.circuit import Circuit  # noqa: E402
from blocks.optimise.evaluate import evaluate_design  # noqa: E402
from blocks.optimise.job import load_job  # noqa: E402
from blocks.optimise.log import LOG_NAME  # noqa: E402
from blocks.optimise.runner import run_optimise, run_sweep  # noqa: E402

JOB = ROOT / "netlists" / "jobs" / "drive_line_controller.yaml"
LONG = ROOT / "netlists" / "examples" / "drive_line.yaml"
MB = 2.0 ** 20
PAGE = os.sysconf("SC_PAGE_SIZE")


def rss() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * PAGE / MB


def reset_peak() -> None:
    gc.collect()
    with open("/proc/self/clear_refs", "w") as f:  # VmHWM back to the current RSS (Linux >= 4.0)
        f.write("5")


def peak() -> float:
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmHWM")) / 1024


class _Mallinfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in
                "arena ordblks smblks hblks hblkhd usmblks fsmblks uordblks fordblks keepcost".split()]


def heap() -> float:
    """Bytes malloc has handed out and not had back (glibc >= 2.33), MB; nan elsewhere."""
    try:
        libc = ctypes.CDLL("libc.so.6")
        libc.mallinfo2.restype = _Mallinfo2
    except (OSError, AttributeError):
        return float("nan")
    m = libc.mallinfo2()
    return (m.uordblks + m.hblkhd) / MB


def measured(call) -> tuple[float, float, object]:
    """(peak RSS increase over the RSS before, MB; peak of the memory allocated during ``call()`` and not
    freed, MB (tracemalloc, which numpy's and numba's arrays report to); what ``call()`` returned)."""
    reset_peak()
    before = rss()
    tracemalloc.start(1)
    try:
        out = call()
        traced = tracemalloc.get_traced_memory()[1] / MB
    finally:
        tracemalloc.stop()
    return peak() - before, traced, out


def log_line_bytes(folder: Path) -> float:
    lines = [line for line in (folder / LOG_NAME).read_bytes().splitlines() if b'"type": "evaluation"' in line]
    return sum(len(line) + 1 for line in lines) / len(lines)


def worker(job, n: int) -> None:
    print(f"1. one worker: evaluate_design of random designs ({JOB.relative_to(ROOT)})")
    spec, rng = job.spec(), np.random.default_rng(1)

    def evaluate(count: int) -> float:
        started = time.perf_counter()
        for _ in range(count):
            evaluate_design(spec, job.values(rng.random(len(job.free))))
        return time.perf_counter() - started

    evaluate(n)
    gc.collect()
    rss1, heap1 = rss(), heap()
    seconds = evaluate(10 * n)
    gc.collect()
    rss2, heap2 = rss(), heap()
    print(f"   {'evaluations':>22s} {'RSS MB':>9s} {'heap MB':>9s}")
    print(f"   {f'{n} (warm-up)':>22s} {rss1:9.2f} {heap1:9.2f}")
    print(f"   {f'+ {10 * n}':>22s} {rss2:9.2f} {heap2:9.2f}   ({1e3 * seconds / (10 * n):.1f} ms per evaluation)")
    print(f"   growth per 1000 evaluations: RSS {1e3 * (rss2 - rss1) / (10 * n):.3f} MB, heap "
          f"{1e3 * (heap2 - heap1) / (10 * n):.4f} MB; ratio RSS after / after warm-up {rss2 / rss1:.3f}")


def optimise_job(job, n: int, folder: Path) -> None:
    def run(budget: int):
        out = folder / f"optimise_{budget}"
        shutil.rmtree(out, ignore_errors=True)
        j = dataclasses.replace(job, output=out, settings=dataclasses.replace(
            job.settings, max_evaluations=budget, tol_x=0.0, tol_f=0.0, candidates=1))
        return out, lambda: run_optimise(j, workers=1, quiet=True).total

    run(10)[1]()  # warm: the report's imports (matplotlib) are not the job's
    print(f"\n   vphs optimise in this process (1 worker, report written), stops off:")
    print(f"   {'evaluations':>22s} {'peak RSS +MB':>13s} {'traced peak MB':>15s}")
    rows = []
    for budget in (max(n // 5, 20), n):
        out, call = run(budget)
        up, traced, total = measured(call)
        rows.append((total, traced, log_line_bytes(out)))
        print(f"   {total:22d} {up:13.2f} {traced:15.2f}")
    per_point(rows, "evaluation")


def per_point(rows, what: str) -> None:
    (a, ta, _), (b, tb, line) = rows
    per = (tb - ta) * MB / (b - a)
    print(f"   kept per {what}: {per / 1e3:.2f} kB (traced peak, difference of the two); its line in the log "
          f"{line / 1e3:.2f} kB; ratio {per / line:.1f}")


def long_run(t_end: float, folder: Path) -> None:
    circuit = Circuit.from_file(LONG)
    settings = circuit.settings.with_(t_end=t_end)
    circuit.simulate()  # warm: the integrator's code loaded
    n_sig = len(circuit.outputs)
    samples = int(round((t_end - settings.t_start) / settings.dt_out)) + 1
    bare = samples * n_sig * 8 / MB
    print(f"\n2. a long run: {LONG.relative_to(ROOT)}, t_end {t_end:g} s: {samples} samples x {n_sig} signals "
          f"x 8 bytes = {bare:.1f} MB bare")
    print(f"   {'':30s} {'peak RSS +MB':>13s} {'ratio':>6s} {'traced peak MB':>15s} {'ratio':>6s}")

    def row(label: str, up: float, traced: float, note: str = "") -> None:
        print(f"   {label:30s} {up:13.1f} {up / bare:6.2f} {traced:15.1f} {traced / bare:6.2f}{note}")

    up, traced, result = measured(lambda: circuit.simulate(settings=settings))
    held = (result.values.nbytes + result.states.nbytes + result.t.nbytes) / MB
    row("Circuit.simulate", up, traced, f"   (the result: {held:.1f} MB, t + {n_sig} signals + "
                                        f"{result.states.shape[1]} states)")
    del result
    csv, png = folder / "long.csv", folder / "long.png"
    cli.main(["run", str(LONG), "-o", str(csv), "--plot", str(png), "-q"])  # warm: matplotlib imported
    for label, extra in (("vphs run -o CSV", []), ("vphs run -o CSV --plot PNG", ["--plot", str(png)])):
        argv = ["run", str(LONG), "--t-end", f"{t_end:g} s", "-o", str(csv), "-q", *extra]
        up, traced, code = measured(lambda: cli.main(argv))
        assert code == 0, code
        row(label, up, traced)


def sweep(job, points: int, folder: Path) -> None:
    def run(p: int):
        out = folder / f"sweep_{p}"
        shutil.rmtree(out, ignore_errors=True)
        kp = np.geomspace(1.0, 40.0, p)
        j = dataclasses.replace(job, output=out, sweep_names=["Kp"], sweep_points=[{"Kp": float(v)} for v in kp])
        return out / "sweep", lambda: run_sweep(j, workers=1, quiet=True).total

    run(5)[1]()  # warm
    print(f"\n3. vphs sweep in this process (1 worker, report written) over Kp")
    print(f"   {'points':>22s} {'peak RSS +MB':>13s} {'traced peak MB':>15s}")
    rows = []
    for p in (max(points // 10, 10), points):
        out, call = run(p)
        up, traced, total = measured(call)
        assert total == p, total
        rows.append((p, traced, log_line_bytes(out)))
        print(f"   {p:22d} {up:13.2f} {traced:15.2f}")
    per_point(rows, "point")


def dask_batch(job, d: int) -> None:
    from distributed import Client, LocalCluster

    from blocks.optimise.executors import DaskExecutor

    print(f"\n4. a Dask batch of {d} designs, in-process LocalCluster (1 worker thread)")
    rng = np.random.default_rng(2)
    designs = [job.values(rng.random(len(job.free))) for _ in range(d)]
    with contextlib.redirect_stderr(io.StringIO()), \
            LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        executor = DaskExecutor(job.spec(), client=client)
        held, read = {}, 0
        reset_peak()
        before = rss()
        for _ in executor.run(designs):
            read += 1
            if read in (d // 2, d):
                held[read] = len(cluster.scheduler.tasks)
        up = peak() - before
        after = len(cluster.scheduler.tasks)
        executor.close()
    print(f"   tasks the scheduler holds: {held[d // 2]} with {d // 2} of {d} results read, {held[d]} with all "
          f"{d} read, {after} after the batch; peak RSS +{up:.1f} MB")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--evaluations", type=int, default=500, help="N: the worker's warm-up (then 10 N more)")
    parser.add_argument("--t-end", type=float, default=300.0, help="the long run's simulated time, s")
    parser.add_argument("--points", type=int, default=2000, help="P: the larger sweep's points")
    parser.add_argument("--dask-points", type=int, default=400, help="D: the Dask batch's designs (0: skip)")
    args = parser.parse_args()
    if args.evaluations < 100 or args.points < 100:  # two sizes apart enough for a difference per evaluation
        parser.error("--evaluations and --points must be at least 100")
    job = load_job(JOB)
    with tempfile.TemporaryDirectory(prefix="vphs_memory_") as tmp:
        folder = Path(tmp)
        worker(job, args.evaluations)
        optimise_job(job, args.evaluations, folder)
        long_run(args.t_end, folder)
        sweep(job, args.points, folder)
        if args.dask_points:
            dask_batch(job, args.dask_points)
    return 0


if __name__ == "__main__":
    sys.exit(main())
