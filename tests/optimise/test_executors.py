"""The local executor: the job's process and its workers, a worker that dies, the job's CPU affinity."""

import os
import signal
from pathlib import Path

import pytest

from blocks.optimise.evaluate import evaluate_design
from blocks.optimise.executors import LocalExecutor
from blocks.optimise.job import load_job

from tests.optimise.test_runner import small_job

DESIGNS = [{"Kp": 4.0, "Kv": 0.3}, {"Kp": 9.0, "Kv": 0.5}, {"Kp": 20.0, "Kv": 0.8}]


def spec(tmp_path: Path):
    return load_job(small_job(tmp_path, cases=2)).spec()


def test_every_task_runs_once_and_matches_the_serial_evaluation(tmp_path):
    s = spec(tmp_path)
    executor = LocalExecutor(s, workers=2)
    try:
        got = dict(executor.run(DESIGNS))
    finally:
        executor.close()
    assert sorted(got) == [0, 1, 2]
    for i, design in enumerate(DESIGNS):
        want = evaluate_design(s, design)
        assert got[i]["cost"] == pytest.approx(want["cost"], rel=1e-12)
        assert got[i]["status"] == want["status"] == "ok"


def test_a_worker_that_dies_fails_its_task_and_the_job_goes_on(tmp_path):
    s = spec(tmp_path)
    executor = LocalExecutor(s, workers=2)
    try:
        worker = executor.pool[0].process
        os.kill(worker.pid, signal.SIGKILL)
        worker.join(timeout=10)
        got = dict(executor.run(DESIGNS))
        assert sorted(got) == [0, 1, 2]
        failed = [r for r in got.values() if r["status"] == "failed"]
        # the dead worker either had a task handed to it (that one fails, naming the worker) or was found
        # dead before (its task stayed in the queue): no task is lost either way
        assert len(failed) <= 1
        for r in failed:
            assert f"worker process {worker.pid} died" in r["error"]
        assert executor.pool == []  # this process evaluated the rest itself
        later = dict(executor.run(DESIGNS[:1]))
        assert later[0]["status"] == "ok"
    finally:
        executor.close()


@pytest.mark.skipif(not hasattr(os, "sched_getaffinity") or len(os.sched_getaffinity(0)) < 2,
                    reason="needs CPU affinity and 2 cores")
def test_one_process_per_core_pinned_and_the_affinity_given_back(tmp_path):
    before = os.sched_getaffinity(0)
    executor = LocalExecutor(spec(tmp_path), workers=len(before))
    try:
        cpus = sorted(before)
        assert os.sched_getaffinity(0) == {cpus[0]}
        assert [os.sched_getaffinity(w.process.pid) for w in executor.pool] == [{c} for c in cpus[1:]]
    finally:
        executor.close()
    assert os.sched_getaffinity(0) == before
