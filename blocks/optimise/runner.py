"""Running a job: the method asks for points, the runner answers them from the log or the executor.

    job = load_job("netlists/jobs/drive_line_controller.yaml")
    summary = run_optimise(job, resume=False, workers=None)      # or run_sweep(job)

Each batch of points the method asks for gets consecutive evaluation indices. On ``--resume`` the method
is re-run from its seed; a point whose index and coordinates are in the log is answered from it, the
others are evaluated (in parallel) and appended as each finishes. Since the methods are deterministic
given the seed, the batching and the costs, the resumed run retraces the interrupted one exactly and goes
on from where it stopped; the batching (``candidates`` of the Complex method) is taken from the log's
header, not from the number of workers of the resumed run.

Before the method starts, ``optimise`` evaluates the netlist's own design (its values of the free
parameters, with the job's fixed values and load cases) once, as evaluation 0 of the log (step
"netlist"), so that the report can say whether the method found better; it is off the method's path (not
counted in its budget nor in its result). A netlist value outside the job's bounds is not a design of the
job: it is then not evaluated, and the report says why.

A point whose coordinates equal, bit for bit, those of an evaluation made earlier in the job (this run's,
or one read back from the log) is a repeat: it is logged with its own index and step but answered from the
earlier record, not simulated (:mod:`blocks.optimise.repeats`); it counts as an evaluation of the method
like any other. ``Summary.evaluated`` counts the simulations, ``repeated`` the repeats answered in this run.

The result (the best design, the evaluations counted, the failures) is taken over the method's path only:
the Complex method evaluates retractions ahead in parallel and discards those it turns out not to need
(:mod:`blocks.optimise.complex`); they stay in the log, marked discarded, but are left out of the summary,
so that the result is that of a one-worker run whatever the number of workers or ``candidates``.

Outputs: ``<output>/`` for ``optimise`` and ``<output>/sweep/`` for ``sweep``: the evaluation log
(:mod:`blocks.optimise.log`) and the report (:mod:`blocks.optimise.report`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from blocks.optimise.complex import ComplexSettings, complex_minimise
from blocks.optimise.executors import EvaluationLost, Terminated, make_executor
from blocks.optimise.job import Job
from blocks.optimise.log import EvaluationLog, point_id
from blocks.optimise.repeats import Repeats, key, repeat_record
from blocks.optimise.scipy_methods import differential_evolution, nelder_mead


class Interrupted(Exception):
    """Ctrl-C (or SIGTERM, ``summary.reason`` "terminated"): the evaluations finished so far are in the log."""

    def __init__(self, summary: "Summary"):
        self.summary = summary
        super().__init__("interrupted")


@dataclass
class Summary:
    job: Job
    command: str
    folder: Path
    workers: int
    executor: str
    candidates: int | None = None
    evaluated: int = 0  # simulated in this run (on the path or not)
    replayed: int = 0  # answered from the log (on the path or not)
    repeated: int = 0  # in this run, repeats of a point evaluated before, answered from its record (repeats.py)
    failed: int = 0  # on the path
    best: dict | None = None  # on the path
    netlist_design: dict | None = None  # the record of the netlist's own design (evaluated first, off the path)
    netlist_skipped: str = ""  # why the netlist's own design was not evaluated (a value outside the bounds)
    reason: str = ""
    seconds: float = 0.0
    iterations: int = 0
    above_penalty: int = 0  # working designs on the path that cost more than a failed one (a penalty set too low)
    records: list = field(default_factory=list)  # the method's path, in the order it asked for them
    discarded: list = field(default_factory=list)  # evaluated ahead and not needed (only in the log)
    report: Path | None = None
    step_checks: list = field(default_factory=list)  # solver fixed: the best design's doubled-step check (report.py)

    @property
    def total(self) -> int:
        """Every evaluation, on the path or discarded."""
        return self.evaluated + self.replayed + self.repeated

    @property
    def path_repeats(self) -> int:
        """The evaluations on the method's path that were repeats, answered from an earlier record."""
        return sum("repeat_of" in record for record in self.records)

    @property
    def rate(self) -> float:
        return self.evaluated / self.seconds if self.seconds > 0 else 0.0


