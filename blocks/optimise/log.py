"""The append-only evaluation log of a job: one JSON line per evaluation, written as each one finishes.

    <output>/evaluations.jsonl
    {"type": "job", "fingerprint": "...", "job": "...", "command": "optimise", "method": "complex", ...}
    {"type": "evaluation", "id": "000017-3f9a12c4", "index": 17, "x": [...], "parameters": {...},
     "status": "ok", "cost": 123.4, "cases": {...}, "error": null, "seconds": 0.0052, "step": "reflection",
     "iteration": 5, "n_rep": 0, "warnings": [], "pids": [4711]}

Each line is written whole and flushed to the operating system as its evaluation finishes, so a Ctrl-C or
a killed process loses at most the evaluations still running. The fsync that puts it on the disk (what a
power cut would need) runs in a background thread: it syncs whatever has been written since its last
sync (a group commit), so every line is on the disk within one disk sync of its writing, and a slow disk
(a sync took 0.2 to 4 ms here) does not hold up the evaluations; ``close`` waits for the last sync. A line
cut short by a kill (no newline at the end of the file) is dropped when the log is reopened -- it was not
finished -- and the file is truncated back to its last whole line before anything is appended.

``index`` counts evaluations in the order the method asked for them (not the order they finished);
``x`` are the coordinates the method works in (normalised, see :mod:`blocks.optimise.runner`) and
``parameters`` the SI values simulated. ``id`` = index + a hash of x: on ``--resume`` the method is
re-run from its seed and each point it asks for is answered from the log when the entry with that index
holds exactly that x, and evaluated otherwise -- so finished evaluations are never repeated and the log
ends up with every evaluation once.

A point evaluated before in the job is not simulated again (:mod:`blocks.optimise.repeats`): its record
copies the earlier one's parameters and outcome, with ``"seconds": 0``, ``"pids": []`` and
``"repeat_of": <the index of the evaluation simulated>``.

    {"type": "discarded", "indices": [18, 19]}

says that those evaluations were made ahead of need in parallel (the Complex method's later retractions,
:mod:`blocks.optimise.complex`) and were not on the method's path: they are kept, but not part of the
result. It is written once the method has seen the batch's costs (after their evaluation lines); on
``--resume`` an index marked already is not marked again. :func:`read_log` gives such a record
``"discarded": true``.
"""

from __future__ import annotations

import hashlib
import json
import os
import threading
from pathlib import Path

from blocks.errors import VphsError

LOG_NAME = "evaluations.jsonl"


class LogError(VphsError):
    pass


def file_in_the_way(folder: Path) -> Path | None:
    """The first of ``folder`` and its parents that exists, if it is not a folder (a file there makes the
    log unwritable, which the operating system would only call 'File exists' or 'Not a directory')."""
    for path in (Path(folder), *Path(folder).parents):
        if path.exists():
            return None if path.is_dir() else path
    return None


def point_id(index: int, x) -> str:
    digest = hashlib.sha1(json.dumps([float(v) for v in x]).encode()).hexdigest()[:8]
    return f"{index:06d}-{digest}"


def changed_source(old: dict[str, str] | None, new: dict[str, str] | None) -> str | None:
    """Which file the circuit is built from changed between two ``sources`` (file -> digest), as a phrase
    ("parts/axis.yaml changed"); None if none did, or if either is unknown."""
    if old is None or new is None:
        return None
    for file in {**old, **new}:
        if file not in new:
            return f"{file} is no longer read by the netlist"
        if file not in old:
            return f"{file} is now read by the netlist"
        if old[file] != new[file]:
            return f"{file} changed"
    return None


