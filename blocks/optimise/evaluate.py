"""One evaluation: a design's parameter values -> a simulation per load case -> cost terms -> one cost.

    spec = EvalSpec(netlist="/abs/drive_line.yaml", fixed={}, cases=(("nominal", {}),), terms=(...), ...)
    record = evaluate_design(spec, {"Kp": 6.0, "Kv": 0.35})

For each load case the overrides are, in order of precedence: the design's free parameters, the load
case's values, the job's fixed ``set:`` values (all SI, by qualified parameter name). Each case's cost is
sum_i weight_i * term_i (:mod:`blocks.optimise.costs`); the cases' costs are combined (sum, mean, worst).

A failed simulation (:class:`~blocks.errors.SimulationError`), a value the netlist refuses
(:class:`~blocks.netlist.parameters.ParameterError` or a netlist error at evaluation), or a non-finite
term gives status "failed", the error's message and the job's penalty as cost; it never raises.
Cavitation warnings are kept with the record.

The circuit is loaded once per process (``Circuit.from_file``; compiled code comes from the disk cache)
and kept for every later evaluation in that process; a lock makes a worker with several threads run one
simulation at a time.
"""

from __future__ import annotations

import math
import os
import threading
import time
from dataclasses import dataclass

from blocks.errors import VphsError
from blocks.optimise.costs import Term, combine, evaluate_term

_CIRCUITS: dict[str, object] = {}
_LOCK = threading.Lock()


@dataclass(frozen=True)
class EvalSpec:
    netlist: str  # absolute path (workers on other machines need a shared file system)
    fixed: tuple[tuple[str, float], ...]
    cases: tuple[tuple[str, tuple[tuple[str, float], ...]], ...]
    terms: tuple[Term, ...]
    combine: str = "sum"
    penalty: float = 1e9


def circuit_for(netlist: str):
    """The compiled circuit of ``netlist``, loaded once per process."""
    circuit = _CIRCUITS.get(netlist)
    if circuit is None:
        from blocks.circuit import Circuit

        circuit = _CIRCUITS[netlist] = Circuit.from_file(netlist)
    return circuit


def case_overrides(spec: EvalSpec, design: dict[str, float], case: tuple) -> dict[str, float]:
    overrides = dict(spec.fixed)
    overrides.update(dict(case[1]))
    overrides.update(design)
    return overrides


def evaluate_design(spec: EvalSpec, design: dict[str, float]) -> dict:
    """Simulate every load case of ``design`` and cost it; a record for the evaluation log (see module doc)."""
    started = time.perf_counter()
    with _LOCK:
        circuit = circuit_for(spec.netlist)
        cases, warnings, error = {}, [], None
        for case in spec.cases:
            name = case[0]
            try:
                result = circuit.simulate(case_overrides(spec, design, case))
            except VphsError as exc:  # SimulationError, ParameterError, NetlistError
                error = f"load case '{name}': {exc}" if len(spec.cases) > 1 else str(exc)
                break
            except Exception as exc:  # a bug, not the design's fault: recorded as such, the job goes on
                error = f"load case '{name}': internal error: {type(exc).__name__}: {exc}"
                break
            warnings += [f"{name}: {w}" if len(spec.cases) > 1 else w for w in result.warnings]
            values = {term.name: evaluate_term(term, result.t, result) for term in spec.terms}
            bad = [k for k, v in values.items() if not math.isfinite(v)]
            if bad:
                error = f"load case '{name}': cost term {', '.join(bad)} is not finite"
                cases[name] = {"terms": values, "cost": None}
                break
            cases[name] = {"terms": values, "cost": sum(t.weight * values[t.name] for t in spec.terms)}
    if error is None:
        cost = combine([c["cost"] for c in cases.values()], spec.combine)
        status = "ok"
    else:
        cost, status = spec.penalty, "failed"
    return {"status": status, "cost": cost, "cases": _finite(cases), "error": error,
            "warnings": warnings[:5], "seconds": round(time.perf_counter() - started, 6), "pid": os.getpid()}


def _finite(cases: dict) -> dict:
    """JSON has no inf/nan: non-finite term values are written as null (the record is 'failed' then)."""
    out = {}
    for name, case in cases.items():
        out[name] = {"terms": {k: (v if math.isfinite(v) else None) for k, v in case["terms"].items()},
                     "cost": case["cost"]}
    return out