class Progress:
    """Progress on stderr: done, best so far, failures, rate. On a terminal one line rewritten at most 5 times
    a second; otherwise (a log file) a line every 10 s."""

    def __init__(self, total: int | None, enabled: bool, stream=None):
        self.total, self.enabled, self.stream = total, enabled, stream or sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.started = time.perf_counter()
        self.last = self.started

    def show(self, s: Summary, force: bool = False) -> None:
        now = time.perf_counter()
        if not self.enabled or (not force and now - self.last < (0.2 if self.tty else 10.0)):
            return
        self.last = now
        elapsed = now - self.started
        rate = s.evaluated / elapsed if elapsed > 0 else 0.0
        kept = s.total - len(s.discarded) - (s.netlist_design is not None)  # on the path, or not yet decided
        done = f"{kept}/{self.total}" if self.total else f"{kept}"
        best = f"{s.best['cost']:.6g}" if s.best else "-"
        notes = [f"{n} {what}" for n, what in ((len(s.discarded), "more discarded"), (s.replayed, "from the log"),
                                               (s.repeated, "repeats not simulated")) if n]
        extra = f" ({', '.join(notes)})" if notes else ""
        line = (f"vphs: {done} evaluations{extra}, {s.failed} failed, best cost {best}, {rate:.1f}/s, "
                f"{elapsed:.1f} s")
        print(f"\r{line}" if self.tty else line, end="" if self.tty else "\n", file=self.stream, flush=True)

    def close(self, s: Summary) -> None:
        if self.enabled:
            self.show(s, force=True)
            if self.tty:
                print(file=self.stream, flush=True)


class Runner:
    """The ``evaluate(points, info)`` the methods call: log lookup, parallel evaluation, logging, progress;
    and ``on_path(used)``, by which a method says how many points of its last batch are on its path."""

    def __init__(self, job: Job, log: EvaluationLog, executor, summary: Summary, progress: Progress, to_design):
        self.job, self.log, self.executor, self.summary, self.progress = job, log, executor, summary, progress
        self.to_design = to_design
        self.next_index = 0
        self.repeats = Repeats()  # every point evaluated so far, to answer a repeat from its record
        self.batch: list[dict] = []  # the last batch's records, until the method says which are on its path

    def __call__(self, points: list, info: list[dict], designs: list[dict] | None = None) -> list[float]:
        """The costs of ``points`` (``designs``: their SI values, if not ``to_design`` of the points)."""
        self.on_path()  # a method that said nothing about its last batch used all of it
        first, self.next_index = self.next_index, self.next_index + len(points)
        batch: list[dict | None] = [self.log.finished(first + pos, z) for pos, z in enumerate(points)]
        for record in filter(None, batch):
            self.repeats.remember(record)
            self.summary.replayed += 1
        todo, copies, firsts = [], [], {}  # copies: (pos, pos of the same point simulated in this batch)
        for pos, z in enumerate(points):
            if batch[pos] is not None:
                continue
            original = self.repeats.original(z)
            if original is not None:
                self._answer(pos, first, points, info, batch, original)
            elif key(z) in firsts:
                copies.append((pos, firsts[key(z)]))
            else:
                firsts[key(z)] = pos
                todo.append(pos)
        if todo:
            designs = [designs[pos] if designs else self.to_design(points[pos]) for pos in todo]
            for k, outcome in self.executor.run(designs):
                pos = todo[k]
                x = [float(v) for v in points[pos]]
                record = {"type": "evaluation", "id": point_id(first + pos, x), "index": first + pos, "x": x,
                          "parameters": designs[k], **info[pos], **outcome}
                self.log.append(record)
                self.repeats.remember(record)
                batch[pos] = record
                self.summary.evaluated += 1
                self.progress.show(self.summary)
        for pos, simulated in copies:
            self._answer(pos, first, points, info, batch, batch[simulated])
        self.batch = batch
        return [record["cost"] for record in batch]

    def _answer(self, pos: int, first: int, points: list, info: list[dict], batch: list, original: dict) -> None:
        """Point ``pos`` of the batch, a repeat of ``original``: answered from its record (logged, not simulated)."""
        x = [float(v) for v in points[pos]]
        record = repeat_record(original, first + pos, point_id(first + pos, x), x, info[pos])
        self.log.append(record)
        batch[pos] = record
        self.summary.repeated += 1

    def aside(self, z, design: dict, step: str) -> dict:
        """One evaluation off the method's path (the netlist's own design): logged and answered from the log
        on ``--resume`` like any other, never part of the result; its record."""
        self([z], [{"step": step, "iteration": 0, "n_rep": 0}], [design])
        record, self.batch = self.batch[0], []
        return record

    def on_path(self, used: int | None = None) -> None:
        """The first ``used`` points of the last batch (all if None) are on the method's path: they make the
        result; the others were evaluated ahead and are not needed: marked discarded in the log."""
        batch, self.batch = self.batch, []
        used = len(batch) if used is None else used
        for record in batch[:used]:
            self._seen(record)
        if batch[used:]:
            self.log.discard([record["index"] for record in batch[used:]])
            self.summary.discarded += batch[used:]
        self.progress.show(self.summary)

    def _seen(self, record: dict) -> None:
        s = self.summary
        s.records.append(record)
        if record["status"] != "ok":
            s.failed += 1
            return
        if record["cost"] >= self.job.penalty:
            s.above_penalty += 1
        if s.best is None or record["cost"] < s.best["cost"]:
            s.best = record


