"""Optimisation and sweep jobs in YAML: the schema (pydantic), the loader and its one-line located errors.

A job file (YAML, ``netlists/jobs/*.yaml``) for ``vphs optimise`` and ``vphs sweep``::

    description: the drive line's controller   # free text
    name: controller                       # default: the file's stem; a plain name (no '/', '\\', '..'):
                                           # it names the default output folder out/<name>
    netlist: ../opt/drive_line.yaml        # relative to the job file
    output: out/controller                 # relative to the working directory; default out/<name>
    seed: 1                                # the methods' random numbers (default 0): same seed, same run
    workers: 2                             # local processes (default: every core); --workers overrides;
                                           # not together with a scheduler
    scheduler: tcp://10.0.0.5:8786         # optional Dask scheduler; --scheduler overrides (the workers
                                           # must read the netlist at the same path)
    set: {V_line: "1 l", Kvp: "Kv/4"}      # fixed overrides for every evaluation (an expression too)
    parameters:                            # the free parameters: qualified names, bounds, log scaling
      Kp: {min: 1, max: 30, log: true}     # log: searched evenly in decades (min > 0)
      spool.wn: {min: "40 rad/s", max: "120 rad/s"}
    cost:
      combine: sum                         # over the load cases: sum | mean | worst
      penalty: 1e9                         # the cost of a failed simulation (default 1e9)
      terms:                               # cost = sum of weight * term per load case; >= 1 weight > 0
        pos: {kind: ise, signal: x, reference: x_ref, unit: mm, weight: 50}   # int ((x - x_ref)/mm)^2 dt
        vib: {kind: hp_ise, signal: pA, wn: "100 rad/s", zeta: 0.7071, weight: 3e-8}  # int (high-passed pA)^2 dt
        max_pos: {kind: max_abs, signal: x, reference: x_ref, unit: mm, weight: 0}    # weight 0: reported only
        settle: {kind: ise, signal: x, reference: "1 m", t_from: "2.5 s", t_to: "3 s"}  # a constant reference,
                                                                                      # over a time window
    load_cases:                            # parameter overrides; each case is simulated per design
      empty: {m_load: "0 kg"}
      full: {m_load: "15 t"}
    algorithm: {method: complex, max_evaluations: 300, rfak: 0, gamma: 0}   # one method and its settings
    sweep:                                 # for 'vphs sweep': one or two parameters
      parameters: {Kp: [2, 4, 8], Kv: {min: 0.2, max: 0.6, points: 5, log: false}}
      combine: grid                        # grid (every combination) | list (the i-th values together)

Cost terms (:mod:`blocks.optimise.costs`) read a logged signal of the netlist (``outputs:``), minus a
``reference`` (another logged signal, or a constant value; none: 0), in the term's ``unit`` (default:
the signal's SI unit), over ``t_from`` <= t <= ``t_to`` (default: the whole run):
``ise`` = int e^2 dt, ``max_abs`` = max |e|, ``hp_ise`` = int h^2 dt with h the signal through the
high-pass s^2/(s^2 + 2*zeta*wn*s + wn^2) (``wn`` required, ``zeta`` default 0.7071, no reference). The
high-pass starts in steady state at the first sample: a constant initial value gives no output, only
what changes after t = 0 does.

Methods and their settings (defaults):
    complex: max_evaluations 500, points max(2n, 3) (the size of the complex, at least n + 1), alpha 1.3
             (reflection distance), n0 4 (retraction law), rfak 0 (randomisation), gamma 0 (forgetting),
             tol_x 1e-4 (stop when the complex's spread in every parameter is below this fraction of its
             range), tol_f 1e-5 (stop when the relative spread of its costs is below this),
             max_retractions 30, candidates auto (= the workers: how many of the reflection and the
             retractions that may follow it are evaluated at once; see blocks.optimise.complex:
             max_evaluations counts the evaluations on the method's path, not the candidates evaluated
             ahead and discarded, so that the result does not depend on the workers)
    nelder_mead: max_evaluations 500, xatol 1e-4, fatol 1e-6, start random | netlist, adaptive false
             (one evaluation at a time: it uses one worker)
    differential_evolution: max_evaluations 1000, popsize 15 (a generation is popsize * n designs, at
             least 5, 6 for rand2bin and rand2exp, each evaluated in parallel; the first is a Latin
             hypercube sample of the box), tol 0.01, atol 0, mutation [0.5, 1.0] (a constant 0 <= F < 2,
             or a dither range [min, max] with 0 <= min < max < 2), recombination 0.7, strategy best1bin
             (scipy's: best1bin, best1exp, rand1bin, rand1exp, rand2bin, rand2exp, randtobest1bin,
             randtobest1exp, currenttobest1bin, currenttobest1exp, best2bin, best2exp), polish false.
             max_evaluations must hold one generation; below two it only samples (the report says so).
    The tolerances (tol_x, tol_f, xatol, fatol, tol, atol) are finite numbers >= 0 (xatol > 0).
Besides the method's evaluations, ``vphs optimise`` evaluates the netlist's own design first (its values of
the free parameters, if inside the bounds) and the report compares the best with it.
A point the method asks for again -- the same coordinates, bit for bit: a design clipped onto a bound once
more, or nelder_mead's ``start: netlist``, which is the netlist's own design -- is answered from its earlier
record, not simulated again (blocks.optimise.repeats); it is still an evaluation of the method and counts
against max_evaluations, so the path and the result are those of simulating it again, and the report says
how many of the evaluations were such repeats.
Outputs: ``vphs optimise`` writes into ``output``, ``vphs sweep`` into ``output``/sweep.
A failed simulation costs ``penalty``: choose it above any cost a working design can have (the report
warns when working designs cost more).

There are no constraints (a ``constraints:`` key is refused). A limit is expressed as a cost that is zero
while it holds: log the excess in the netlist with a ``dead_band`` block (zero inside [lower, upper]) and
give a term on it a large weight, e.g. for pA <= 250 bar::

    # netlist: components: {pA_sensor: {type: pressure_sensor}, over: {type: dead_band,
    #                        params: {lower: "-1000 bar", upper: "250 bar"}}}
    #          nets: A: {ports: [..., pA_sensor.port]}, p_over: [pA_sensor.p, over.u]
    #          outputs: {pA_over: {of: over.y, unit: bar}}
    limit: {kind: max_abs, signal: pA_over, unit: bar, weight: 1000}

(a soft limit: a design beyond it is not refused, but costs the more the further it goes).

Values are numbers in SI or "<number> <unit>" strings, checked against the parameter's unit and bounds.
A value of ``set:`` or of a load case may also be an expression, as the netlist's ``parameters:`` take
(``"0.085 + m_load*0.075**2/39**2"``, ``"2*w0 + 1 rad/s"``), over the netlist's parameters by their
qualified names. It is evaluated once, when the job is loaded, with the netlist's values and the job's plain
values in their place (``set:``'s, and for a load case also that case's), so it may not read, itself or
through the netlist's expressions, a parameter the job varies, one a load case sets (an expression in
``set:``), or another expression of the same section: it would not follow them (write such an expression in
the netlist, where it does).
The reports, sweep.csv and the console show each free parameter in the unit the job wrote its bounds (or
its sweep values) in; for bare numbers, in the unit the netlist writes its value in, else in SI
(blocks.optimise.display).
A load case's value wins over the same parameter in ``set:``; a varied parameter may be in neither.
The methods work in normalised coordinates z in [0, 1] per free parameter:
value = min + z*(max - min), or with ``log: true`` value = min * (max/min)**z; their tolerances
(tol_x, xatol) are therefore fractions of each parameter's range (of its decades with log).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal, Union

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator
from pydantic_core import PydanticCustomError

from blocks.errors import NetlistError
from blocks.netlist.spec import Count, Number, Value
from blocks.netlist.yaml_source import Located, document_path, in_words, read_yaml, shown_key, unknown_key, wrong_kind
from blocks.optimise.complex import ComplexSettings
from blocks.optimise.costs import Term
from blocks.optimise.display import as_written, plain, shown, written_unit
from blocks.optimise.scipy_methods import DESettings, NelderMeadSettings
from blocks.units import GENERIC, UnitError, nearest, parse_unit, quantity, si_name, si_value


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", str_strip_whitespace=True)


class FreeParameter(Strict):
    min: Value
    max: Value
    log: bool = False


class TermSpec(Strict):
    kind: Literal["ise", "max_abs", "hp_ise"]
    signal: str
    reference: Value | None = None
    unit: str | None = None
    weight: Number = Field(1.0, ge=0, allow_inf_nan=False)
    wn: Value | None = None
    zeta: Number = Field(0.7071067811865476, gt=0, allow_inf_nan=False)
    t_from: Value | None = None
    t_to: Value | None = None


class CostSpec(Strict):
    terms: dict[str, TermSpec] = Field(min_length=1)
    combine: Literal["sum", "mean", "worst"] = "sum"
    penalty: Number = Field(1e9, gt=0, allow_inf_nan=False)


class SweepRange(Strict):
    min: Value
    max: Value
    points: Count = Field(ge=2, le=100_000)
    log: bool = False


class SweepSpec(Strict):
    parameters: dict[str, Union[list[Value], SweepRange]] = Field(min_length=1, max_length=2)
    combine: Literal["grid", "list"] = "grid"


class ComplexSpec(Strict):
    method: Literal["complex"]
    max_evaluations: Count = Field(500, ge=1)
    points: Count | None = Field(None, ge=2)
    alpha: Number = Field(1.3, gt=0, allow_inf_nan=False)
    n0: Number = Field(4.0, gt=0, allow_inf_nan=False)
    rfak: Number = Field(0.0, ge=0, allow_inf_nan=False)
    gamma: Number = Field(0.0, ge=0, allow_inf_nan=False)
    tol_x: Number = Field(1e-4, ge=0, allow_inf_nan=False)
    tol_f: Number = Field(1e-5, ge=0, allow_inf_nan=False)
    max_retractions: Count = Field(30, ge=0)
    candidates: Union[Count, Literal["auto"]] = "auto"


class NelderMeadSpec(Strict):
    method: Literal["nelder_mead"]
    max_evaluations: Count = Field(500, ge=1)
    xatol: Number = Field(1e-4, gt=0, allow_inf_nan=False)
    fatol: Number = Field(1e-6, ge=0, allow_inf_nan=False)
    start: Literal["random", "netlist"] = "random"
    adaptive: bool = False


DE_STRATEGIES = ("best1bin", "best1exp", "rand1bin", "rand1exp", "rand2bin", "rand2exp", "randtobest1bin",
                 "randtobest1exp", "currenttobest1bin", "currenttobest1exp", "best2bin", "best2exp")
"""scipy.optimize.differential_evolution's strategies (its docstring's list; a test checks scipy takes each)."""


class DESpec(Strict):
    method: Literal["differential_evolution"]
    max_evaluations: Count = Field(1000, ge=1)
    popsize: Count = Field(15, ge=1)
    tol: Number = Field(0.01, ge=0, allow_inf_nan=False)
    atol: Number = Field(0.0, ge=0, allow_inf_nan=False)
    mutation: Union[Number, tuple[Number, Number]] = (0.5, 1.0)
    recombination: Number = Field(0.7, ge=0, le=1)
    strategy: str = "best1bin"
    polish: bool = False

    @field_validator("mutation", mode="before")
    @classmethod
    def _mutation_shape(cls, value):
        if isinstance(value, (list, tuple)) and len(value) != 2:
            raise PydanticCustomError("de_mutation", "a list of {count} values; give one number 0 <= F < 2, or a "
                                      "dither range [min, max] with 0 <= min < max < 2", {"count": len(value)})
        return value

    @field_validator("mutation")
    @classmethod
    def _mutation(cls, value):
        """scipy's rule, said before the run (scipy's own ValueError came out as an internal error): a
        constant 0 <= F < 2, or a dither range [min, max] with 0 <= min < max < 2 (scipy refuses 2 in both)."""
        if isinstance(value, tuple):
            low, high = value
            if not (math.isfinite(low) and math.isfinite(high) and 0 <= low < high < 2):
                raise PydanticCustomError("de_mutation", "[{low}, {high}] is not a dither range: give [min, max] with "
                                          "0 <= min < max < 2 (or one number 0 <= F < 2)",
                                          {"low": _plain(low), "high": _plain(high)})
        elif not (math.isfinite(value) and 0 <= value < 2):
            raise PydanticCustomError("de_mutation", "{value} is outside [0, 2): give a number 0 <= F < 2, or a "
                                      "dither range [min, max] with 0 <= min < max < 2", {"value": _plain(value)})
        return value

    @field_validator("strategy")
    @classmethod
    def _strategy(cls, value):
        if value not in DE_STRATEGIES:
            raise PydanticCustomError("de_strategy", "unknown strategy '{value}' (strategies: {known})",
                                      {"value": value, "known": ", ".join(DE_STRATEGIES)})
        return value


def _plain(number: float) -> str:
    """A number as the job likely wrote it: 2 rather than 2.0."""
    return f"{number:g}"


METHODS = {"complex": ComplexSpec, "nelder_mead": NelderMeadSpec, "differential_evolution": DESpec}


class JobFile(Strict):
    description: str = ""
    name: str | None = None
    netlist: str
    output: str | None = None
    seed: Count = Field(0, ge=0)
    workers: Count | None = Field(None, ge=1)
    scheduler: str | None = None
    set: dict[str, Value] = Field(default_factory=dict)
    parameters: dict[str, FreeParameter] = Field(default_factory=dict)
    cost: CostSpec
    load_cases: dict[str, dict[str, Value]] = Field(default_factory=dict)
    algorithm: dict[str, object] | None = None
    sweep: SweepSpec | None = None


_MODELS = {(): JobFile, ("cost",): CostSpec, ("sweep",): SweepSpec}


@dataclass
class FreeParam:
    name: str
    lower: float
    upper: float
    log: bool
    unit: str  # shown in (blocks.optimise.display): the unit the job wrote the bounds in, ... ("": a plain number)


@dataclass
class Job:
    """A loaded, checked job: every value in SI, every name resolved against the netlist."""

    file: str
    name: str
    netlist: str  # absolute
    output: Path
    seed: int
    workers: int | None
    scheduler: str | None
    fixed: dict[str, float]
    free: list[FreeParam]
    terms: list[Term]
    cases: list[tuple[str, dict[str, float]]]
    combine: str
    penalty: float
    method: str | None
    settings: object | None
    sweep_names: list[str] = field(default_factory=list)
    sweep_points: list[dict[str, float]] = field(default_factory=list)
    fingerprint: str = ""
    sources: dict[str, str] = field(default_factory=dict)  # every file the circuit is built from -> a digest
    start_values: dict[str, float] = field(default_factory=dict)  # the netlist's values of the free parameters
    units: dict[str, str] = field(default_factory=dict)  # parameter -> the unit it is shown in (display.py)
    si_units: dict[str, str] = field(default_factory=dict)  # parameter -> the SI unit its values are in
    sweep_combine: str = "grid"
    start: str = "random"  # nelder_mead: start at a seeded random point or at the netlist's values
    warnings: list[str] = field(default_factory=list)  # said before the run (:meth:`_Resolver.edges_failing`)

    @property
    def lower(self) -> np.ndarray:
        return np.zeros(len(self.free))

    @property
    def upper(self) -> np.ndarray:
        return np.ones(len(self.free))

    def values(self, z) -> dict[str, float]:
        """Normalised coordinates -> SI values of the free parameters."""
        out = {}
        for p, zi in zip(self.free, z):
            zi = float(min(max(zi, 0.0), 1.0))
            out[p.name] = p.lower * (p.upper / p.lower) ** zi if p.log else p.lower + zi * (p.upper - p.lower)
        return out

    def coordinates(self, values: dict[str, float]) -> np.ndarray:
        """SI values -> normalised coordinates (clipped into [0, 1])."""
        z = []
        for p in self.free:
            v = values[p.name]
            if p.log:
                zi = math.log(v / p.lower) / math.log(p.upper / p.lower) if v > 0 else 0.0
            else:
                zi = (v - p.lower) / (p.upper - p.lower)
            z.append(min(max(zi, 0.0), 1.0))
        return np.array(z)

    def netlist_design_outside(self) -> str:
        """Why the netlist's own design (its values of the free parameters) is not a design of the job: the
        values outside the bounds, as a phrase; "" if it lies within them."""
        outside = [f"{p.name} = {shown(self.start_values[p.name], p.unit)} is outside [{shown(p.lower, p.unit)}, "
                   f"{shown(p.upper, p.unit)}]" for p in self.free if not p.lower <= self.start_values[p.name] <= p.upper]
        return "; ".join(outside)

    def spec(self, check_fixed_step: bool = False):
        """What a worker needs to evaluate a design (``check_fixed_step``: see :mod:`blocks.optimise.evaluate`)."""
        from blocks.optimise.evaluate import EvalSpec

        return EvalSpec(self.netlist, tuple(self.fixed.items()),
                        tuple((name, tuple(values.items())) for name, values in self.cases),
                        tuple(self.terms), self.combine, self.penalty, check_fixed_step,
                        tuple(sorted(self.sources.items())))


def load_job(file: str | Path) -> Job:
    """Read and check a job file against its netlist; :class:`NetlistError` (file:line:col: message) if wrong."""
    located = read_yaml(file)
    model = _validate(located)
    return _Resolver(located, model).job()


def _validate(located: Located) -> JobFile:
    if not isinstance(located.data, dict):
        raise located.error((), "a job must be a mapping with netlist:, parameters:, cost:, algorithm: or sweep:")
    try:
        model = JobFile.model_validate(located.data)
    except ValidationError as exc:
        raise (wrong_kind(located, "an optimisation job") or _located(located, exc, ())) from None
    if model.scheduler and model.workers is not None:
        raise located.error(("workers",), "workers: sets the local processes, which a job with scheduler: does not "
                                          "use (the Dask cluster's workers evaluate); give one or the other")
    if model.scheduler:
        from blocks.optimise.executors import scheduler_problem

        problem = scheduler_problem(model.scheduler)
        if problem:
            raise located.error(("scheduler",), f"scheduler: '{model.scheduler}': {problem}")
    if model.algorithm is not None:
        method = model.algorithm.get("method")
        if method not in METHODS:
            raise located.error(("algorithm", "method") if method is not None else ("algorithm",),
                                f"algorithm.method: " + (f"unknown method '{method}'" if method is not None else "missing")
                                + f" (methods: {', '.join(METHODS)})")
        try:
            METHODS[method].model_validate(model.algorithm)
        except ValidationError as exc:
            raise _located(located, exc, ("algorithm",), METHODS[method]) from None
    return model


def _located(located: Located, exc: ValidationError, prefix: tuple, model=None) -> NetlistError:
    """The first pydantic error as 'file:line:col: where: what' (the style of the netlist loader)."""
    errors = exc.errors()
    first = max(errors, key=lambda e: len(e["loc"]))  # of a union's branches, the one that got furthest
    path = prefix + document_path(_get(located.data, prefix), first["loc"], _ALL_FIELDS)
    where = ".".join(shown_key(p) for p in path) or "job"
    message = in_words(first)
    if path[:2] == ("sweep", "parameters") and len(path) == 3:
        message = "expected a list of values, or {min:, max:, points:, log:}"
    elif first["type"] == "extra_forbidden":
        parent = model if model is not None and len(path) == len(prefix) + 1 else _parent_model(path)
        message = unknown_key(path[-1], parent.model_fields) if parent is not None else \
            f"unknown key '{shown_key(path[-1])}'"
    elif first["type"] == "missing":
        message = f"missing '{first['loc'][-1]}'"
    return located.error(path, f"{where}: {message}")


def _get(data, path):
    for key in path:
        data = data[key]
    return data


def _parent_model(path: tuple):
    if path[:-1] in _MODELS:
        return _MODELS[path[:-1]]
    if len(path) == 3 and path[0] == "parameters":
        return FreeParameter
    if len(path) == 4 and path[:2] == ("cost", "terms"):
        return TermSpec
    if len(path) == 4 and path[:2] == ("sweep", "parameters"):
        return SweepRange
    return None


_ALL_FIELDS = {name for m in (JobFile, CostSpec, SweepSpec, SweepRange, TermSpec, FreeParameter, *METHODS.values())
               for name in m.model_fields}


def source_digests(files: list[str], root: Path) -> dict[str, str]:
    """File -> digest of its bytes, for every file a circuit is built from (``FlatCircuit.files``: the
    netlist, its subsystem files, its data files); ``--resume`` refuses a log when one of them changed.
    Files are named relative to ``root`` (the netlist's folder), so that a project moved or mounted
    elsewhere still resumes, as the job's fingerprint does."""
    return {os.path.relpath(file, root): hashlib.sha256(Path(file).read_bytes()).hexdigest()[:16] for file in files}


def _dimension(output):
    """The dimension of a logged signal: its SI unit, or for a generic signal block the unit a port on its
    net declares (:class:`blocks.circuit.ResolvedOutput`), else the netlist's display unit
    (x: {of: travel.y, unit: mm} is a length); None if none says."""
    for text in (output.unit, output.declared, output.display_unit):
        if text not in ("1", "", None, GENERIC):
            return parse_unit(text)
    return None


def _origin(exc: NetlistError) -> str:
    """' (rig.yaml:10:32)': where in the netlist a check of its values failed ('' if it names no file)."""
    if not exc.file:
        return ""
    return f" ({exc.file}:{exc.line}:{exc.column})" if exc.line is not None else f" ({exc.file})"


class _Resolver:
    """Names, units and bounds of a validated job, checked against its netlist."""

    def __init__(self, located: Located, model: JobFile):
        self.located, self.model = located, model
        self.error = located.error
        self.start = "random"

    def job(self) -> Job:
        from blocks.circuit import Circuit

        m, here = self.model, Path(self.located.file).parent
        netlist = (here / m.netlist).resolve()
        if not netlist.is_file():
            raise self.error(("netlist",), f"netlist: file not found: {netlist}")
        self.circuit = Circuit.from_file(netlist, compile=False)
        self.table = self.circuit.flat.parameters
        self.entries = self.table.entries
        name = self.name()
        varied = dict.fromkeys([*m.parameters, *(m.sweep.parameters if m.sweep else ())], "the job varies")
        by_case = {k: f"load case {case} sets" for case, values in reversed(m.load_cases.items()) for k in values}
        fixed = self.settings(m.set, ("set",), {}, {**by_case, **varied})
        free = [self.free_param(k, p) for k, p in m.parameters.items()]
        cases = [(case, self.settings(values, ("load_cases", case), fixed, varied))
                 for case, values in m.load_cases.items()] or [("nominal", {})]
        terms = [self.term(k, t) for k, t in m.cost.terms.items()]
        if not any(t.weight > 0 for t in terms):
            raise self.error(("cost", "terms"), "cost.terms: every weight is 0, so every design would cost 0 and "
                             "nothing could be minimised or compared; give at least one term a weight above 0")
        method, settings = self.algorithm()
        sweep_names, sweep_points = self.sweep()
        varied = set(m.parameters) | set(sweep_names)
        for case, values in m.load_cases.items():
            for k in values:
                if k in varied:
                    raise self.error(("load_cases", case, k), f"load_cases.{case}.{k}: {k} is varied by the job; "
                                     f"it cannot also be set by a load case")
        for case, values in cases:  # every case must evaluate (expressions, cross-parameter checks)
            try:
                self.circuit.vectors({**fixed, **values})
            except NetlistError as exc:
                where = f"load_cases.{case}" if m.load_cases else "set"
                origin = _origin(exc)
                raise self.error(("load_cases", case) if m.load_cases else ("set",),
                                 f"{where}: with these values {exc.message}{origin}") from None
        start = self.circuit.vectors(fixed).values
        job = Job(
            file=self.located.file, name=name, netlist=str(netlist), output=self.output(name),
            seed=m.seed, workers=m.workers, scheduler=m.scheduler, fixed=fixed, free=free, terms=terms,
            cases=cases, combine=m.cost.combine, penalty=m.cost.penalty, method=method, settings=settings,
            sweep_names=sweep_names, sweep_points=sweep_points,
            start_values={p.name: float(start[p.name]) for p in free},
            units={k: self.display_unit(k) for k in list(m.parameters) + sweep_names},
            si_units={k: self.si_unit(k) for k in list(m.parameters) + sweep_names}, start=self.start,
            sweep_combine=m.sweep.combine if m.sweep else "grid",
        )
        job.fingerprint = self.fingerprint(netlist)
        job.sources = source_digests(self.circuit.flat.files, Path(netlist).resolve().parent)
        job.warnings = self.edges_failing(free, fixed, cases, job.units)
        return job

    def edges_failing(self, free: list[FreeParam], fixed: dict[str, float], cases: list, units: dict[str, str]
                      ) -> list[str]:
        """A line for each free parameter at a bound of its range where the blocks' checks of their values
        together refuse the design (a relief's p_set free up to 200 bar, its p_open fixed at 160 bar), the
        others at the netlist's values, in the first load case that refuses it: such designs fail and cost the
        penalty, which the job should know before it runs rather than read in its count of failures."""
        from blocks.optimise.display import shown

        lines = []
        for p in free:
            for edge, value in (("min", p.lower), ("max", p.upper)):
                for case, values in cases:
                    try:
                        self.circuit.vectors({**fixed, **values, p.name: value})
                    except NetlistError as exc:
                        where = f"load case {case}, " if len(cases) > 1 else ""
                        lines.append(f"{self.located.file}: parameters.{p.name}.{edge} = "
                                     f"{shown(value, units[p.name])} ({where}the rest at the netlist's values) is "
                                     f"refused: {exc.message}{_origin(exc)}; designs there fail and cost the penalty")
                        break
        return lines

    def name(self) -> str:
        """The job's name (default: the file's stem). It names the default output folder out/<name>, so it
        must be a plain name: no path separator, not '.' or '..' (a folder outside out/)."""
        given = self.model.name
        if given is None:
            return Path(self.located.file).stem
        if given in ("", ".") or ".." in given or "/" in given or "\\" in given:
            raise self.error(("name",), f"name: '{given}' is not a plain name; it names the output folder "
                             f"(out/<name>), so give it without '/', '\\' or '..'")
        return given

    def output(self, name: str) -> Path:
        """The output folder (relative to the working directory, not to the job file); a file in its place
        is said now, located at output:, not when the log is first written."""
        from blocks.optimise.log import file_in_the_way

        given = self.model.output
        output = Path(given) if given else Path("out") / name
        blocker = file_in_the_way(output)
        if blocker is not None:
            what = f"output '{given}'" if given else f"the default output folder '{output}' (set output:)"
            raise self.error(("output",) if given else (), f"{what} is a file, not a folder" if blocker == output
                             else f"{what}: '{blocker}' is a file, not a folder")
        return output

    # ---- values ---------------------------------------------------------------------------------------
    def entry(self, name: str, path: tuple):
        entry = self.entries.get(name)
        if entry is None:
            hint = nearest(name, self.entries)
            raise self.error(path, f"'{name}' is not a parameter of {self.model.netlist}"
                             + (f" (did you mean {', '.join(hint)}?)" if hint else ""))
        if entry.elements is not None or isinstance(entry.constant, tuple):
            raise self.error(path, f"'{name}' is an array parameter; only single values can be set or varied")
        if name in self.table.derived:
            raise self.error(path, f"'{name}' is derived from {self.table.derived[name]}: set or vary that instead")
        return entry

    def si_unit(self, name: str) -> str:
        """The SI unit of ``name``'s values: its declared unit if named, else the SI unit of the dimension
        the netlist gives it ("" for a plain number or one the netlist does not say)."""
        entry = self.entries[name]
        if entry.unit not in (None, GENERIC):
            return plain(entry.unit)  # a ratio declared "1": "" as for any plain number
        dims = self.table.dimension(name)
        return "" if dims is None or dims.same_dimension(parse_unit("1")) else si_name(dims)

    def display_unit(self, name: str) -> str:
        """The unit ``name`` is shown in (the rule of :mod:`blocks.optimise.display`): as the job wrote its
        bounds or sweep values, else as the netlist wrote its value, else its SI unit."""
        free = self.model.parameters.get(name)
        swept = self.model.sweep.parameters.get(name) if self.model.sweep else None
        raws = [free.min, free.max] if free is not None else []
        raws += [swept.min, swept.max] if isinstance(swept, SweepRange) else (swept or [])
        entry = self.entries[name]
        netlist = entry.raw if entry.expression is None and isinstance(entry.constant, float) else None
        return plain(written_unit(*raws) or written_unit(netlist) or self.si_unit(name))

    def settings(self, raws: dict, path: tuple, given: dict[str, float], changed: dict[str, str]) -> dict[str, float]:
        """The values of ``raws`` (``set:``, or a load case's) in SI, by :meth:`value`, or for an expression
        over the netlist's parameters (as the netlist writes one: ``"2*w0 + 1 rad/s"``) its value with the
        netlist's values, ``given`` and the plain values of ``raws`` in their place. It is evaluated once,
        before the job changes anything: an expression that reads, itself or through the netlist's
        expressions, a parameter named in ``changed`` (-> what changes it), or another expression of ``raws``,
        is refused (it would not follow; such an expression belongs in the netlist)."""
        plain, expressions = {}, {}
        for k, raw in raws.items():
            where = ".".join(shown_key(p) for p in path + (k,))
            self.entry(k, path + (k,))
            entry = self.table.given_expression(k, raw, self.located, path + (k,), where)
            if entry is None:
                plain[k] = self.value(k, raw, path + (k,))
            else:
                expressions[k] = entry
        held = {**given, **plain}
        try:
            values = self.table.evaluate(held) if expressions else {}
        except NetlistError as exc:
            raise self.error(path, f"{'.'.join(path)}: with these values {exc.message}{_origin(exc)}") from None
        for k, value in self.table.given_values(expressions, values, held, changed, ".".join(path)).items():
            plain[k] = self.checked(k, value, raws[k], path + (k,))
        return {k: plain[k] for k in raws}

    def value(self, name: str, raw, path: tuple) -> float:
        """A job value for parameter ``name`` in SI, its unit and bounds checked."""
        self.entry(name, path[:-1] if path[-1] in ("min", "max") else path)
        where = ".".join(shown_key(p) for p in path)
        try:
            value = self.table.value_si(name, raw)
        except UnitError as exc:
            raise self.error(path, f"{where}: {exc}") from None
        return self.checked(name, value, raw, path)

    def checked(self, name: str, value: float, raw, path: tuple) -> float:
        """``value`` (SI), given as ``raw`` for ``name`` at ``path``, if it is finite and inside the netlist's
        bounds of ``name``."""
        entry, where = self.entries[name], ".".join(shown_key(p) for p in path)
        if not math.isfinite(value):
            raise self.error(path, f"{where}: {value} is not finite")
        if entry.bounds is not None:
            problem = entry.bounds.check(value)
            if problem:
                raise self.error(path, f"{where}: {as_written(raw)} is outside the netlist's bounds ({problem})")
        return value

    def free_param(self, name: str, p: FreeParameter) -> FreeParam:
        path = ("parameters", name)
        if name in self.model.set:
            raise self.error(path, f"parameters.{name}: also fixed in set:; a parameter is either free or fixed")
        bounds = self.bounds(name, p, path)
        if getattr(self.entries[name].bounds, "integer", False):
            raise self.error(path, f"parameters.{name}: a whole-number switch ({self.entries[name].bounds.description})"
                                   f" cannot be optimised; set it under set: or a load case")
        return FreeParam(name, *bounds, p.log, self.display_unit(name))

    def bounds(self, name: str, given: FreeParameter | SweepRange, path: tuple) -> tuple[float, float]:
        """The SI bounds ``given.min`` < ``given.max``; a message quotes them as the job wrote them."""
        lower, upper = self.value(name, given.min, path + ("min",)), self.value(name, given.max, path + ("max",))
        where = ".".join(shown_key(p) for p in path)
        if not upper > lower:
            raise self.error(path + ("max",), f"{where}: max ({as_written(given.max)}) must be above min "
                             f"({as_written(given.min)})")
        if given.log and not lower > 0:
            raise self.error(path + ("min",), f"{where}: log scaling needs min > 0, got {as_written(given.min)}")
        return lower, upper

    # ---- cost terms -----------------------------------------------------------------------------------
    def term(self, name: str, t: TermSpec) -> Term:
        path = ("cost", "terms", name)
        where = f"cost.terms.{name}"
        outputs = {o.name: o for o in self.circuit.outputs}
        signal = outputs.get(t.signal)
        if signal is None:
            hint = nearest(t.signal, outputs)
            raise self.error(path + ("signal",), f"{where}: '{t.signal}' is not a logged signal of the netlist "
                             + (f"(did you mean {', '.join(hint)}?)" if hint else f"(logged: {', '.join(outputs)})"))
        dims = _dimension(signal)
        scale, unit = 1.0, (t.unit or signal.unit)
        if t.unit is not None:
            try:
                parsed = parse_unit(t.unit)
            except UnitError as exc:
                raise self.error(path + ("unit",), f"{where}.unit: {exc}") from None
            if dims is not None and not parsed.same_dimension(dims):
                raise self.error(path + ("unit",), f"{where}.unit: '{t.unit}' does not fit signal {t.signal}, "
                                 f"which is in {dims.describe_dims()}")
            scale = parsed.factor
        elif dims is not None:
            unit = si_name(dims)
        reference, offset = None, 0.0
        if t.kind == "hp_ise":
            if t.reference is not None:
                raise self.error(path + ("reference",), f"{where}: hp_ise filters the signal itself; no reference")
            if t.wn is None:
                raise self.error(path, f"{where}: hp_ise needs wn, the high-pass corner (e.g. '100 rad/s')")
        elif t.wn is not None:
            raise self.error(path + ("wn",), f"{where}: wn belongs to hp_ise terms only")
        if isinstance(t.reference, str) and t.reference in outputs:
            ref_dims = _dimension(outputs[t.reference])
            if dims is not None and ref_dims is not None and not ref_dims.same_dimension(dims):
                raise self.error(path + ("reference",), f"{where}: reference {t.reference} is in "
                                 f"{ref_dims.describe_dims()}, signal {t.signal} in {dims.describe_dims()}")
            reference = t.reference
        elif t.reference is not None:
            try:
                offset = si_value(t.reference, dims)
            except UnitError as exc:
                hint = nearest(str(t.reference), outputs)
                raise self.error(path + ("reference",), f"{where}.reference: neither a logged signal"
                                 + (f" (did you mean {', '.join(hint)}?)" if hint else "")
                                 + f" nor a value: {exc}") from None
        wn = self.seconds_or(path, "wn", t.wn, "rad/s") if t.wn is not None else 0.0
        if t.wn is not None and not wn > 0:
            raise self.error(path + ("wn",), f"{where}.wn must be positive")
        t_from = self.seconds_or(path, "t_from", t.t_from, "s") if t.t_from is not None else None
        t_to = self.seconds_or(path, "t_to", t.t_to, "s") if t.t_to is not None else None
        term = Term(name, t.kind, t.signal, t.weight, reference, offset, scale, unit, wn, t.zeta, t_from, t_to)
        self.check_window(term, path)
        return term

    def check_window(self, term: Term, path: tuple) -> None:
        """Refuse a time window that keeps too few of the run's output samples for the term to mean anything.

        A window with no sample scores 0 (so does an integral over a single sample), whatever the design:
        t_from after t_to, t_from after the simulation's end, t_to before its start, or a window between two
        output samples. The samples are the ones every run logs (:func:`blocks.solve.run.output_times` of the
        netlist's simulation: settings; a load case sets parameters only, never the span), kept as the term
        keeps them (:func:`blocks.optimise.costs.window`)."""
        from blocks.optimise.costs import window
        from blocks.solve.run import output_times

        settings = self.circuit.settings
        where = f"cost.terms.{term.name}"
        if term.t_from is not None and term.t_to is not None and term.t_from > term.t_to:
            raise self.error(path + ("t_from",), f"{where}.t_from: {term.t_from:g} s is after t_to ({term.t_to:g} s)")
        if term.t_from is not None and term.t_from > settings.t_end:
            raise self.error(path + ("t_from",), f"{where}.t_from: {term.t_from:g} s is after the simulation's end "
                             f"({settings.t_end:g} s)")
        if term.t_to is not None and term.t_to < settings.t_start:
            raise self.error(path + ("t_to",), f"{where}.t_to: {term.t_to:g} s is before the simulation's start "
                             f"({settings.t_start:g} s)")
        needed = 1 if term.kind == "max_abs" else 2  # an integral over one sample is 0
        kept = int(np.count_nonzero(window(term, output_times(settings))))
        if kept < needed:
            key = "t_from" if term.t_from is not None else "t_to"
            lo = f"{term.t_from:g} s" if term.t_from is not None else "the run's start"
            hi = f"{term.t_to:g} s" if term.t_to is not None else "the run's end"
            raise self.error(path + (key,), f"{where}: the window {lo} ... {hi} holds {kept} of the run's output "
                             f"samples (one every {settings.dt_out:g} s from {settings.t_start:g} s); "
                             f"{term.kind} needs {needed} at least")

    def seconds_or(self, path, key, raw, unit) -> float:
        try:
            return quantity(raw, unit)
        except UnitError as exc:
            raise self.error(path + (key,), f"{'.'.join(map(str, path))}.{key}: {exc}") from None

    # ---- algorithm and sweep --------------------------------------------------------------------------
    def algorithm(self):
        m = self.model
        if m.algorithm is None:
            return None, None
        spec = METHODS[m.algorithm["method"]].model_validate(m.algorithm)
        if not m.parameters:
            raise self.error(("parameters",) if "parameters" in self.located.data else (),
                             "an optimisation needs free parameters (parameters: name: {min:, max:})")
        n = len(m.parameters)
        if isinstance(spec, ComplexSpec):
            settings = ComplexSettings(spec.points, spec.alpha, spec.n0, spec.rfak, spec.gamma, spec.tol_x, spec.tol_f,
                                       spec.max_evaluations, spec.max_retractions,
                                       0 if spec.candidates == "auto" else spec.candidates)
            k = spec.points if spec.points is not None else max(2 * n, 3)
            if k < n + 1:
                raise self.error(("algorithm", "points"), f"algorithm.points: the complex needs at least "
                                 f"n + 1 = {n + 1} points for {n} free parameters")
            if spec.max_evaluations < k:
                raise self.error(("algorithm", "max_evaluations"), f"algorithm.max_evaluations: {spec.max_evaluations} "
                                 f"is fewer than the {k} points of the initial complex")
            if spec.candidates != "auto" and spec.candidates < 1:
                raise self.error(("algorithm", "candidates"), "algorithm.candidates: at least 1 (or auto)")
            return "complex", settings
        if isinstance(spec, NelderMeadSpec):
            self.start = spec.start
            return "nelder_mead", NelderMeadSettings(spec.max_evaluations, spec.xatol, spec.fatol, None, spec.adaptive)
        # scipy makes a generation of 5 at least (the budget, counted in popsize * n, would be wrong), and its
        # rand2 strategies draw 5 designs besides the one they mutate (with 5 in all: a ValueError inside scipy)
        fewest = 6 if spec.strategy.startswith("rand2") else 5
        if spec.popsize * n < fewest:
            needs = f"{fewest} at least" + (f" with strategy {spec.strategy}" if fewest == 6 else "")
            raise self.error(("algorithm", "popsize") if "popsize" in m.algorithm else ("algorithm",),
                             f"algorithm.popsize: popsize * n = {spec.popsize * n} designs a generation for {n} free "
                             f"parameter{'s' if n > 1 else ''}; differential evolution needs {needs} "
                             f"(popsize: {-(-fewest // n)} or more)")
        if spec.max_evaluations < spec.popsize * n:
            raise self.error(("algorithm", "max_evaluations"), f"algorithm.max_evaluations: {spec.max_evaluations} "
                             f"is fewer than one generation (popsize * n = {spec.popsize * n})")
        return "differential_evolution", DESettings(spec.max_evaluations, spec.popsize, spec.tol, spec.atol,
                                                    spec.mutation, spec.recombination, spec.strategy, spec.polish)

    def sweep(self):
        s = self.model.sweep
        if s is None:
            return [], []
        columns = {}
        for name, values in s.parameters.items():
            path = ("sweep", "parameters", name)
            if name in self.model.set:
                raise self.error(path, f"sweep.parameters.{name}: also fixed in set:")
            if isinstance(values, list):
                if not values:
                    raise self.error(path, f"sweep.parameters.{name}: an empty list")
                columns[name] = [self.value(name, raw, path + (i,)) for i, raw in enumerate(values)]
            else:
                lower, upper = self.bounds(name, values, path)
                grid = np.geomspace(lower, upper, values.points) if values.log else np.linspace(lower, upper, values.points)
                columns[name] = [float(v) for v in grid]
                if getattr(self.entries[name].bounds, "integer", False) and any(v != math.floor(v) for v in grid):
                    raise self.error(path, f"sweep.parameters.{name}: a whole-number switch "
                                           f"({self.entries[name].bounds.description}); list its values instead")
        names = list(columns)
        if s.combine == "list":
            lengths = {len(v) for v in columns.values()}
            if len(lengths) > 1:
                raise self.error(("sweep", "combine"), "sweep.combine: list pairs the i-th values of each parameter; "
                                 f"give them equally many values (got {', '.join(str(len(v)) for v in columns.values())})")
            points = [dict(zip(names, row)) for row in zip(*columns.values())]
        else:
            grids = np.meshgrid(*columns.values(), indexing="ij")
            points = [dict(zip(names, (float(g.flat[i]) for g in grids))) for i in range(grids[0].size)]
        if len(points) > 1_000_000:
            raise self.error(("sweep",), f"sweep: {len(points)} points is too many")
        return names, points

    def fingerprint(self, netlist: Path) -> str:
        """What the results depend on: the job (not where or how fast it runs) and the netlist's text."""
        data = {k: v for k, v in self.located.data.items() if k not in ("output", "workers", "scheduler", "description")}
        digest = hashlib.sha256(json.dumps(data, sort_keys=True, default=str).encode())
        digest.update(netlist.read_bytes())
        return digest.hexdigest()[:16]
