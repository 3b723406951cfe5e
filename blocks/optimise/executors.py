"""Where evaluations run: in this process, in a local pool of processes, or on a Dask distributed cluster.

Every executor takes a batch of designs (dicts of SI parameter values) and yields ``(position, record)``
as each evaluation finishes (in any order), so the caller can log it at once. The parallel executors
submit each load case of each design as a task of its own and yield a design when its last case is back. The evaluation itself is
:func:`blocks.optimise.evaluate.evaluate_design`; each worker process loads the circuit once
(``Circuit.from_file``, compiled code from the disk cache) and keeps it for every later evaluation.

- ``serial``: in this process, one after another.
- ``local`` (default): a pool of worker processes, one per core unless ``workers`` says otherwise.
  Workers are forked from this process when it runs no other thread (they inherit the loaded circuit:
  no start-up cost), spawned otherwise (each loads the circuit once, about a second). Workers ignore
  Ctrl-C; the job stops them.
- ``dask``: a Dask distributed cluster at ``scheduler`` (``tcp://host:8786``) or an existing
  ``distributed.Client``. The job's evaluation spec is sent to every worker once; the netlist path must
  be readable on the workers (a shared file system), and each worker process keeps its circuit.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
from typing import Iterator

from blocks.optimise.evaluate import EvalSpec, combine_cases, evaluate_case, evaluate_design


def cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


class SerialExecutor:
    kind = "serial"

    def __init__(self, spec: EvalSpec):
        self.spec, self.workers = spec, 1
        warm_up(spec)

    def run(self, designs: list[dict]) -> Iterator[tuple[int, dict]]:
        for position, design in enumerate(designs):
            yield position, evaluate_design(self.spec, design)

    def close(self) -> None:
        pass


_WORKER_SPEC: EvalSpec | None = None


def warm_up(spec: EvalSpec) -> None:
    """Load the circuit and evaluate the netlist's own design once: numba reads the integrator's compiled
    code from the disk cache at the first call and the cost terms import scipy.signal (together a second
    or so), which should happen once per process, not inside the first evaluation. A failure is fine."""
    evaluate_design(spec, {})


def _worker_start(spec: EvalSpec, parent: int, warm: bool) -> None:
    global _WORKER_SPEC
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the job's to handle
    threading.Thread(target=_orphan_watch, args=(parent,), daemon=True).start()
    _WORKER_SPEC = spec
    if warm:  # a spawned worker loads the circuit itself; a forked one inherited it warm
        warm_up(spec)


def _orphan_watch(parent: int) -> None:
    """End this worker when the job's process is gone (killed): a forked worker holds the task queue's
    pipe open itself, so it would otherwise wait for work for ever."""
    import time

    while os.getppid() == parent:
        time.sleep(0.5)
    os._exit(1)


def _ready(_) -> int:
    return os.getpid()


def _worker_task(design: dict, k: int) -> dict:
    return evaluate_case(_WORKER_SPEC, design, k)


class _Assembler:
    """Collects the load cases of each design as they finish; says which design is complete."""

    def __init__(self, spec: EvalSpec, n: int):
        self.spec, self.parts = spec, [[] for _ in range(n)]

    def add(self, i: int, part: dict) -> dict | None:
        self.parts[i].append(part)
        return combine_cases(self.spec, self.parts[i]) if len(self.parts[i]) == len(self.spec.cases) else None


class LocalExecutor:
    """A pool of worker processes (see the module docstring)."""

    kind = "local"

    def __init__(self, spec: EvalSpec, workers: int | None = None):
        from concurrent.futures import ProcessPoolExecutor

        self.spec = spec
        self.workers = workers or cores()
        fork_ok = "fork" in multiprocessing.get_all_start_methods() and threading.active_count() == 1
        if fork_ok:
            warm_up(spec)  # loaded (and its compiled code read from the cache) once here; forked workers inherit it
        context = multiprocessing.get_context("fork" if fork_ok else "spawn")
        self.pool = ProcessPoolExecutor(self.workers, mp_context=context, initializer=_worker_start,
                                        initargs=(spec, os.getpid(), not fork_ok))
        # start the workers now, before the job starts threads of its own (the log's fsync thread), so that
        # they are forked from a process with one thread; and so that their start-up is not in an evaluation
        list(self.pool.map(_ready, range(self.workers)))

    def run(self, designs: list[dict]) -> Iterator[tuple[int, dict]]:
        from concurrent.futures import as_completed

        futures = {self.pool.submit(_worker_task, design, k): i
                   for i, design in enumerate(designs) for k in range(len(self.spec.cases))}
        assembler = _Assembler(self.spec, len(designs))
        try:
            for future in as_completed(futures):
                record = assembler.add(futures[future], future.result())
                if record is not None:
                    yield futures[future], record
        finally:
            for future in futures:
                future.cancel()

    def close(self) -> None:
        self.pool.shutdown(wait=True, cancel_futures=True)


class DaskExecutor:
    """Evaluations on a Dask distributed cluster (see the module docstring)."""

    kind = "dask"

    def __init__(self, spec: EvalSpec, scheduler=None, client=None):
        from distributed import Client

        self.spec = spec
        self.own_client = client is None
        try:
            self.client = client or Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            from blocks.errors import VphsError

            raise VphsError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from None
        self.workers = max(1, sum(self.client.nthreads().values()))
        try:  # each worker loads the circuit now (once), and a netlist the workers cannot read is said now
            self.client.run(warm_up, spec)
        except Exception as exc:
            if self.own_client:
                self.client.close()
            from blocks.errors import VphsError

            raise VphsError(f"a Dask worker could not load {spec.netlist}: {type(exc).__name__}: {exc} "
                            f"(the workers need the netlist at the same path)") from None
        # hash=False: a key of its own, so that releasing another job's copy of the same spec cannot cancel ours
        self.spec_future = self.client.scatter(spec, broadcast=True, hash=False)

    def run(self, designs: list[dict]) -> Iterator[tuple[int, dict]]:
        from distributed import as_completed

        index, futures = {}, []
        for i, design in enumerate(designs):
            for k in range(len(self.spec.cases)):
                future = self.client.submit(evaluate_case, self.spec_future, design, k, pure=False)
                index[future.key] = (i, k)
                futures.append(future)
        assembler = _Assembler(self.spec, len(designs))
        try:
            for future in as_completed(futures):
                i, k = index[future.key]
                try:
                    part = future.result()
                except Exception as exc:  # the cluster lost the task (a worker died, ...): a failed case
                    part = {"case": self.spec.cases[k][0], "terms": None, "cost": None, "warnings": [],
                            "error": f"dask: {type(exc).__name__}: {exc}", "seconds": 0.0, "pid": None}
                record = assembler.add(i, part)
                if record is not None:
                    yield i, record
        finally:
            for future in futures:
                future.cancel()

    def close(self) -> None:
        if self.own_client:
            self.client.close()


def make_executor(spec: EvalSpec, workers: int | None = None, scheduler: str | None = None, client=None):
    """Dask if a scheduler (or client) is given, else serial for one worker, else a local pool."""
    if client is not None or scheduler:
        return DaskExecutor(spec, scheduler, client)
    if workers == 1:
        return SerialExecutor(spec)
    return LocalExecutor(spec, workers)