def _open(job: Job, command: str, folder: Path, resume: bool, workers, scheduler, client, header_extra):
    """Check the output folder's log, start the executor, open the log (``header_extra(executor, old_header)``
    gives the method's entries of a new header). ``workers`` with a Dask scheduler is refused: the cluster's
    workers evaluate, and a number of local processes would be ignored."""
    if workers is not None and (scheduler or job.scheduler or client is not None):
        from blocks.errors import VphsError

        where = f"--scheduler {scheduler}" if scheduler else \
            f"the job's scheduler: {job.scheduler}" if job.scheduler else "a Dask client"
        raise VphsError(f"--workers {workers} sets the local processes, but {where} evaluates on the Dask cluster's "
                        f"workers; give one or the other")
    fingerprint = f"{job.fingerprint}-{command}"
    old = EvaluationLog.existing(folder, fingerprint, resume, job.sources)  # a foreign log, before any worker starts
    # a sweep reports every point, so each is run again at twice a fixed step; an optimisation only its best
    executor = make_executor(job.spec(check_fixed_step=command == "sweep"), workers or job.workers,
                             scheduler or job.scheduler, client)
    header = {"type": "job", "fingerprint": fingerprint, "job": str(job.file), "name": job.name,
              "command": command, "netlist": job.netlist, "seed": job.seed, "sources": job.sources,
              **header_extra(executor, old)}
    try:
        log = EvaluationLog(folder, header)
    except BaseException:
        executor.close()
        raise
    return log, executor


