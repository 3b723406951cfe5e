"""Where evaluations run: in this process, in a local pool of processes, or on a Dask distributed cluster.

Every executor takes a batch of designs (dicts of SI parameter values) and yields ``(position, record)``
as each evaluation finishes (in any order), so the caller can log it at once. The parallel executors
submit each load case of each design as a task of its own and yield a design when its last case is back.
The evaluation itself is :func:`blocks.optimise.evaluate.evaluate_design`; each process loads the circuit
once (``Circuit.from_file``, compiled code from the disk cache) and keeps it for every later evaluation.

- ``serial``: in this process, one after another.
- ``local`` (default): one process per core -- the job's own process and ``workers - 1`` worker
  processes, each joined to it by a pipe of its own. The job's process hands a task to every idle worker,
  evaluates the next one itself, then collects what came back; so a batch of p designs on p cores costs
  one pipe round trip per worker (tens of microseconds) and no core waits for a dispatcher. (A
  ``concurrent.futures`` pool passes every task through a queue, a feeder thread and a management thread:
  about 1-2 ms a batch, a third of a 3 ms evaluation.) Workers are forked from this process when it runs
  no other thread (they inherit the loaded circuit: no start-up cost), spawned otherwise (each loads the
  circuit once, about a second). Workers ignore Ctrl-C (the job stops them) and end when the job's process
  is gone. A worker that dies (killed from outside) is dropped and its task is tried again once, by
  another process; a task that kills two fails with that message. The job goes on either way.
- ``dask``: a Dask distributed cluster at ``scheduler`` (``tcp://host:8786``) or an existing
  ``distributed.Client``. The job's evaluation spec is sent to every worker once; the netlist path must
  be readable on the workers (a shared file system), and each worker process keeps its circuit.
  A task the cluster loses (its worker died, a connection closed: ``future.result()`` raises, which
  :func:`evaluate_case` itself never does) is not the design's failure: it is submitted again, at most
  ``LOST_RESUBMISSIONS`` times (with the spec scattered again if the lost copy was the only one). Lost
  once more, a trivial task is sent as a probe: if the cluster answers it, the loss is the design's (its
  worker dies running it, as a local worker that dies twice on one task: logged as failed, so that the
  job can end); if not, the cluster's: the job stops with :class:`EvaluationLost`, its log resumable. A
  failed simulation inside the task is a failed design, as everywhere.
"""

from __future__ import annotations

import contextlib
import dataclasses
import multiprocessing
import os
import signal
import threading
from typing import Iterator

from blocks import interrupt
from blocks.errors import VphsError
from blocks.optimise.evaluate import EvalSpec, combine_cases, evaluate_case, evaluate_design


def cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


Terminated = interrupt.Terminated
"""SIGTERM to a job's process that handles it (:func:`terminate_as_interrupt`): stopped as by Ctrl-C."""


def terminate_as_interrupt(signum, frame) -> None:
    """A SIGTERM handler for the job's process (``vphs optimise|sweep``): the job stops as on Ctrl-C, after
    the evaluation under way, its log resumable and the resume command said, rather than dying silently."""
    raise Terminated


@contextlib.contextmanager
def interrupt_after_evaluation():
    """Ctrl-C (and SIGTERM where :func:`terminate_as_interrupt` handles it) while this process evaluates
    ends the job after the evaluation, not inside it: raised inside the compiled integrator,
    KeyboardInterrupt surfaces as a SystemError that would look like a failed design. Evaluations take
    milliseconds to seconds; a second signal waits as well. A signal ignored or left to the system's default
    is left alone (:func:`blocks.interrupt.deferred`)."""
    with interrupt.deferred():
        yield


class SerialExecutor:
    kind = "serial"

    def __init__(self, spec: EvalSpec):
        self.spec, self.workers = spec, 1
        warm_up(spec)

    def run(self, designs: list[dict]) -> Iterator[tuple[int, dict]]:
        for position, design in enumerate(designs):
            with interrupt_after_evaluation():
                record = evaluate_design(self.spec, design)
            yield position, record

    def close(self) -> None:
        pass


_WORKER_SPEC: EvalSpec | None = None


