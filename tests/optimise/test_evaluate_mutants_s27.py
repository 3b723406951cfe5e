"""Gaps found by mutation testing blocks/optimise/evaluate.py (session 27).

combine_cases puts an evaluation's record together from its load cases (module and function docstrings):
failed if any case failed, with the first failure's message (in the job's order of cases) and the penalty
as cost; the cases whose simulation ran, with their terms; the time as the sum of the cases' times and the
worker processes that ran them. evaluate_case times a case from its start to its end. Each test builds the
expected record by hand.
"""

import time

from blocks.errors import SimulationError
from blocks.optimise import evaluate
from blocks.optimise.evaluate import EvalSpec, combine_cases, evaluate_case

SPEC = EvalSpec(netlist="/nowhere/n.yaml", fixed=(), cases=(("empty", ()), ("full", ()), ("half", ())), terms=(),
                combine="worst", penalty=1e9)


def part(case, cost, error=None, terms=True, seconds=0.5, pid=100):
    return {"case": case, "terms": {"pos": cost} if terms else None, "cost": None if error else cost,
            "error": error, "warnings": [], "seconds": seconds, "pid": pid}


def test_a_case_whose_simulation_failed_is_left_out_of_the_cases_and_fails_the_evaluation():
    """Parts given in any order: 'half' failed in simulation (no terms), 'full' had a non-finite term (terms,
    but an error). The record: failed, the penalty as cost, the error of 'full' (first in the job's order of
    cases), only the cases that have terms, time 0.5 + 0.25 + 0.125 s, the pids sorted once each."""
    parts = [part("half", None, error="load case 'half': solver", terms=False, seconds=0.125, pid=300),
             part("full", 7.0, error="load case 'full': cost term pos is not finite", seconds=0.25, pid=100),
             part("empty", 2.0, seconds=0.5, pid=200)]
    record = combine_cases(SPEC, parts)
    assert record["status"] == "failed" and record["cost"] == 1e9
    assert record["error"] == "load case 'full': cost term pos is not finite"
    assert set(record["cases"]) == {"empty", "full"}
    assert list(record["cases"]) == ["empty", "full"]
    assert record["seconds"] == 0.875
    assert record["pids"] == [100, 200, 300]


def test_the_cases_costs_are_combined_and_a_missing_pid_is_not_listed():
    """All cases ok: cost = the worst of 2, 7 and 3 (combine 'worst'); a part without a pid (None: it never
    reached a worker) adds no pid."""
    parts = [part("empty", 2.0, pid=None), part("full", 7.0, pid=5), part("half", 3.0, pid=5)]
    record = combine_cases(SPEC, parts)
    assert record["status"] == "ok" and record["cost"] == 7.0 and record["error"] is None
    assert record["pids"] == [5]
    assert record["cases"]["full"] == {"terms": {"pos": 7.0}, "cost": 7.0, "seconds": 0.5, "pid": 5}


class SlowFailingCircuit:
    """A circuit whose simulation takes 30 ms and then fails, as a solver that gives up does."""

    class settings:
        @staticmethod
        def with_(**kw):
            return None

    def simulate(self, overrides, settings=None):
        time.sleep(0.03)
        raise SimulationError("the solver gave up at t = 0.1 s")


def test_a_case_is_timed_from_its_start_to_its_end(monkeypatch):
    """'seconds' is the time the case took: at least the 30 ms the simulation took, at most the time the call
    took as measured around it. The failure is recorded, not raised."""
    monkeypatch.setattr(evaluate, "circuit_for", lambda netlist, sources=(): SlowFailingCircuit())
    spec = EvalSpec(netlist="/nowhere/n.yaml", fixed=(), cases=(("nominal", ()),), terms=())
    started = time.perf_counter()
    out = evaluate_case(spec, {"Kp": 2.0}, 0)
    took = time.perf_counter() - started
    assert out["error"] is not None and "gave up" in out["error"] and out["cost"] is None
    assert 0.03 <= out["seconds"] <= took + 1e-6