def run_optimise(job: Job, resume: bool = False, workers: int | None = None, scheduler: str | None = None,
                 client=None, quiet: bool = False, stream=None, report: bool = True) -> Summary:
    """Run the job's optimisation (see the module docstring); :class:`Interrupted` on Ctrl-C."""
    if job.method is None:
        from blocks.errors import NetlistError

        raise NetlistError(job.file, "the job has no algorithm: section; 'vphs optimise' needs one "
                                     "(or run 'vphs sweep' for its sweep:)")
    folder = job.output
    settings = job.settings

    def header(executor, old) -> dict:
        entries = {"method": job.method}
        if job.method == "complex":  # a resumed run keeps the batching it was started with
            entries["candidates"] = int(old["candidates"]) if old else (settings.candidates or executor.workers)
        return entries

    log, executor = _open(job, "optimise", folder, resume, workers, scheduler, client, header)
    summary = Summary(job, "optimise", folder, executor.workers, executor.kind)
    if job.method == "complex":
        summary.candidates = int(log.header["candidates"])
        settings = ComplexSettings(**{**settings.__dict__, "candidates": summary.candidates})
    budget = getattr(settings, "max_evaluations", None)
    progress = Progress(budget, not quiet, stream)
    runner = Runner(job, log, executor, summary, progress, job.values)
    with _running(executor, log, progress, summary):
        summary.netlist_skipped = job.netlist_design_outside()
        if not summary.netlist_skipped:  # first: in the log (index 0) and resumed like the method's points
            summary.netlist_design = runner.aside(job.coordinates(job.start_values), dict(job.start_values), "netlist")
        if job.method == "complex":
            result = complex_minimise(runner, job.lower, job.upper, settings, job.seed, on_path=runner.on_path)
        elif job.method == "nelder_mead":
            if job.start == "netlist":
                settings = dataclasses.replace(settings, x0=list(job.coordinates(job.start_values)))
            result = nelder_mead(runner, job.lower, job.upper, settings, job.seed)
        else:
            result = differential_evolution(runner, job.lower, job.upper, settings, job.seed)
        runner.on_path()
        summary.reason, summary.iterations = result.reason, result.iterations
    if report:
        from blocks.optimise.report import write_optimise_report

        summary.report = write_optimise_report(summary)
    return summary


def run_sweep(job: Job, resume: bool = False, workers: int | None = None, scheduler: str | None = None,
              client=None, quiet: bool = False, stream=None, report: bool = True) -> Summary:
    """Evaluate every point of the job's sweep (in parallel); :class:`Interrupted` on Ctrl-C."""
    if not job.sweep_points:
        from blocks.errors import NetlistError

        raise NetlistError(job.file, "the job has no sweep: section; 'vphs sweep' needs one")
    folder = job.output / "sweep"
    log, executor = _open(job, "sweep", folder, resume, workers, scheduler, client,
                          lambda executor, old: {"sweep": job.sweep_names})
    summary = Summary(job, "sweep", folder, executor.workers, executor.kind)
    progress = Progress(len(job.sweep_points), not quiet, stream)
    names = job.sweep_names
    runner = Runner(job, log, executor, summary, progress, lambda x: dict(zip(names, (float(v) for v in x))))
    points = [np.array([p[n] for n in names]) for p in job.sweep_points]
    with _running(executor, log, progress, summary):
        runner(points, [{"step": "sweep", "iteration": 0, "n_rep": 0}] * len(points))
        runner.on_path()
        summary.reason = "done"
    if report:
        from blocks.optimise.report import write_sweep_report

        summary.report = write_sweep_report(summary)
    return summary


@contextlib.contextmanager
def _running(executor, log, progress, summary: Summary):
    """Times the job's evaluations into ``summary.seconds`` and closes the executor, the log and the
    progress line however the job ends; Ctrl-C becomes :class:`Interrupted` (the summary so far), and
    an evaluation the cluster lost (:class:`~blocks.optimise.executors.EvaluationLost`) gets the summary
    so far as its ``summary``."""
    started = time.perf_counter()
    interrupted = False
    try:
        yield
    except KeyboardInterrupt as exc:
        interrupted = True
        summary.reason = "terminated" if isinstance(exc, Terminated) else "interrupted"
    except EvaluationLost as exc:
        summary.reason = "an evaluation lost by the cluster"
        exc.summary = summary
        raise
    finally:
        summary.seconds = time.perf_counter() - started
        try:
            executor.close()
        finally:
            log.close()
            progress.close(summary)
    if interrupted:
        raise Interrupted(summary) from None
