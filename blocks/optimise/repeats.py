"""Repeats: a point the job has evaluated already is answered from its record, not simulated again.

The rule: a point a method (or a sweep) asks for whose coordinates ``x`` are identical, bit for bit, to
those of an evaluation made earlier in the same job -- in this run or read back from the log on
``--resume``; on the method's path, evaluated ahead and discarded, or the netlist's own design -- is not
simulated. It still gets a record of its own, with its own index, ``x`` and step, so that the log, the
path, ``--resume`` and the counts hold every point the method asked for, exactly as before; the record
copies the earlier one's ``parameters`` (the design simulated) and outcome (status, cost, cases, error,
warnings), takes no time (``seconds`` 0, no ``pids``) and says ``"repeat_of": <index of the evaluation
simulated>``. Of equal points in one batch the first is simulated and the others are answered from it.

A simulation is deterministic, so the method sees the cost it would have got by simulating the point
again: its path and its result are unchanged, only simulations are saved. One exception: the netlist's
own design is matched by the coordinates it maps to, and a coordinate does not always map back to the
value exactly (a log-scaled bound: Kp = 4 -> x -> 3.9999999999999996); a method starting there (below)
is answered with the netlist's value itself, so its first cost can differ from what simulating its
point would give in the last digits (about 1e-7 relative in the case seen). A repeat is an evaluation of
the method like any other: it counts against ``max_evaluations``, and the report says how many of the
evaluations were repeats. Typical repeats: the Complex method reflecting a design onto a bound it was
clipped to before, and ``nelder_mead`` with ``start: netlist``, whose first point is the netlist's own
design (evaluation 0): it is answered with that evaluation, the netlist's values exactly.
"""

from __future__ import annotations


def key(x) -> tuple[float, ...]:
    """What makes two points the same: their coordinates, bit for bit."""
    return tuple(float(v) for v in x)


class Repeats:
    """The first record of every point evaluated so far in the job, by its coordinates."""

    def __init__(self):
        self.first: dict[tuple[float, ...], dict] = {}

    def remember(self, record: dict) -> None:
        self.first.setdefault(key(record["x"]), record)

    def original(self, x) -> dict | None:
        """The record of an earlier evaluation of exactly the point ``x``, None if it is new."""
        return self.first.get(key(x))


def repeat_record(original: dict, index: int, record_id: str, x: list[float], info: dict) -> dict:
    """The record of evaluation ``index`` (of point ``x``, asked for as ``info`` says) answered from
    ``original``'s: its design and outcome, no time, and the index of the evaluation that was simulated."""
    outcome = {k: original[k] for k in ("parameters", "status", "cost", "cases", "error", "warnings")}
    return {"type": "evaluation", "id": record_id, "index": index, "x": x, **outcome, **info,
            "seconds": 0.0, "pids": [], "repeat_of": original.get("repeat_of", original["index"])}
