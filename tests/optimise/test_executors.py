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


def test_a_worker_killed_from_outside_loses_no_task_and_fails_no_design(tmp_path):
    s = spec(tmp_path)
    executor = LocalExecutor(s, workers=2)
    try:
        worker = executor.pool[0].process
        os.kill(worker.pid, signal.SIGKILL)
        worker.join(timeout=10)
        # the dead worker either had a task handed to it (tried again here) or was found dead before
        # (its task stayed in the queue): every design is evaluated, none is blamed for the kill
        got = dict(executor.run(DESIGNS))
        assert sorted(got) == [0, 1, 2]
        assert [r["status"] for r in got.values()] == ["ok"] * 3
        assert executor.pool == []  # this process evaluated the rest itself
        later = dict(executor.run(DESIGNS[:1]))
        assert later[0]["status"] == "ok"
    finally:
        executor.close()


def test_ctrl_c_is_deferred_only_where_it_would_interrupt(tmp_path):
    """A job run with Ctrl-C ignored (a background job) must not start stopping on it."""
    import signal as sig

    from blocks.optimise.executors import interrupt_after_evaluation

    previous = sig.signal(sig.SIGINT, sig.SIG_IGN)
    try:
        with interrupt_after_evaluation():
            os.kill(os.getpid(), sig.SIGINT)
        # a terminal's Ctrl-C, whatever this test runs under (a test run in the background has it ignored)
        sig.signal(sig.SIGINT, sig.default_int_handler)
        with pytest.raises(KeyboardInterrupt):
            with interrupt_after_evaluation():
                os.kill(os.getpid(), sig.SIGINT)
                done = True  # the block runs to its end first
        assert done
    finally:
        sig.signal(sig.SIGINT, previous)


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
