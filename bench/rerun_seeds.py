"""Rerun Monte Carlo seeds at their recorded sizes and archive each record beside its rerun.

A change to the code (or to the machine's packages) is checked against the committed records without replacing
them: each named seed of each named case is run again by bench/calibrate_mc.py's own ``run_seed``, planted at
the values its record holds (so a truth that moved is not resized), and the pair {latest, rerun} goes to
``bench/records/archive/ARCHIVE`` (one JSON line per seed; what calibrate_mc.py's table compares: the accepted
effects, the judgements, the verdict, chi^2/nu, the held-out ratio and the estimates). The latest is the
seed's rerun in the last archive of calibrate_mc.py's ``RERUNS`` that has one, else its record.
calibrate_mc.py's ``RERUNS`` list turns an archive into a paragraph of the table's versions. The committed
records, and so the table's rows, stay as they were.

    python bench/rerun_seeds.py s27_packages.jsonl --cases steady_none steady_flow_force --seeds 1 2
    python bench/rerun_seeds.py s27_packages.jsonl --flows 20 --cases steady_none --seeds 1
    python bench/rerun_seeds.py s27_packages.jsonl --recorded --cases time_none --seeds 1

A seed already in the archive from the same records file is skipped (an interrupted run resumes); a seed with
no record, or whose record is an error, is an error before anything runs.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import calibrate_mc as mc  # noqa: E402

COMPARED = ("accepted", "found", "recovered", "unexplained", "chi2nu_after", "heldout_ratio", "estimates")


def compared(record: dict) -> dict:
    return {key: record.get(key) for key in COMPARED}


def _kind(case: str) -> str:
    return next(c.kind for c in mc.CASES if c.name == case)


def latest(file: str, record: dict) -> tuple[dict, str]:
    """What a rerun is compared with: the seed's rerun in the last archive of ``mc.RERUNS`` holding one
    (its compared keys), else its record; and which it is."""
    found, source = compared(record), "record"
    for name, _intro in mc.RERUNS:
        for row in mc._archived(name):
            if (row["file"], row["case"], row["seed"]) == (file, record["case"], record["seed"]):
                found, source = row["after"], name
    return found, source


def plan(cases: list[str], seeds: list[int], archived: list[dict]) -> tuple[list[tuple], list[str]]:
    """The reruns to make, (case, seed, sizes, record) for each named seed of each named case in the records
    now configured (``mc.configure``), seed by seed over the cases (an interrupted run covers every case),
    leaving out those the archive already holds from the same records file; and the seeds with no record to
    compare with (none, or an error)."""
    records = {(r["case"], r["seed"]): r for r in mc.load_results()}
    done = {(r["file"], r["case"], r["seed"]) for r in archived}
    jobs, missing = [], []
    for seed in seeds:
        for name in cases:
            record = records.get((name, seed))
            if record is None or "error" in record:
                missing.append(f"{name} seed {seed}")
            elif (mc.results_file(_kind(name)).name, name, seed) not in done:
                sizes = (record["planted"], record["lambda"], record.get("lambda_levels"))
                jobs.append((name, seed, sizes, record))
    return jobs, missing


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("archive", help="file name under bench/records/archive/, e.g. s27_packages.jsonl")
    parser.add_argument("--cases", nargs="+", required=True, help="case names")
    parser.add_argument("--seeds", nargs="+", type=int, required=True, help="seed numbers")
    parser.add_argument("--flows", type=int, help="the steady cases' records with this many flows per setting")
    parser.add_argument("--recorded", action="store_true", help="the recorded-command time-series records")
    parser.add_argument("--workers", type=int, default=1)
    args = parser.parse_args(argv)
    if "/" in args.archive or not args.archive.endswith(".jsonl"):
        parser.error(f"archive {args.archive!r}: give a file name ending in .jsonl (it goes to "
                     f"{mc.RECORDS / 'archive'})")
    unknown = [c for c in args.cases if c not in {case.name for case in mc.CASES}]
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)}")
    mc.configure(args.flows, args.recorded)
    archive = mc.RECORDS / "archive" / args.archive
    jobs, missing = plan(args.cases, args.seeds, mc._records(archive))
    jobs = [((name, seed, sizes, args.flows, args.recorded), record) for name, seed, sizes, record in jobs]
    if missing:
        print(f"error: no record to compare with in {mc.RESULTS.name} or {mc.MCV_RESULTS.name}: "
              f"{', '.join(missing)}", file=sys.stderr)
        return 2
    print(f"{len(jobs)} reruns -> {archive}", flush=True)
    with ProcessPoolExecutor(max_workers=args.workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = {pool.submit(mc._worker, job): record for job, record in jobs}
        for fut in as_completed(futures):
            before, after = futures[fut], fut.result()
            if "error" in after:
                print(f"{after['case']} seed {after['seed']}: {after['error']} (not archived)", flush=True)
                continue
            file = mc.results_file(_kind(after["case"])).name
            before, source = latest(file, before)
            line = {"file": file, "case": after["case"], "seed": after["seed"], "before": before,
                    "before_from": source, "after": compared(after), "seconds": after["seconds"],
                    "environment": after.get("environment")}
            with open(archive, "a") as handle:
                handle.write(json.dumps(line, default=float) + "\n")
            print(f"{after['case']} seed {after['seed']}: accepted {before['accepted']} -> {after['accepted']}, "
                  f"chi2/nu {before['chi2nu_after']:.6g} -> {after['chi2nu_after']:.6g} (against {source}), "
                  f"{after['seconds']:.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