def warm_up(spec: EvalSpec) -> None:
    """Load the circuit and evaluate the netlist's own design once: numba reads the integrator's compiled
    code from the disk cache at the first call and the cost terms import scipy.signal (together a second
    or so), which should happen once per process, not inside the first evaluation. A failure is fine; nothing
    is said of it, so a fixed step is not checked."""
    evaluate_design(dataclasses.replace(spec, check_fixed_step=False), {})


def _worker_start(spec: EvalSpec, parent: int, warm: bool) -> None:
    global _WORKER_SPEC
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the job's to handle
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the job's handler, inherited by a fork: a worker just ends
    threading.Thread(target=_orphan_watch, args=(parent,), daemon=True).start()
    _WORKER_SPEC = spec
    if warm:  # a spawned worker loads the circuit itself; a forked one inherited it warm
        warm_up(spec)


def _orphan_watch(parent: int) -> None:
    """End this worker when the job's process is gone (killed): a forked worker inherited copies of the
    job's ends of the pipes, so its own pipe never reports end-of-file and it would wait for work for ever."""
    import time

    while os.getppid() == parent:
        time.sleep(0.5)
    os._exit(1)


def _failed_case(spec: EvalSpec, k: int, error: str) -> dict:
    return {"case": spec.cases[k][0], "terms": None, "cost": None, "warnings": [], "error": error,
            "seconds": 0.0, "pid": None}


def _worker_loop(connection, spec: EvalSpec, parent: int, warm: bool, cpu: int | None) -> None:
    """A local worker: answer ``(tag, design, k)`` with ``(tag, evaluate_case(...))`` until told to stop."""
    if cpu is not None:
        os.sched_setaffinity(0, {cpu})
    _worker_start(spec, parent, warm)
    connection.send(("ready", os.getpid()))
    while True:
        try:
            message = connection.recv()
        except (EOFError, OSError):  # the job's process closed its end
            return
        if message is None:
            return
        tag, design, k = message
        try:
            part = evaluate_case(spec, design, k)
        except BaseException as exc:  # evaluate_case records errors itself; this is a last resort
            part = _failed_case(spec, k, f"internal error in worker {os.getpid()}: {type(exc).__name__}: {exc}")
        connection.send((tag, part))


class _Assembler:
    """Collects the load cases of each design as they finish; says which design is complete."""

    def __init__(self, spec: EvalSpec, n: int):
        self.spec, self.parts = spec, [[] for _ in range(n)]

    def add(self, i: int, part: dict) -> dict | None:
        self.parts[i].append(part)
        return combine_cases(self.spec, self.parts[i]) if len(self.parts[i]) == len(self.spec.cases) else None


class _Worker:
    def __init__(self, process, connection):
        self.process, self.connection, self.task = process, connection, None


