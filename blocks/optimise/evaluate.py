"""One evaluation: a design's parameter values -> a simulation per load case -> cost terms -> one cost.

    spec = EvalSpec(netlist="/abs/drive_line.yaml", fixed={}, cases=(("nominal", {}),), terms=(...), ...)
    record = evaluate_design(spec, {"Kp": 6.0, "Kv": 0.35})

For each load case the overrides are, in order of precedence: the design's free parameters, the load
case's values, the job's fixed ``set:`` values (all SI, by qualified parameter name). The load cases of a
design are independent simulations; the parallel executors run them as tasks of their own
(:func:`evaluate_case`) and put the record together when the last one is back (:func:`combine_cases`),
so that a job with several load cases keeps every worker busy even when the method asks for one design
at a time. Each case's cost is
sum_i weight_i * term_i (:mod:`blocks.optimise.costs`); the cases' costs are combined (sum, mean, worst).

A failed simulation (:class:`~blocks.errors.SimulationError`), a value the netlist refuses
(:class:`~blocks.netlist.parameters.ParameterError` or a netlist error at evaluation), or a non-finite
term gives status "failed", the error's message and the job's penalty as cost; it never raises.
Cavitation warnings are kept with the record.

With ``solver: fixed`` a simulation normally runs again at twice the step to say whether the step is too
long (:mod:`blocks.solve.step_check`, half a run more). An optimisation's evaluations skip that check
(``check_fixed_step`` False): thousands of designs would pay it, and only the design reported is run
again with it (:func:`blocks.optimise.report.write_optimise_report`). A sweep reports every point, so each
point is checked.

The circuit is loaded once per process (``Circuit.from_file``; compiled code comes from the disk cache)
and kept for every later evaluation in that process, under the digests of the files it is built from as
the job read them (``Job.sources``): a worker that outlives a job (a Dask cluster, a Python session) builds
the circuit again when a later job's netlist or one of its files has changed, and a file changed between
the job's start and a worker's first load fails that evaluation with a message rather than evaluating the
design on another circuit. A lock makes a worker with several threads run one simulation at a time.
"""

from __future__ import annotations

import math
import os
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from blocks.errors import VphsError
from blocks.optimise.costs import Term, combine, evaluate_term

_CIRCUITS: dict[tuple, tuple] = {}  # (netlist, digests given) -> (circuit, its files' digests), most recent last
_KEPT = 4  # circuits a process keeps (each job's own)
_LOCK = threading.Lock()


@dataclass(frozen=True)
class EvalSpec:
    netlist: str  # absolute path (workers on other machines need a shared file system)
    fixed: tuple[tuple[str, float], ...]
    cases: tuple[tuple[str, tuple[tuple[str, float], ...]], ...]
    terms: tuple[Term, ...]
    combine: str = "sum"
    penalty: float = 1e9
    check_fixed_step: bool = False  # solver fixed: run each simulation again at twice the step (a sweep's)
    sources: tuple[tuple[str, str], ...] = ()  # every file the circuit is built from -> its digest (Job.sources)


def circuit_for(netlist: str, sources: tuple[tuple[str, str], ...] = ()):
    """The compiled circuit of ``netlist`` whose files have the digests ``sources``, loaded once per process; a
    file that no longer has its digest is a :class:`VphsError`. With no digests given, the files as they are
    now: a kept circuit whose files have changed since it was built is built again."""
    key = (netlist, sources)
    kept = _CIRCUITS.pop(key, None)
    if kept is not None and not sources and _digests(kept[0], netlist) != kept[1]:
        kept = None
    if kept is None:
        from blocks.circuit import Circuit

        circuit = Circuit.from_file(netlist)
        now = _digests(circuit, netlist)
        changed = sorted(name for name, digest in sources if now.get(name) != digest)
        if changed:
            raise VphsError(f"{netlist}: {', '.join(changed)} changed since the job read it: this design would be "
                            f"evaluated on another circuit than the others; start the job again")
        kept = (circuit, now)
    _CIRCUITS[key] = kept  # the most recent last
    while len(_CIRCUITS) > _KEPT:
        del _CIRCUITS[next(iter(_CIRCUITS))]
    return kept[0]


