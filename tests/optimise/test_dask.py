"""A small job through a Dask distributed LocalCluster: the same evaluations as in this process."""

import json
import os
from pathlib import Path

import pytest

from blocks.optimise.job import load_job
from blocks.optimise.log import LOG_NAME
from blocks.optimise.runner import run_optimise, run_sweep

distributed = pytest.importorskip("distributed")
ROOT = Path(__file__).resolve().parents[2]
DRIVE_LINE = ROOT / "netlists" / "opt" / "drive_line.yaml"


def job(tmp_path, out: str):
    path = tmp_path / f"{out}.yaml"
    path.write_text(f"""\
netlist: {DRIVE_LINE}
output: {tmp_path / out}
seed: 11
parameters:
  Kp: {{min: 1, max: 40, log: true}}
  Kvp: {{min: 0, max: 2}}
cost:
  terms:
    pos: {{kind: ise, signal: x, reference: x_ref, unit: mm, weight: 50}}
    vib: {{kind: hp_ise, signal: pA, wn: "100 rad/s", weight: 3e-8}}
algorithm: {{method: complex, max_evaluations: 30, candidates: 2}}
sweep: {{parameters: {{Kp: [2, 4, 8, 16]}}}}
""")
    return load_job(path)


def records(folder: Path) -> dict:
    lines = [json.loads(line) for line in (folder / LOG_NAME).read_text().splitlines()]
    return {r["index"]: r for r in lines if r["type"] == "evaluation"}


def test_a_job_runs_on_a_dask_local_cluster(tmp_path):
    from distributed import Client, LocalCluster

    on_dask, here, by_cli = job(tmp_path, "dask"), job(tmp_path, "serial"), job(tmp_path, "cli")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        s = run_optimise(on_dask, client=client, quiet=True, report=False)
        sweep = run_sweep(on_dask, client=client, quiet=True, report=False)
        worker_pids = set(client.run(os.getpid).values())
        import cli  # the command line's --scheduler reaches the same cluster by its address

        assert cli.main(["sweep", by_cli.file, "--scheduler", cluster.scheduler_address, "-q"]) == 0
    assert s.executor == "dask" and s.workers == 2 and len(s.records) == 30  # the budget counts the path
    run_optimise(here, workers=1, quiet=True, report=False)
    remote, local = records(on_dask.output), records(here.output)
    assert sorted(remote) == list(range(s.total))
    assert {i: (r["x"], r["cost"]) for i, r in remote.items()} == {i: (r["x"], r["cost"]) for i, r in local.items()}
    pids = {pid for r in remote.values() for pid in r["pids"]}
    assert pids and pids <= worker_pids  # evaluated in the cluster's worker processes (which ones: the scheduler's choice)
    assert sweep.total == 4 and {pid for r in records(on_dask.output / "sweep").values() for pid in r["pids"]} <= worker_pids
    assert {pid for r in records(by_cli.output / "sweep").values() for pid in r["pids"]} <= worker_pids
    assert {i: r["cost"] for i, r in records(by_cli.output / "sweep").items()} == \
        {i: r["cost"] for i, r in records(on_dask.output / "sweep").items()}