class LocalExecutor:
    """The job's own process and ``workers - 1`` worker processes (see the module docstring)."""

    kind = "local"

    def __init__(self, spec: EvalSpec, workers: int | None = None):
        self.spec = spec
        self.workers = workers or cores()
        fork_ok = "fork" in multiprocessing.get_all_start_methods() and threading.active_count() == 1
        warm_up(spec)  # this process evaluates too; forked workers inherit the loaded circuit
        context = multiprocessing.get_context("fork" if fork_ok else "spawn")
        self.pool: list[_Worker] = []
        cpus = self._pin_cpus()
        try:
            # started now, before the job starts threads of its own (the log's fsync thread), so that they
            # are forked from a process with one thread; and so that their start-up is not in an evaluation
            for _ in range(self.workers - 1):
                ours, theirs = context.Pipe()
                cpu = cpus[len(self.pool) + 1] if cpus else None
                process = context.Process(target=_worker_loop, args=(theirs, spec, os.getpid(), not fork_ok, cpu),
                                          daemon=True)
                process.start()
                theirs.close()
                self.pool.append(_Worker(process, ours))
            for worker in self.pool:
                worker.connection.recv()  # "ready"
        except BaseException:
            self.close()  # the workers started so far, and this process's affinity
            raise

    def _pin_cpus(self) -> list[int] | None:
        """When the job takes every core it may run on, one process per core, pinned: this process to the
        first, worker j to the (j+1)-th. Unpinned, Linux wakes a worker on the core of the process that
        woke it and the job's process waits for a core of its own again: about 0.5 ms per task handed
        out, measured here (bench/optimise.py). The job's own affinity is given back at close."""
        self.affinity = None
        if not hasattr(os, "sched_setaffinity"):
            return None
        cpus = sorted(os.sched_getaffinity(0))
        if len(cpus) != self.workers or self.workers < 2:
            return None
        self.affinity = set(cpus)
        os.sched_setaffinity(0, {cpus[0]})
        return cpus

    def _lost(self, worker: _Worker) -> str:
        worker.process.join(timeout=1.0)
        self.pool.remove(worker)
        return f"worker process {worker.process.pid} died (exit code {worker.process.exitcode})"

    def _drain(self) -> None:
        """Wait out the tasks a previous batch left running (the caller stopped reading it)."""
        for worker in [w for w in self.pool if w.task is not None]:
            try:
                while worker.connection.recv()[0] != worker.task:
                    pass
                worker.task = None
            except (EOFError, OSError):
                self._lost(worker)

    def run(self, designs: list[dict]) -> Iterator[tuple[int, dict]]:
        from collections import deque
        from multiprocessing.connection import wait

        self._drain()
        tasks = deque((i, k) for i in range(len(designs)) for k in range(len(self.spec.cases)))
        assembler = _Assembler(self.spec, len(designs))

        retried: set[tuple[int, int]] = set()

        def dispatch() -> None:
            for worker in list(self.pool):
                if worker.task is None and tasks:
                    worker.task = tasks.popleft()  # before the send: an interrupt between them leaves no doubt
                    i, k = worker.task
                    try:
                        worker.connection.send(((i, k), designs[i], k))
                    except (BrokenPipeError, OSError):  # died while idle: the task stays for the others
                        tasks.appendleft(worker.task)
                        self._lost(worker)

        def collect(timeout: float | None) -> Iterator[tuple[int, dict]]:
            busy = {w.connection: w for w in self.pool if w.task is not None}
            for connection in wait(list(busy), timeout):
                worker = busy[connection]
                i, k = task = worker.task
                try:
                    tag, part = connection.recv()
                except (EOFError, OSError):
                    error = self._lost(worker)
                    if task not in retried:  # killed from outside (OOM killer, kill): not the design's fault
                        retried.add(task)
                        tasks.appendleft(task)
                        continue
                    tag, part = task, _failed_case(self.spec, k, f"{error}, twice on this task")
                worker.task = None
                if tag != task:  # a stale answer (cannot happen after _drain; never misattributed)
                    raise RuntimeError(f"worker answered task {tag} while holding {task}")
                record = assembler.add(i, part)
                if record is not None:
                    yield i, record

        while tasks or any(w.task is not None for w in self.pool):
            dispatch()
            if tasks:  # every worker is busy: this process takes the next task itself
                i, k = tasks.popleft()
                with interrupt_after_evaluation():
                    part = evaluate_case(self.spec, designs[i], k)
                record = assembler.add(i, part)
                if record is not None:
                    yield i, record
                yield from collect(0)
            else:
                yield from collect(None)

    def close(self) -> None:
        for worker in self.pool:
            try:
                worker.connection.send(None)
            except (BrokenPipeError, OSError):
                pass
        for worker in self.pool:
            worker.process.join(timeout=2.0)
            if worker.process.is_alive():  # still in a long simulation
                worker.process.terminate()
                worker.process.join(timeout=2.0)
            worker.connection.close()
        self.pool = []
        if self.affinity is not None:
            os.sched_setaffinity(0, self.affinity)
            self.affinity = None


LOST_RESUBMISSIONS = 3  # a Dask task the cluster loses is submitted again at most this many times
PROBE_ANSWER = 42


def _probe() -> int:
    """The trivial task that tells a cluster that answers from one that does not (DaskExecutor._answers)."""
    return PROBE_ANSWER


