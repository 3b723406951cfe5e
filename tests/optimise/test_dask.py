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


def on_path(s) -> list:
    return [(r["x"], r["cost"], r["status"]) for r in sorted(s.records, key=lambda r: r["index"])]


def test_a_worker_killed_mid_job_loses_no_design(tmp_path, monkeypatch):
    """kill -9 of the only worker takes the scattered spec with it; the nanny starts a new worker. The
    evaluations lost are submitted again, none is logged as failed, and the result is the one-worker run's."""
    import signal
    from distributed import Client, LocalCluster

    from blocks.optimise import executors, runner

    class KillingAtBatch3(executors.DaskExecutor):
        batches = 0

        def run(self, designs):
            KillingAtBatch3.batches += 1
            if KillingAtBatch3.batches == 3:
                for pid in self.client.run(os.getpid).values():
                    os.kill(pid, signal.SIGKILL)
            return super().run(designs)

    monkeypatch.setattr(runner, "make_executor", lambda spec, workers, scheduler, client: KillingAtBatch3(spec, client=client))
    on_dask, here = job(tmp_path, "dask"), job(tmp_path, "serial")
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        first_pids = set(client.run(os.getpid).values())
        s = run_optimise(on_dask, client=client, quiet=True, report=False)
        later_pids = set(client.run(os.getpid).values())
    assert KillingAtBatch3.batches > 3 and later_pids.isdisjoint(first_pids)  # the worker was replaced
    assert s.failed == 0 and all(r["status"] == "ok" for r in records(on_dask.output).values())
    assert on_path(s) == on_path(run_optimise(here, workers=1, quiet=True, report=False))


def _lost(*args):
    from distributed.client import FutureCancelledError

    raise FutureCancelledError("evaluate_case-x", reason="lost dependencies")


class LosingClient:
    """A client whose cluster loses every task after the first ``keep`` (as if its workers kept dying)."""

    def __init__(self, client, keep: int):
        self.client, self.keep = client, keep

    def __getattr__(self, name):
        return getattr(self.client, name)

    def submit(self, fn, *args, **kwargs):
        self.keep -= 1
        return self.client.submit(fn if self.keep >= 0 else _lost, *args, **kwargs)


def test_an_evaluation_the_cluster_keeps_losing_stops_the_job_resumably(tmp_path, monkeypatch, capsys):
    from distributed import Client, LocalCluster

    import cli
    from blocks.optimise import executors, runner

    on_dask, here = job(tmp_path, "dask"), job(tmp_path, "serial")
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        monkeypatch.setattr(runner, "make_executor", lambda spec, workers, scheduler, _:
                            executors.DaskExecutor(spec, client=LosingClient(client, keep=10)))
        code = cli.main(["optimise", on_dask.file, "-q"])
    err = capsys.readouterr().err.strip()
    assert code == 1 and len(err.splitlines()) == 1, err
    assert "lost an evaluation 4 times" in err and f"vphs optimise {on_dask.file} --resume" in err
    logged = records(on_dask.output)
    assert sorted(logged) == list(range(len(logged))) and 0 < len(logged) <= 10  # nothing lost was logged
    assert all(r["status"] == "ok" for r in logged.values())
    monkeypatch.undo()
    resumed = run_optimise(load_job(on_dask.file), resume=True, workers=1, quiet=True, report=False)
    assert resumed.replayed == len(logged)
    assert on_path(resumed) == on_path(run_optimise(here, workers=1, quiet=True, report=False))


class DesignKillingClient(LosingClient):
    """A client whose cluster loses every task of one design (as if that design killed its worker each
    time) and runs every other."""

    def __init__(self, client, deadly: dict):
        super().__init__(client, keep=0)
        self.deadly = deadly

    def submit(self, fn, *args, **kwargs):
        deadly = len(args) > 1 and args[1] == self.deadly  # (spec, design, k): an evaluation of that design
        return self.client.submit(_lost if deadly else fn, *args, **kwargs)


def test_a_design_that_kills_its_worker_every_time_is_a_failed_design_and_the_job_ends(tmp_path, monkeypatch):
    """A review: such a design stopped the job, and --resume replayed it, so the job could never end. It is
    now failed (as a local worker that dies twice on one task), while the other designs run."""
    from distributed import Client, LocalCluster

    from blocks.optimise import executors, runner

    on_dask = job(tmp_path, "dask")
    deadly = dict(load_job(on_dask.file).start_values)  # the netlist's own design, evaluated first
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        monkeypatch.setattr(runner, "make_executor", lambda spec, workers, scheduler, _:
                            executors.DaskExecutor(spec, client=DesignKillingClient(client, deadly)))
        s = run_optimise(load_job(on_dask.file), quiet=True, report=False)
    logged = records(on_dask.output)
    failed = [r for r in logged.values() if r["status"] != "ok"]
    assert [r["parameters"] for r in failed] == [deadly] and "lost this evaluation 4 times" in failed[0]["error"]
    assert "while it answers others: its worker dies running it" in failed[0]["error"] and len(logged) > 5


def test_a_task_is_released_as_soon_as_its_result_is_read(tmp_path):
    """A sweep is one batch of all its points: the batch's futures, each holding its task and its result on
    the cluster, were all kept until the batch ended (a 400-point batch: 401 tasks on the scheduler with
    every result read; bench/memory.py). A future is dropped as soon as it is read."""
    from distributed import Client, LocalCluster

    from blocks.optimise.executors import DaskExecutor

    spec = job(tmp_path, "dask").spec()
    designs = [{"Kp": kp} for kp in (2.0, 4.0, 8.0, 16.0, 32.0, 5.0)]
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        executor = DaskExecutor(spec, client=client)
        held = []  # the evaluation tasks this client still holds each time a record is read
        for _ in executor.run(designs):
            held.append(sum(1 for key in client.refcount if str(key).startswith("evaluate_case")))
        executor.close()
    assert len(held) == len(designs)
    assert held[-1] <= 1, held  # the batch's results are not kept (at most the one being read)