def _digests(circuit, netlist: str) -> dict[str, str]:
    """The digests of every file ``circuit`` is built from, named as :attr:`Job.sources` names them."""
    from blocks.optimise.job import source_digests

    return source_digests(circuit.flat.files, Path(netlist).resolve().parent)


def case_overrides(spec: EvalSpec, design: dict[str, float], case: tuple) -> dict[str, float]:
    overrides = dict(spec.fixed)
    overrides.update(dict(case[1]))
    overrides.update(design)
    return overrides


def evaluate_case(spec: EvalSpec, design: dict[str, float], k: int) -> dict:
    """Load case ``k`` of ``design``: {"case", "terms", "cost", "error", "warnings", "seconds", "pid"}; the
    terms are None if the simulation failed, the cost None if anything failed."""
    started = time.perf_counter()
    name = spec.cases[k][0]
    label = f"load case '{name}': " if len(spec.cases) > 1 else ""
    part = {"case": name, "terms": None, "cost": None, "error": None, "warnings": [], "pid": os.getpid()}
    with _LOCK:
        try:
            circuit = circuit_for(spec.netlist, spec.sources)
            settings = None if spec.check_fixed_step else circuit.settings.with_(fixed_step_check=False)
            result = circuit.simulate(case_overrides(spec, design, spec.cases[k]), settings=settings)
        except VphsError as exc:  # SimulationError, ParameterError, NetlistError
            part["error"] = f"{label}{exc}"
        except Exception as exc:  # a bug, not the design's fault: recorded as such, the job goes on
            part["error"] = f"{label}internal error: {type(exc).__name__}: {exc}"
        else:
            part["warnings"] = [f"{name}: {w}" if len(spec.cases) > 1 else w for w in result.warnings]
            values = {term.name: evaluate_term(term, result.t, result) for term in spec.terms}
            bad = [key for key, v in values.items() if not math.isfinite(v)]
            # JSON has no inf/nan: a non-finite term is written as null (and fails the evaluation)
            part["terms"] = {key: (v if math.isfinite(v) else None) for key, v in values.items()}
            if bad:
                part["error"] = f"{label}cost term {', '.join(bad)} is not finite"
            else:
                part["cost"] = sum(t.weight * values[t.name] for t in spec.terms)
    part["seconds"] = round(time.perf_counter() - started, 6)
    return part


def combine_cases(spec: EvalSpec, parts: list[dict]) -> dict:
    """The evaluation's record from its load cases (any order): failed if any case failed (the first
    failure's message, the penalty as cost), else the cases' costs combined."""
    parts = sorted(parts, key=lambda p: [c[0] for c in spec.cases].index(p["case"]))
    errors = [p["error"] for p in parts if p["error"]]
    cost = spec.penalty if errors else combine([p["cost"] for p in parts], spec.combine)
    return {"status": "failed" if errors else "ok", "cost": cost,
            "cases": {p["case"]: {"terms": p["terms"], "cost": p["cost"], "seconds": p["seconds"], "pid": p["pid"]}
                      for p in parts if p["terms"] is not None},
            "error": errors[0] if errors else None, "warnings": [w for p in parts for w in p["warnings"]][:5],
            "seconds": round(sum(p["seconds"] for p in parts), 6), "pids": sorted({p["pid"] for p in parts if p["pid"] is not None})}


def evaluate_design(spec: EvalSpec, design: dict[str, float]) -> dict:
    """Every load case of ``design``, one after the other, and the record for the evaluation log."""
    return combine_cases(spec, [evaluate_case(spec, design, k) for k in range(len(spec.cases))])