class EvaluationLost(VphsError):
    """The cluster lost an evaluation (a worker died, the connection closed) more than LOST_RESUBMISSIONS
    times: the job stops; what it logged so far stays resumable. Not a failure of the design."""


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
            raise VphsError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from None
        self.workers = max(1, sum(self.client.nthreads().values()))
        try:  # each worker loads the circuit now (once), and a netlist the workers cannot read is said now
            self.client.run(warm_up, spec)
        except Exception as exc:
            if self.own_client:
                self.client.close()
            raise VphsError(f"a Dask worker could not load {spec.netlist}: {type(exc).__name__}: {exc} "
                            f"(the workers need the netlist at the same path)") from None
        # hash=False: a key of its own, so that releasing another job's copy of the same spec cannot cancel ours
        self.spec_future = self.client.scatter(spec, broadcast=True, hash=False)

    def _spec_for(self, lost_with=None):
        """The scattered spec to submit with; scattered again if ``lost_with`` (the copy a lost task had) is
        the current one: a worker killed with the only copy takes it with it, and every task submitted with
        that copy afterwards is cancelled ("lost dependencies") even once another worker has joined."""
        if lost_with is not None and lost_with is self.spec_future:
            try:
                self.spec_future.release()
            except Exception:  # already gone with its worker
                pass
            self.spec_future = self.client.scatter(self.spec, broadcast=True, hash=False)
        return self.spec_future

    def run(self, designs: list[dict]) -> Iterator[tuple[int, dict]]:
        from distributed import as_completed

        # future key -> (design, load case, the spec copy it was given), and the futures not yet read: a future
        # is dropped as soon as it is read, so that the cluster forgets its task and result then, not at the end
        # of the batch (a sweep is one batch of all its points)
        tasks, unread = {}, {}
        losses: dict[tuple[int, int], int] = {}

        def submit(i: int, k: int, lost_with=None):
            spec = self._spec_for(lost_with)
            future = self.client.submit(evaluate_case, spec, designs[i], k, pure=False)
            tasks[future.key], unread[future.key] = (i, k, spec), future
            return future

        pending = as_completed([submit(i, k) for i in range(len(designs)) for k in range(len(self.spec.cases))])
        assembler = _Assembler(self.spec, len(designs))
        try:
            for future in pending:
                i, k, spec = tasks.pop(future.key)
                del unread[future.key]
                try:
                    part = future.result()
                except Exception as exc:  # evaluate_case never raises: the cluster lost the task, not the design
                    losses[i, k] = losses.get((i, k), 0) + 1
                    if losses[i, k] <= LOST_RESUBMISSIONS:
                        pending.add(submit(i, k, lost_with=spec))
                        continue
                    lost = f"the Dask cluster lost this evaluation {losses[i, k]} times ({type(exc).__name__}: {exc})"
                    if not self._answers():
                        raise EvaluationLost(f"{lost.replace('this', 'an')}, and does not answer a probe either; it "
                                             f"is not a failure of the design and was not logged") from None
                    part = _failed_case(self.spec, k, f"{lost}, while it answers others: its worker dies running it")
                finally:
                    del future  # the last reference to a task that is read: the cluster releases it
                record = assembler.add(i, part)
                if record is not None:
                    yield i, record
        finally:
            for future in unread.values():
                future.cancel()

    def _answers(self, timeout: float = 60.0) -> bool:
        """Whether the cluster still runs a trivial task (within ``timeout`` s)."""
        try:
            return self.client.submit(_probe, pure=False).result(timeout=timeout) == PROBE_ANSWER
        except Exception:  # lost, cancelled, timed out: the cluster is not answering
            return False

    def close(self) -> None:
        if self.own_client:
            self.client.close()


def scheduler_problem(address: str) -> str | None:
    """What is wrong with the form of a Dask scheduler address, or None: found before connecting, where
    distributed would fail with a bare ValueError ("missing port number")."""
    try:
        from distributed.comm import parse_address
        from distributed.comm.registry import get_backend
    except ImportError:
        return "the Dask distributed package is not installed"
    try:
        scheme, location = parse_address(address)
        get_backend(scheme)
    except ValueError as exc:  # an unknown scheme: distributed lists the known ones
        return str(exc)
    if scheme in ("tcp", "tls", "ws", "wss") and not location.rpartition(":")[2].isdigit():
        return "the port is missing or not a number; expected tcp://HOST:PORT, e.g. tcp://10.0.0.5:8786"
    return None


def make_executor(spec: EvalSpec, workers: int | None = None, scheduler: str | None = None, client=None):
    """Dask if a scheduler (or client) is given, else serial for one worker, else a local pool."""
    if client is not None or scheduler:
        return DaskExecutor(spec, scheduler, client)
    if workers == 1:
        return SerialExecutor(spec)
    return LocalExecutor(spec, workers)