class EvaluationLog:
    """Read, check and append to ``<folder>/evaluations.jsonl``.

    ``EvaluationLog.existing(folder, fingerprint, resume)`` first: the header of a log that may be
    continued (None if there is none), or a :class:`LogError` for one that may not; then
    ``EvaluationLog(folder, header)`` opens it (loading its records) or starts it with ``header``."""

    def __init__(self, folder: Path, header: dict):
        self.path = Path(folder) / LOG_NAME
        self.records: dict[int, dict] = {}
        self.discarded: set[int] = set()
        self._dirty, self._closing = threading.Event(), False
        self._syncer = threading.Thread(target=self._sync_loop, name="vphs-log-fsync", daemon=True)
        blocker = file_in_the_way(self.path.parent)
        if blocker is not None:
            raise LogError(f"{self.path}: cannot write the evaluation log: '{blocker}' is a file, not a folder")
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            if self.path.exists() and self.path.stat().st_size > 0:
                self.header = self._load()
                self.handle = open(self.path, "a", encoding="utf-8")
            else:
                self.header = header
                self.handle = open(self.path, "w", encoding="utf-8")
                self._write(header)
        except OSError as exc:
            raise LogError(f"{self.path}: cannot write the evaluation log: {exc.strerror or exc}") from None
        self._syncer.start()

    @classmethod
    def existing(cls, folder: Path, fingerprint: str, resume: bool, sources: dict[str, str] | None = None) -> dict | None:
        """``sources`` (file -> digest, the header's ``"sources"``) are the files the job's circuit is built
        from; a log whose header lists them is refused, naming the file, if any of them changed. ``resume``
        without a log is an error too (never a new job started silently)."""
        path = Path(folder) / LOG_NAME
        if not (path.exists() and path.stat().st_size > 0):
            if resume:  # a mistyped output: or a deleted folder would otherwise start the job again silently
                raise LogError(f"{folder}: --resume, but this output folder holds no evaluation log ({LOG_NAME}); "
                               f"there is nothing to continue -- check the job's output:, or run without --resume")
            return None
        if path.is_dir():
            raise LogError(f"{path}: a folder, not a log")
        log = cls.__new__(cls)
        log.path, log.records, log.discarded = path, {}, set()
        if not resume:
            raise LogError(f"{path}: this job's output folder holds a log already ({log._count_lines()} lines); "
                           f"continue it with --resume, or give another output folder (or delete this one)")
        header = log._load()
        if "sources" not in header:  # its evaluation 0 is the method's first point, not the netlist's design
            raise LogError(f"{path}: this log was written by an earlier version of vphs (before the netlist's own "
                           f"design was evaluated first and the circuit's files recorded); this version cannot "
                           f"continue it -- run the job into another output folder")
        changed = changed_source(header.get("sources"), sources)
        if changed:
            raise LogError(f"{path}: {changed} since the log was written; its results would not be this "
                           f"circuit's, so the log cannot be resumed -- restore the file or use another output folder")
        if header.get("fingerprint") != fingerprint:
            raise LogError(f"{path}: the log was written by a different job (the job file, its settings or the "
                           f"netlist changed: fingerprint {header.get('fingerprint')} != {fingerprint}); it cannot "
                           f"be resumed -- use another output folder")
        return header

    def _count_lines(self) -> int:
        with open(self.path, "rb") as handle:
            return sum(1 for _ in handle)

    def _load(self) -> dict:
        raw = self.path.read_bytes()
        whole = raw[: raw.rfind(b"\n") + 1]
        if len(whole) < len(raw):  # the last line was being written when the process died
            with open(self.path, "r+b") as handle:
                handle.truncate(len(whole))
                handle.flush()
                os.fsync(handle.fileno())
        header = None
        for number, line in enumerate(whole.decode("utf-8").splitlines(), 1):
            if not line.strip():
                continue
            try:
                record = json.loads(line)
            except json.JSONDecodeError as exc:
                raise LogError(f"{self.path}:{number}: not a JSON line ({exc.msg}); the log is damaged") from None
            if record.get("type") == "job" and header is None:
                header = record
            elif record.get("type") == "evaluation":
                self.records.setdefault(int(record["index"]), record)
            elif record.get("type") == "discarded":
                self.discarded.update(int(i) for i in record["indices"])
        if header is None:
            raise LogError(f"{self.path}: no job header line; not an evaluation log of vphs")
        return header

    def _write(self, record: dict) -> None:
        self.handle.write(json.dumps(record, allow_nan=False) + "\n")
        self.handle.flush()
        self._dirty.set()

    def _sync_loop(self) -> None:
        while True:
            self._dirty.wait()
            self._dirty.clear()
            if self._closing:
                return
            try:
                os.fsync(self.handle.fileno())
            except (OSError, ValueError):  # closed under us, or a file system without fsync
                return

    def finished(self, index: int, x) -> dict | None:
        """The logged record of evaluation ``index`` if it was of exactly the point ``x``."""
        record = self.records.get(index)
        if record is None:
            return None
        if record.get("x") != [float(v) for v in x]:
            raise LogError(f"{self.path}: evaluation {index} in the log is of another point than the resumed job "
                           f"asks for; the log does not belong to this job's run -- use another output folder")
        return record

    def append(self, record: dict) -> None:
        self._write(record)
        self.records[int(record["index"])] = record

    def discard(self, indices: list[int]) -> None:
        """Mark evaluations as made ahead of need and not on the method's path (once each)."""
        new = [int(i) for i in indices if int(i) not in self.discarded]
        if new:
            self._write({"type": "discarded", "indices": new})
            self.discarded.update(new)

    def close(self) -> None:
        self._closing = True
        self._dirty.set()
        self._syncer.join()
        if not self.handle.closed:
            self.handle.flush()
            os.fsync(self.handle.fileno())
            self.handle.close()


def read_log(folder: Path) -> tuple[dict, list[dict]]:
    """The header and the evaluation records (by index) of a finished or interrupted job's log; a record
    evaluated ahead and not on the method's path has ``"discarded": True``."""
    path = Path(folder) / LOG_NAME
    header, records, discarded = {}, {}, set()
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            record = json.loads(line)
        except json.JSONDecodeError:
            continue
        if record.get("type") == "job":
            header = record
        elif record.get("type") == "evaluation":
            records.setdefault(int(record["index"]), record)
        elif record.get("type") == "discarded":
            discarded.update(int(i) for i in record["indices"])
    return header, [{**records[i], "discarded": True} if i in discarded else records[i] for i in sorted(records)]
