"""The experiment file: which netlist, which data, what is imposed, what is compared, what is free.

An experiment file (YAML, ``netlists/experiments/*.yaml``; paths relative to the file)::

    description: steady points of the relief rig, three crack settings
    netlist: circuits/relief_rig.yaml
    data: data/relief_rig.csv            # one CSV: steady points (no t column) or a time series (t column);
                                         # several files: [a.csv, b.csv] (steady points, or one run each)
    group: setting                       # the grouping column (optional; a time series: its runs)
    repeats: point                       # a column marking repeated points (optional; for noise: repeats)
    inputs:                              # measured columns imposed on the circuit
      Q: {parameter: Q_in, noise: "0.5 l/min"}          # steady: the parameter each point sets
      # time series: cmd: {signal: cmd, latent: [u1, u2, u3], noise: 0.005}   (the profile's levels)
      #          or: cmd: {signal: cmd, latent: trace, noise: 0.005}  (the recording, read by the netlist)
    outputs:                             # measured columns compared with logged signals
      p1: {signal: p1, noise: "0.2 bar"}
      p3: {signal: p3, noise: repeats}   # noise given, or estimated: repeats (steady) / diff (time series)
    overrides: {R_meter: "5e8 Pa*s/m^3"} # parameter values for every point
    groups:                              # per group: parameter values (e.g. each crack setting) ...
      "1": {p_set: "30 bar"}
      "2": {p_set: "p_set + 15 bar"}   # or an expression over the netlist's parameters (evaluated once)
    group_table: {file: crack.csv, columns: {crack: relief.p_set}}   # ... or read from a table per group:
                                         # one row per group, 'crack [bar]' in a unit of p_set's dimension
                                         # (a name the table sets is not also set under groups:;
                                         # a group's value, by either, takes the place of overrides:'s)
    free:                                # the declared free parameters, values in any unit of their dimension
      k_s: {initial: "50 bar", lower: "5 bar", upper: "500 bar"}   # step: the finite-difference step (> 0)
      shaft.initial: {initial: "0 rpm", per: group}   # one value per group (a time series: per run); a start
                                                      # per group: initial: {a: "0 rpm", b: "600 rpm"}
    drift: [k_s]                         # refitted per group (or run), should stay constant
    heldout: {scheme: leave_one_group_out}      # or {scheme: kfold, k: 5}, leave_one_experiment_out (each
                                                # data file in turn) or {scheme: kfold_experiments, k: 3}
    steady: {t_end: "0.15 s", settle_tol: 0.05} # settling runs (steady data); t_max: the longest a run
                                                # not settled at t_end may be lengthened to (8 x t_end);
                                                # method: equilibrium (default: a point's equilibrium by
                                                # Newton, started from its first settling run) or settle
    trace: {rounds: 3, top: 3, exclude: [extra_volume]}   # or only: [flow_force, leakage]; top: refits a round
    solver: {rtol: 1e-8, atol: 1e-8}     # tolerances of the calibration runs (default: the netlist's)
    corrections: {p1: {offset: "0.3 bar", gain: 0.01}}   # sensor corrections held fixed (an offset with its
                                                          # channel's unit, a relative gain)

Errors name the file, line and column (the style of :mod:`blocks.netlist.flatten`). Every measured column,
imposed or compared, and its noise are in a unit of the dimension the netlist gives the channel
(:func:`channel_unit`: a flow for ``Q_in: "40 l/min"``; where the netlist cannot say, as for a command level
``u1: 0.1`` in a profile's values, the data column's unit);
a column of another dimension (``Q [bar]``), without unit (``Q``) or a noise of another dimension
(``noise: "0.5 bar"``) is an error, not a quantity read as one of the channel's. Inputs of steady data
are imposed through a netlist parameter per point; inputs of a time series are logged signals of the
netlist (e.g. a command profile) whose levels are the netlist parameters listed under ``latent``: the true
input is latent in both cases (errors-in-variables, :mod:`blocks.calibrate.model`).

A recorded input trace can instead be imposed by the netlist itself: a ``profile`` block whose times and
values read the data file's columns (``times: {csv: data.csv, column: t}``, ``values: {csv: data.csv,
column: cmd}``). Listed under ``inputs:`` with ``latent: trace`` (``cmd: {signal: cmd, latent: trace,
noise: 0.005}``), the recording is a noisy reading of a latent linear spline whose knots are fitted
(:mod:`blocks.calibrate.latent_trace`; the profile's breakpoints are replaced by the knots; with several
runs, one data file each, the netlist reads one of them and each run gets the knots of its own
recording). Not listed, such a column is imposed exactly, its measurement noise not accounted for; the
report names it (:func:`read_by_netlist`), and the verdict does when a discrepancy remains.

A free parameter with ``per: group`` is fitted once per group of the data, as ``<name>[<group>]`` (each run
of a time series: its own initial state when the runs start mid-motion, its own payload; each group of
steady points: its own setting). The groups are known from the data, so the copies are made with it
(:func:`blocks.calibrate.run.per_group_globals`). Such a parameter is not in ``drift:`` (drift refits a
shared one per group), and in a held-out refit the held-out group's own values are fitted to that group
alone (:mod:`blocks.calibrate.heldout`).

A value of ``overrides:`` or of a group under ``groups:`` may also be an expression over the netlist's
parameters by their qualified names, as the netlist writes one (``"1.1*R_meter"``, ``"p_crack + 10 bar"``).
It is evaluated once, when the experiment is loaded, with the netlist's values and the plain values of its
section in their place (``overrides:``'s; for a group, the overrides' and the group's own, its group table's
included), so it may not read, itself or through the netlist's expressions, a parameter the calibration
changes (a free one, an input's parameter set point by point, a latent level), another expression of the
same section, or for ``overrides:`` (the same in every group) a parameter a group sets: it would not follow
them (write such an expression in the netlist, where it does). Its own name reads the netlist's value
(``p_set: "p_set + 5 bar"``).
"""

from __future__ import annotations

import ast

from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from blocks.errors import NetlistError
from blocks.netlist.parameters import ParameterError
from blocks.netlist.yaml_source import Located, document_path, in_words, read_yaml, shown_key, unknown_key, wrong_kind
from blocks.units import (GENERIC, UnitError, display_factor, nearest, parse_unit, quantity, quantity_name, si_name,
                          split_quantity)

from blocks.netlist.spec import Value  # a number, or '<number> <unit>'; never a YAML boolean (step: true was 1)


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", str_strip_whitespace=True)


class ChannelSpec(_Strict):
    signal: str | None = None
    parameter: str | None = None
    latent: Union[list[str], str] = Field(default_factory=list)  # level parameters, or "trace"
    noise: Value


class FreeSpec(_Strict):
    initial: Union[Value, dict[Union[str, int], Value], None] = None  # per: group may start each group apart
    lower: Value | None = None
    upper: Value | None = None
    step: Value | None = None
    per: Literal["group"] | None = None  # one value fitted per group (a time series: per run)


class HeldOutSpec(_Strict):
    scheme: Literal["leave_one_group_out", "leave_one_experiment_out", "kfold_experiments", "kfold"] = \
        "leave_one_group_out"
    k: int = Field(5, ge=2, le=50)
    seed: int = 0


class SteadySpec(_Strict):
    t_end: Value | None = None
    t_max: Value | None = None  # the longest a settling run may be lengthened to (default 8 x t_end)
    settle_tol: float = Field(0.05, gt=0)
    method: Literal["equilibrium", "settle"] = "equilibrium"  # Newton from each point's settled state, or runs only


class TraceSpec(_Strict):
    rounds: int = Field(3, ge=1, le=3)
    top: int = Field(3, ge=1, le=20)
    only: list[str] | None = None
    exclude: list[str] = Field(default_factory=list)


class SolverSpec(_Strict):
    rtol: float | None = Field(None, gt=0, lt=1)
    atol: float | None = Field(None, gt=0, lt=1)


class GroupTableSpec(_Strict):
    file: str
    columns: dict[str, str]


class ExperimentSpec(_Strict):
    description: str = ""
    netlist: str
    data: Union[str, Annotated[list[str], Field(min_length=1)]]
    group: str | None = None
    repeats: str | None = None  # a column whose equal values (in a group and file) mark one operating point
    inputs: dict[str, ChannelSpec] = Field(default_factory=dict)
    outputs: dict[str, ChannelSpec]
    overrides: dict[str, Value] = Field(default_factory=dict)
    groups: dict[str, dict[str, Value]] = Field(default_factory=dict)
    group_table: GroupTableSpec | None = None
    free: dict[str, FreeSpec] = Field(default_factory=dict)
    drift: list[str] = Field(default_factory=list)
    heldout: HeldOutSpec = Field(default_factory=HeldOutSpec)
    steady: SteadySpec = Field(default_factory=SteadySpec)
    trace: TraceSpec = Field(default_factory=TraceSpec)
    solver: SolverSpec = Field(default_factory=SolverSpec)
    corrections: dict[str, dict[str, Value]] = Field(default_factory=dict)
    """Sensor corrections found by an earlier calibration: {channel: {offset: value, gain: value}}."""


@dataclass
class Channel:
    """A measured column: an imposed input or a compared output, its noise level in SI."""

    name: str
    role: str  # "input" or "output"
    signal: str | None
    parameter: str | None
    latent: list[str]
    noise: float | None  # SI; None: estimated from the data (``noise_method``)
    noise_method: str  # "given", "repeats" or "diff"
    unit: str = ""  # the data column's unit (for reports)
    si_unit: str = ""  # the SI unit of its dimension ("1": dimensionless; "": not known, see channel_unit)
    trace: str | None = None  # latent: trace: the profile's values parameter that reads this column
    written: str = ""  # the unit the netlist writes the channel in ('l/min' for Q_in: "40 l/min"; '': not known)

    @property
    def place(self) -> str:
        """What the column is in the circuit, for messages: 'imposed as Q_in', 'compared with the signal p1'."""
        if self.role == "output":
            return f"compared with the signal {self.signal}"
        if self.parameter is not None:
            return f"imposed as {self.parameter}"
        return f"imposed as the signal {self.signal}" + (f" (levels {', '.join(self.latent)})" if self.latent else "")


@dataclass
class Free:
    """A fitted parameter: qualified name, start, bounds and finite-difference step (SI)."""

    name: str
    initial: float
    lower: float
    upper: float
    step: float
    unit: str  # display unit
    kind: str = "declared"  # declared, latent, trace, candidate, correction
    at: float | None = None  # a latent trace's knot value (kind "trace"): the knot's start time, s
    run: str | None = None  # a latent level or knot of one run of a grouped time series (name "<...>[<run>]"),
    # or a declared parameter's value in one group (per: group; name "<parameter>[<group>]")
    per_group: bool = False  # a declared parameter fitted per group (per: group), before per_group_globals
    starts: dict = field(default_factory=dict)  # per: group: a group's own start (SI), else ``initial``


@dataclass
class Experiment:
    file: str
    spec: ExperimentSpec
    located: Located
    netlist: Path
    data: Path  # the first data file (the only one of a time series)
    channels: list[Channel]
    overrides: dict[str, float]
    groups: dict[str, dict[str, float]]
    free: list[Free]
    corrections: dict[str, dict[str, float]] = field(default_factory=dict)
    data_files: list[Path] = field(default_factory=list)
    exact_columns: list[tuple[str, str]] = field(default_factory=list)  # (column, parameter): see read_by_netlist

    @property
    def inputs(self) -> list[Channel]:
        return [c for c in self.channels if c.role == "input"]

    @property
    def outputs(self) -> list[Channel]:
        return [c for c in self.channels if c.role == "output"]

    @property
    def fits_inputs(self) -> bool:
        """Whether the fit takes an imposed input as a latent value (its levels, or a trace's knots) rather than
        as the netlist or the data give it."""
        return any(c.latent or c.trace is not None for c in self.inputs)

    def error(self, path: tuple, message: str) -> NetlistError:
        return self.located.error(path, message)

    def resolve(self, relative: str) -> Path:
        return (Path(self.file).parent / relative).resolve()


def load_spec(file: str | Path) -> tuple[ExperimentSpec, Located]:
    """Parse and validate the shape of an experiment file (errors with line and column)."""
    located = read_yaml(file)
    if not isinstance(located.data, dict):
        raise located.error((), "an experiment file is a mapping with netlist:, data:, outputs:, free:, ...")
    try:
        return ExperimentSpec.model_validate(located.data), located
    except ValidationError as exc:
        if (other := wrong_kind(located, "a calibration experiment")) is not None:
            raise other from None
        errors = exc.errors()
        first = errors[0]
        if first["type"] == "missing":  # a misspelt key ('heldot:') is missing and unknown at once: say the latter
            first = next((e for e in errors if e["type"] == "extra_forbidden" and e["loc"][:-1] == first["loc"][:-1]),
                         first)
        if isinstance(first.get("input"), list):  # a union (data: a file or a list): its list branch's error
            first = next((e for e in errors if any(str(p).startswith("list[") for p in e["loc"])), first)
        path = document_path(located.data, first["loc"])
        where = ".".join(shown_key(p) for p in path) or "experiment"
        message = in_words(first)
        if first["type"] == "extra_forbidden":
            model = _model_at(path[:-1])
            message = (unknown_key(path[-1], model.model_fields) if model is not None
                       else f"unknown key '{shown_key(path[-1])}'" if path else "unknown key")
        elif first["type"] == "missing":
            message = f"missing '{first['loc'][-1]}'"
        elif first["type"] == "too_short" and isinstance(first.get("input"), list):
            message = f"an empty list: give at least {first['ctx']['min_length']} entry"
        elif first["type"] == "model_type":  # pydantic names its class ("a valid dictionary or instance of X")
            model = _model_at(tuple(path))
            message = "expected a mapping" + (f" with keys {', '.join(model.model_fields)}" if model else "") + \
                f", got {type(first.get('input')).__name__} {first.get('input')!r}"
        raise located.error(path, f"{where}: {message}") from None


def _model_at(path: tuple):
    top = {(): ExperimentSpec, ("heldout",): HeldOutSpec, ("steady",): SteadySpec, ("trace",): TraceSpec,
           ("solver",): SolverSpec, ("group_table",): GroupTableSpec}
    if path in top:
        return top[path]
    if len(path) == 2 and path[0] in ("inputs", "outputs"):
        return ChannelSpec
    if len(path) == 2 and path[0] == "free":
        return FreeSpec
    return None


def load_experiment(file: str | Path, circuit=None) -> Experiment:
    """Read an experiment file and check it against its netlist (``circuit``: an already built one).

    Values are converted to SI with each parameter's unit; names of parameters and signals are checked
    against the netlist (an unknown one is an error with the nearest names)."""
    from blocks.circuit import Circuit

    file = str(file)
    spec, located = load_spec(file)
    check_candidate_names(spec.trace, located)
    base = Path(file).parent
    netlist = (base / spec.netlist).resolve()
    if not netlist.is_file():
        raise located.error(("netlist",), f"netlist: file not found: {spec.netlist}" + _looked_for(spec.netlist, netlist))
    names = [spec.data] if isinstance(spec.data, str) else list(spec.data)
    data_files = []
    for k, name in enumerate(names):
        path = (base / name).resolve()
        where = ("data",) if isinstance(spec.data, str) else ("data", k)
        if not path.is_file():
            raise located.error(where, f"data: file not found: {name}" + _looked_for(name, path))
        if path in data_files:
            raise located.error(where, f"data: {name} is listed twice (its points would count twice)")
        data_files.append(path)
    data = data_files[0]
    if circuit is None:
        circuit = Circuit.from_file(netlist, compile=False)
    entries = circuit.flat.parameters.entries
    signals = {o.name: o for o in circuit.outputs}

    def param_name(name: str, path: tuple) -> str:
        if name not in entries:
            hint = nearest(name, entries)
            raise located.error(path, f"unknown parameter '{name}' in {spec.netlist}"
                                + (f" (did you mean {', '.join(hint)}?)" if hint else ""))
        if name in circuit.flat.parameters.derived:
            raise located.error(path, f"'{name}' is derived from {circuit.flat.parameters.derived[name]}: "
                                      f"use that instead")
        return name

    def si(name: str, raw, path: tuple) -> float:
        try:
            return circuit.flat.parameters.value_si(name, raw)
        except UnitError as exc:
            raise located.error(path, f"{name}: {exc}") from None

    channels: list[Channel] = []
    for role, table in (("input", spec.inputs), ("output", spec.outputs)):
        for name, ch in table.items():
            path = (f"{role}s", name)
            if role == "output" and ch.parameter is not None:
                raise located.error(path + ("parameter",), f"outputs.{name}: 'parameter' is for inputs (a value set "
                                    f"per point); an output is compared with a logged signal: "
                                    + ("give signal: <name> instead" if ch.signal is None else "leave it out")
                                    + f" (logged in {spec.netlist}: {', '.join(signals)})")
            if role == "output" and ch.signal is None:
                raise located.error(path, f"outputs.{name}: missing 'signal' (the logged signal it is compared with)")
            if role == "input" and (ch.signal is None) == (ch.parameter is None):
                raise located.error(path, f"inputs.{name}: give 'parameter' (steady points: the parameter each "
                                          f"point sets) or 'signal' with 'latent' (a time series)")
            if ch.signal is not None and ch.signal not in signals:
                hint = nearest(ch.signal, signals)
                raise located.error(path + ("signal",), f"{role}s.{name}: no logged signal '{ch.signal}' in "
                                    f"{spec.netlist} (logged: {', '.join(signals)})"
                                    + (f"; did you mean {', '.join(hint)}?" if hint else ""))
            if ch.parameter is not None:
                param_name(ch.parameter, path + ("parameter",))
            if isinstance(ch.latent, str) and ch.latent != "trace":
                raise located.error(path + ("latent",), f"{role}s.{name}.latent: '{ch.latent}' is not a latent "
                                    f"input: give the netlist parameters of its levels (e.g. [u1, u2]) or 'trace' "
                                    f"(the recorded column, read by the netlist, fitted as a latent spline)")
            if ch.latent == "trace" and ch.parameter is not None:
                raise located.error(path + ("latent",), f"{role}s.{name}.latent: 'trace' is for the recorded input "
                                    f"of a time series (given by 'signal'), not a steady point's 'parameter'")
            levels = [] if isinstance(ch.latent, str) else list(ch.latent)
            if levels and ch.parameter is not None:
                raise located.error(path + ("latent",), f"{role}s.{name}.latent: [{', '.join(levels)}] is for the "
                                    f"command levels of a time series (an input given by 'signal'); a steady input "
                                    f"is set point by point through 'parameter' ({ch.parameter}), its true value at "
                                    f"each point fitted already: leave latent out")
            if isinstance(ch.latent, list) and not levels and "latent" in ch.model_fields_set:
                raise located.error(path + ("latent",), f"{role}s.{name}.latent: lists no level; give the netlist "
                                    f"parameters of its levels (e.g. [u1, u2]) or 'trace', or leave it out")
            for k, lat in enumerate(levels):
                param_name(lat, path + ("latent", k))
                if lat in levels[:k]:
                    raise located.error(path + ("latent", k), f"{role}s.{name}.latent: {lat} is listed twice")
                if role == "input" and not is_signal_level(circuit.flat.parameters, lat):
                    raise located.error(path + ("latent", k), f"{role}s.{name}.latent: {lat} is not a level of a "
                                        f"signal block (no profile's values or signal block's parameter reads it "
                                        f"as it stands), so it is not a level of the command '{ch.signal}'")
            if role == "output" and (ch.parameter or ch.latent):
                raise located.error(path, f"outputs.{name}: an output takes 'signal' and 'noise' only")
            channel = Channel(name, role, ch.signal, ch.parameter, levels, None, "given",
                              si_unit=channel_unit(ch, levels, circuit.flat.parameters, signals))
            channel.written = written_unit(channel, entries, signals)
            if isinstance(ch.noise, str) and ch.noise.strip() in ("repeats", "diff"):
                channel.noise_method = ch.noise.strip()
            else:
                try:
                    channel.noise = channel_si(ch.noise, channel)
                except UnitError as exc:
                    raise located.error(path + ("noise",), f"{role}s.{name}.noise: {exc}") from None
                if not channel.noise > 0:
                    raise located.error(path + ("noise",), f"{role}s.{name}.noise must be positive")
            channels.append(channel)
    if not any(c.role == "output" for c in channels):
        raise located.error(("outputs",), "outputs: at least one compared column is needed")

    for key in ("t_end", "t_max"):  # settling-run times: checked here, read by blocks/calibrate/model.py
        raw = getattr(spec.steady, key)
        if raw is not None:
            try:
                seconds = quantity(raw, "s")
            except UnitError as exc:
                raise located.error(("steady", key), f"steady.{key}: {exc}") from None
            if not seconds > 0:
                raise located.error(("steady", key), f"steady.{key} must be positive, got {raw}")

    table, fitted = circuit.flat.parameters, _changed_by_fit(spec, channels)
    plain, expressions = _given_section(table, located, spec.overrides, ("overrides",), param_name, si)
    computed = _expression_values(circuit, located, ("overrides",), "overrides", expressions, plain,
                                  {**_set_per_group(spec), **fitted})
    overrides = {n: plain[n] if n in plain else computed[n] for n in spec.overrides}
    groups: dict[str, dict[str, float]] = {}
    pending = {}  # each group's expressions, evaluated with its plain values and its group table's
    for label, values in spec.groups.items():
        groups[str(label)], pending[label] = _given_section(table, located, values, ("groups", label), param_name, si)
    if spec.group_table is not None:
        _read_group_table(spec, located, base, groups, param_name, table)
    for label, expressions in pending.items():
        key = str(label)
        computed = _expression_values(circuit, located, ("groups", label), f"group {key}", expressions,
                                      {**overrides, **groups[key]}, fitted)
        groups[key] = {**computed, **groups[key]}

    for c in channels:  # a latent level is fitted: a value given for it too would be silently overridden
        for k, level in enumerate(c.latent):
            given = "overrides" if level in overrides else next(
                (f"groups.{label}" for label, values in groups.items() if level in values), None)
            if given is not None:
                raise located.error(("inputs", c.name, "latent", k), f"inputs.{c.name}.latent: {level} is also set "
                                    f"by {given}; a latent level is fitted from the measured input (with several "
                                    f"runs, one value per run), not set")
    set_by = {c.parameter: f"inputs.{c.name}" for c in channels if c.parameter is not None}
    set_by.update({n: f"inputs.{c.name}.latent" for c in channels for n in c.latent})
    set_by.update({n: "overrides" for n in overrides})
    set_by.update({n: f"groups.{label}" for label, values in groups.items() for n in values})
    free: list[Free] = []
    for name, fs in spec.free.items():
        path = ("free", name)
        param_name(name, path)
        if name in set_by:
            raise located.error(path, f"free.{name}: also set by {set_by[name]}; a parameter is either fitted "
                                      f"(free) or set, not both")
        entry = entries[name]
        values = circuit.flat.parameters.evaluate({})
        starts = {}
        if isinstance(fs.initial, dict):  # a start per group
            if fs.per != "group":
                raise located.error(path + ("initial",), f"free.{name}.initial: a start per group (a mapping) "
                                    f"needs per: group")
            starts = {str(g): si(name, v, path + ("initial", g)) for g, v in fs.initial.items()}
        start = values[name] if fs.initial is None or starts else si(name, fs.initial, path + ("initial",))
        if isinstance(start, tuple):
            raise located.error(path, f"free.{name}: an array parameter cannot be free")
        if getattr(entry.bounds, "integer", False):
            raise located.error(path, f"free.{name}: a whole-number switch ({entry.bounds.description}) cannot "
                                      f"be fitted; set it under overrides")
        lower = -np.inf if fs.lower is None else si(name, fs.lower, path + ("lower",))
        upper = np.inf if fs.upper is None else si(name, fs.upper, path + ("upper",))
        unit = display_unit(entry, fs)
        shown = ((lambda v: f"{v:g}") if unit == "1" else (lambda v: f"{v / display_factor(unit):g} {unit}".strip())
                 if unit else (lambda v: f"{v:g} (SI)"))
        if entry.bounds is not None:  # a block's parameter: bounds beyond its own are refused, not clamped (the
            own = entry.bounds        # fit would stop at the block's bound while the experiment says another)
            for key, raw, value, limit, beyond in (("lower", fs.lower, lower, own.lower, "below"),
                                                   ("upper", fs.upper, upper, own.upper, "above")):
                if raw is not None and limit is not None and (value < limit if key == "lower" else value > limit):
                    raise located.error(path + (key,), f"free.{name}: {key} {raw} is {beyond} {name}'s own {key} "
                                                       f"bound {shown(limit)}")
            if own.lower is not None:
                lower = max(lower, own.lower)
            if own.upper is not None:
                upper = min(upper, own.upper)
        if not lower < upper:
            raise located.error(path, f"free.{name}: the lower bound {shown(lower)} is not below the upper "
                                f"{shown(upper)}" + (" (with the netlist's bounds of the parameter)"
                                                     if entry.bounds is not None else "")
                                + ("; a parameter held at one value is set under overrides, not free"
                                   if lower == upper else ""))
        for group, value in [(None, start)] + list(starts.items()):
            if not lower <= value <= upper:
                raise located.error(path + (("initial", group) if group is not None else ()),
                                    f"free.{name}" + (f".initial.{group}" if group is not None else "")
                                    + f": the start value {shown(value)} is outside [{shown(lower)}, {shown(upper)}]")
        step = si(name, fs.step, path + ("step",)) if fs.step is not None else default_step(start, lower, upper)
        if not (np.isfinite(step) and step > 0):  # the finite-difference step: a size, not a direction
            raise located.error(path + ("step",), f"free.{name}.step: {_written(fs.step, step)} is not a positive "
                                f"step; give the finite-difference step of {name} as a size above 0")
        free.append(Free(name, float(start), float(lower), float(upper), float(step), unit,
                         per_group=fs.per == "group", starts=starts))
    for k, name in enumerate(spec.drift):
        if name not in spec.free:
            raise located.error(("drift", k), f"drift: '{name}' is not a free parameter")
        if spec.free[name].per is not None:
            raise located.error(("drift", k), f"drift: '{name}' is fitted per group already (free.{name}.per); "
                                f"drift refits a parameter shared by the groups")
    corrections = {}
    for ch_name, corr in spec.corrections.items():
        channel = next((c for c in channels if c.name == ch_name), None)
        if channel is None:
            raise located.error(("corrections", ch_name), f"corrections: no channel '{ch_name}'")
        unknown = set(corr) - {"offset", "gain"}
        if unknown:
            raise located.error(("corrections", ch_name), f"corrections.{ch_name}: only offset and gain")
        corrections[ch_name] = {key: _correction(located, ch_name, key, corr.get(key, 0.0), channel)
                                for key in ("offset", "gain")}
    exact = read_by_netlist(circuit, data_files)
    for ch in channels:
        if spec.inputs.get(ch.name) is not None and ch.role == "input" and spec.inputs[ch.name].latent == "trace":
            ch.trace = trace_parameter(circuit, exact, ch.name, located, spec.netlist)
    exact = [(column, param) for column, param in exact if param not in {c.trace for c in channels}]
    check_values(circuit, overrides, groups, spec, located)
    check_free_values(circuit, overrides, groups, free, spec, located)
    return Experiment(file, spec, located, netlist, data, channels, overrides, groups, free, corrections, data_files,
                      exact)


def _given_section(table, located: Located, raws: dict, path: tuple, param_name, si) -> tuple[dict, dict]:
    """The values of ``overrides:`` or of a group (``raws``, at ``path``): the numbers and ``"<number> <unit>"``
    in SI (by ``si``), and apart, the expressions over the netlist's parameters (by name, as
    :meth:`~blocks.netlist.parameters.ParameterTable.given_expression` reads them, their names and dimension
    checked, errors located at their key), which :func:`_expression_values` evaluates."""
    plain, expressions = {}, {}
    for name, raw in raws.items():
        where = path + (name,)
        param_name(name, where)
        try:  # an array (a table) takes no single value, an expression's no more than a number
            table.check_single(name)
        except UnitError as exc:
            raise located.error(where, f"{name}: {exc}") from None
        entry = table.given_expression(name, raw, located, where, ".".join(shown_key(p) for p in where))
        if entry is None:
            plain[name] = si(name, raw, where)
        else:
            expressions[name] = entry
    return plain, expressions


def _expression_values(circuit, located: Located, path: tuple, what: str, expressions: dict, known: dict[str, float],
                       changed: dict[str, str]) -> dict[str, float]:
    """The values of the ``expressions`` of one section of the experiment (at ``path``: ``overrides:``, a
    group), evaluated once, with the netlist's values and ``known`` (the section's plain values, and for a
    group the overrides) in their place. One that reads, itself or through the netlist's expressions, a
    parameter in ``changed`` (-> what changes it: the fit, a group) or another expression of its section
    would not follow it and is refused, at its key (:meth:`~blocks.netlist.parameters.ParameterTable.
    given_values`). Plain values the netlist's expressions cannot take (``known``: a 0 it divides by) refuse
    the section, as :func:`check_values` says; the blocks' checks of their values together wait for the
    expressions' values (``p_open: "p_set + 10 bar"`` may be what makes a higher p_set right)."""
    if not expressions:
        return {}
    table = circuit.flat.parameters
    try:
        values = table.evaluate(known)
    except (NetlistError, ParameterError):
        _check_with(circuit, known, path, what, located)
        raise
    return table.given_values(expressions, values, known, changed, ".".join(shown_key(p) for p in path))


def _check_with(circuit, values: dict[str, float], path: tuple, what: str, located: Located) -> None:
    """The netlist evaluated with the experiment's ``values`` (those of ``what``, set at ``path``), its blocks'
    checks included: values it cannot take are the experiment's error, located at ``path``; the netlist's own
    failure (with its own values) is raised as it is, located in the netlist."""
    try:
        circuit.vectors(values)
    except (NetlistError, ParameterError) as exc:
        try:
            circuit.vectors({})
        except (NetlistError, ParameterError):
            raise exc from None
        raise located.error(path, f"{path[0]}: with the values of {what} the netlist cannot be evaluated: "
                                  f"{exc}") from None


def _changed_by_fit(spec: ExperimentSpec, channels: list[Channel]) -> dict[str, str]:
    """The parameters the calibration changes (-> how: for a message), which an expression among the
    experiment's values may not read: the free ones, a steady input's (set point by point) and the latent
    levels of a time series' inputs."""
    changed = {c.parameter: f"inputs.{c.name} sets point by point" for c in channels if c.parameter is not None}
    changed.update({n: f"the calibration fits (inputs.{c.name}.latent)" for c in channels for n in c.latent})
    changed.update({n: f"the calibration fits (free.{n})" for n in spec.free})
    return changed


def _set_per_group(spec: ExperimentSpec) -> dict[str, str]:
    """The parameters set per group (-> by what: for a message), by ``groups:`` or ``group_table:``, which an
    expression in ``overrides:`` (the same for every group) may not read."""
    found = {n: "group_table sets per group" for n in spec.group_table.columns.values()} if spec.group_table else {}
    for label, values in reversed(spec.groups.items()):  # the first group that sets one names it
        found.update({n: f"groups.{shown_key(label)} sets" for n in values})
    return found


def _looked_for(written: str, path: Path) -> str:
    """Where a file named in the experiment was looked for, when that is not what was written."""
    if Path(written).is_absolute():
        return ""
    return f" (looked for {path}: paths in an experiment file are relative to its folder)"


def trace_parameter(circuit, exact: list[tuple[str, str]], column: str, located: Located, netlist: str) -> str:
    """The ``values`` parameter of the profile block that reads the data column of a ``latent: trace`` input
    (:mod:`blocks.calibrate.latent_trace`); an error at the input if the netlist reads it nowhere else."""
    from blocks.library.signal.profile import Profile

    path = ("inputs", column, "latent")
    readers = [param for col, param in exact if col == column]
    profiles = [p for p in readers if p.endswith(".values")
                and circuit.flat.components.get(p.rsplit(".", 1)[0]) is not None
                and circuit.flat.components[p.rsplit(".", 1)[0]].cls is Profile]
    if not readers:
        raise located.error(path, f"inputs.{column}.latent: 'trace' fits the recorded column {column} as a latent "
                            f"spline, so {netlist} must impose it by reading it from the data file (a profile "
                            f"block with values: {{csv: <data file>, column: {column}}}); it reads no such column")
    if len(profiles) != 1 or len(readers) != 1:
        raise located.error(path, f"inputs.{column}.latent: 'trace' needs the column {column} read by one profile "
                            f"block's values in {netlist}; it is read by {', '.join(readers)}")
    return profiles[0]


def read_by_netlist(circuit, data_files: list[Path]) -> list[tuple[str, str]]:
    """(column, parameter) of every array parameter the netlist reads from one of the experiment's data files
    (``{csv:, column:}``, e.g. a recorded command trace on a ``profile`` block). Such a column is imposed
    exactly: its measurement noise is not accounted for (errors-in-variables covers the inputs listed under
    ``inputs:``), so the report names it, and the verdict does when a discrepancy remains."""
    from blocks.netlist.spec import CsvColumn

    files = {Path(f).resolve() for f in data_files}
    found = []
    for name, entry in circuit.flat.parameters.entries.items():
        if isinstance(entry.raw, CsvColumn):
            source = (Path(entry.source.file).parent / entry.raw.csv).resolve()
            column = entry.raw.column.split("[")[0].strip()
            if source in files and column != "t":  # sample times are exact in the model
                found.append((column, name))
    return found


def _read_group_table(spec, located, base: Path, groups: dict, param_name, parameters) -> None:
    """The values per group from ``group_table.file``: one row per group; each mapped column in a unit of its
    parameter's dimension (a column in kg for a pressure, or without a unit for one, is refused as a data
    column is: read in SI it would set 95.4 Pa for '95.4' meant in bar; where the netlist gives the parameter
    no dimension, in a unit its readers allow, :func:`_check_undimensioned_column`) and a number in every row."""
    from blocks.datafile import DataFileError, header_of, read_table

    gt = spec.group_table
    if spec.group is None:
        raise located.error(("group_table",), "group_table: needs 'group' (the grouping column)")
    path = (base / gt.file).resolve()
    if not path.is_file():
        raise located.error(("group_table", "file"), f"group_table.file: file not found: {gt.file}"
                            + _looked_for(gt.file, path))
    table = read_table(path, group=spec.group)
    _, header = header_of(path)
    bracketed = {name: unit for name, unit in header}
    for column, target in gt.columns.items():
        param_name(target, ("group_table", "columns", column))
        if column not in table.columns:
            raise located.error(("group_table", "columns", column),
                                f"group_table: no numeric column '{column}' in {gt.file} "
                                f"(columns: {', '.join(table.columns)})")
        dims = parameters.dimension(target)
        sets = f"it sets {target} (group_table.columns.{shown_key(column)} in {Path(located.file).name})"
        if dims is None:  # the netlist does not say: the column's unit must suit what the readers make of it
            _check_undimensioned_column(table, column, bracketed.get(column), sets, parameters.unit_conflict(
                target, parse_unit(table.units[column])))
            continue
        si_unit = si_name(dims)
        if bracketed.get(column) is None and si_unit != "1":
            suggestion = display_unit(parameters.entries[target])
            try:
                fits = bool(suggestion) and parse_unit(suggestion).same_dimension(dims)
            except UnitError:
                fits = False
            raise DataFileError(table.file, f"column '{column}' has no unit, but {sets}, {described(si_unit)}: "
                                f"write '{column} [{suggestion if fits else si_unit}]'", table.header_line,
                                table.positions[column])
        given = parse_unit(table.units[column])
        if not given.same_dimension(dims):
            raise table.error(f"{quantity_name(given)}, but {sets}, {described(si_unit)}", column)
    for label, rows in table.groups.items():
        if len(rows) > 1:
            lines = [table.lines[k] for k in rows]
            raise table.error(f"group '{label}' has {len(rows)} rows (lines {', '.join(map(str, lines[:-1]))} and "
                              f"{lines[-1]}); a group table gives one row per group, else which values the group "
                              f"takes is ambiguous", spec.group, int(rows[1]))
    written = {str(label): (label, values) for label, values in spec.groups.items()}
    for k, label in enumerate(table.labels):
        for column, target in gt.columns.items():
            if target in written.get(label, (None, {}))[1]:
                key = written[label][0]
                raise located.error(("groups", key, target), f"groups.{shown_key(key)}.{target} is also set by "
                                    f"group_table.columns.{shown_key(column)} ({gt.file}); set it in one of "
                                    f"the two, else which value group {label} takes is ambiguous")
            value = float(table.columns[column][k])
            if not np.isfinite(value):
                raise table.error(f"no value for group '{label}' (an empty cell); it sets {target}", column, k)
            groups.setdefault(label, {})[target] = value


def _check_undimensioned_column(table, column: str, bracketed: str | None, sets: str, conflict: str | None) -> None:
    """A group-table column setting a parameter the netlist gives no dimension: its values are converted with
    the column's unit (a column without one: plain numbers), as ``groups:`` values are (:meth:`blocks.netlist.
    parameters.ParameterTable.value_si`); where the parameter's readers refuse that dimension (``conflict``:
    'f [mm]' for the factor in ``p_set*f``), an error, not a value silently taken in SI."""
    from blocks.datafile import DataFileError

    if conflict is None:
        return
    if bracketed is None:
        raise DataFileError(table.file, f"column '{column}' has no unit, but {sets}, and {conflict}: write the unit "
                            f"in brackets", table.header_line, table.positions[column])
    raise table.error(f"{quantity_name(parse_unit(bracketed))}, but {sets}, and {conflict}", column)


def channel_unit(ch: ChannelSpec, levels: list[str], table, signals: dict) -> str:
    """The SI unit of the dimension a measured column and its noise must have, as the netlist gives it
    ("1": dimensionless); "" where the netlist does not say, and the data column's unit decides
    (:func:`blocks.calibrate.data._load_file`; the noise is then checked against the column).

    - an output, or an input imposed through a logged signal: the signal's unit; for a generic signal block
      (SI of any unit) the unit the netlist logs it in (``x: {of: travel.y, unit: mm}``), else the dimension
      of its latent levels; not known for ``latent: trace`` (the netlist reads the data column itself, in the
      column's unit) or levels of no known dimension (``u1: 0.1`` in a profile's values, which take any unit);
    - an input imposed through a parameter: :meth:`blocks.netlist.parameters.ParameterTable.dimension` (its
      declared unit, the unit its value is written in, or for a bare number the places it is put:
      ``Q_in: "40 l/min"`` and ``Q_in: 6.7e-4`` put as a flow source's ``q`` are flows); not known for a bare
      number put only where any unit goes or read inside expressions."""
    if ch.signal is not None:
        signal = signals[ch.signal]
        for text in (signal.unit, signal.display_unit):
            if text not in ("", None, GENERIC):
                return si_name(parse_unit(text))
        found = [table.dimension(level) for level in levels]
        if not found or any(d is None for d in found) or any(not d.same_dimension(found[0]) for d in found):
            return ""
        return si_name(found[0])
    dims = table.dimension(ch.parameter)
    return "" if dims is None else si_name(dims)


def written_unit(channel: Channel, entries: dict, signals: dict) -> str:
    """The unit the netlist writes a channel in, to suggest for a data column written without one: the logged
    signal's display unit (``p1: {of: P1, unit: bar}``), the unit the imposed parameter is written in
    (``Q_in: "40 l/min"``), else the SI unit of the channel's dimension ('' where that is not known either)."""
    if channel.si_unit in ("", GENERIC):
        return ""
    found = [signals[channel.signal].display_unit] if channel.signal is not None else []
    if channel.parameter is not None:
        found.append(display_unit(entries[channel.parameter]))
    for text in found:
        try:
            if text and parse_unit(text).same_dimension(parse_unit(channel.si_unit)):
                return text
        except UnitError:
            continue
    return channel.si_unit


def unit_problem(unit_text: str, channel: Channel, subject: str = "it", place: str | None = None) -> str | None:
    """Why a value in ``unit_text`` (a data column's unit, a noise level's) cannot be one of ``channel``:
    'a pressure, but it is imposed as Q_in, a flow (m^3/s)'; None if it can or the dimension is not known
    (``channel.si_unit`` ""). Outputs and inputs alike: a column or noise in a unit of another dimension would
    be read as a quantity of the channel's (a pressure in bar taken for a flow in l/min)."""
    if channel.si_unit in ("", GENERIC):
        return None
    given, expected = parse_unit(unit_text or "1"), parse_unit(channel.si_unit)
    if given.same_dimension(expected):
        return None
    return f"{quantity_name(given)}, but {subject} is {place or channel.place}, {described(channel.si_unit)}"


def described(si_unit: str) -> str:
    """'a flow (m^3/s)', 'a plain number (dimensionless)'."""
    dims = parse_unit(si_unit)
    return f"{quantity_name(dims)} ({'dimensionless' if si_unit == '1' else si_unit})"


def channel_si(raw, channel: Channel) -> float:
    """A quantity of ``channel``'s dimension in SI: its given noise level, or a sensor correction's offset.
    Its unit must fit the channel's dimension (:func:`unit_problem`; not checked where it is not known,
    ``si_unit`` "": then against the data column, in :mod:`blocks.calibrate.data`), and for a dimensioned
    channel it needs a unit (a bare number would be read in SI, a noise 0.2 or an offset 0.5 meant in bar as
    0.2 or 0.5 Pa)."""
    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
        raise UnitError(f"expected a number or a '<number> <unit>' string, got {raw!r}")
    number, unit_text = (float(raw), "") if not isinstance(raw, str) else split_quantity(raw)
    if not unit_text:
        if channel.si_unit not in ("", "1", GENERIC):
            example = "bar" if channel.si_unit == "Pa" else channel.si_unit
            raise UnitError(f"{raw} has no unit; write it with one (e.g. \"{raw} {example}\"): a bare number "
                            f"would be read in SI, as {raw} {channel.si_unit}")
        return number
    problem = unit_problem(unit_text, channel, channel.name)
    if problem:
        raise UnitError(f"wrong unit: '{raw}' is {problem}")
    return number * parse_unit(unit_text).factor


def _correction(located, ch_name: str, key: str, raw, channel: Channel) -> float:
    """A sensor correction of ``channel`` in SI: its ``offset``, a quantity of the channel's dimension
    (:func:`channel_si`: a bare number refused where the channel has a dimension, as a noise is), or its
    ``gain``, a relative gain error (dimensionless: a bare number)."""
    try:
        return channel_si(raw, channel) if key == "offset" else float(quantity(raw, "1"))
    except UnitError as exc:
        raise located.error(("corrections", ch_name, key), f"corrections.{ch_name}.{key}: {exc}") from None


def display_unit(entry, given: FreeSpec | None = None) -> str:
    """The unit a parameter is shown in: the unit it was written with in the netlist, else the unit the
    experiment gives it in (``given``: its free: entry's start or bounds, ``"0 rpm"`` for a net's initial
    speed that the netlist never wrote), else its SI unit."""
    for raw in [entry.raw] + ([] if given is None else [given.initial, given.lower, given.upper]):
        for text in (raw.values() if isinstance(raw, dict) else [raw]):
            if isinstance(text, str):
                try:
                    _, unit = split_quantity(text)
                except UnitError:
                    continue
                if unit:
                    return unit
    return entry.unit if entry.unit not in (None, "SI") else ""


def default_step(start: float, lower: float, upper: float) -> float:
    """Absolute finite-difference step: 1e-3 of the value, or of the bounded range if the value is 0."""
    if start != 0.0:
        return 1e-3 * abs(start)
    if np.isfinite(lower) and np.isfinite(upper) and upper > lower:
        return 1e-3 * (upper - lower)
    return 1e-6


def check_candidate_names(trace: TraceSpec, located: Located) -> None:
    """``trace.only`` and ``trace.exclude`` name candidates of the library: a misspelt name would screen
    nothing (only) or exclude nothing (exclude) without a word."""
    from blocks.calibrate.candidates import registered

    library = list(registered())
    for key, names in (("only", trace.only or []), ("exclude", trace.exclude)):
        for k, name in enumerate(names):
            if name not in library:
                hint = nearest(name, library)
                raise located.error(("trace", key, k), f"trace.{key}: no candidate '{name}' in the library"
                                    + (f"; did you mean {', '.join(hint)}?" if hint else "")
                                    + f" (the library: {', '.join(library)})")


def check_values(circuit, overrides: dict[str, float], groups: dict[str, dict[str, float]], spec: ExperimentSpec,
                 located: Located) -> None:
    """The netlist evaluated with the experiment's values (overrides, then each group's on top): a value the
    netlist cannot take (R_meter = 0 in G = 1/R_meter) is the experiment's error, located at the entry that
    sets it, before any fit (it was found after the first, and pointed at the netlist's line). A netlist that
    cannot be evaluated with its own values is not the experiment's error: left to the run to report."""
    try:
        circuit.vectors({})
    except (NetlistError, ParameterError):
        return
    tries = [(("overrides",), "overrides", overrides)] + [
        ((("groups", label) if label in {str(k) for k in spec.groups} else ("group_table",)), f"group {label}",
         {**overrides, **values}) for label, values in groups.items()]
    for path, what, values in tries:
        _check_with(circuit, values, path, what, located)


def check_free_values(circuit, overrides: dict[str, float], groups: dict[str, dict[str, float]], free: list[Free],
                      spec: ExperimentSpec, located: Located) -> None:
    """The netlist evaluated at each free parameter's start, and at each bound the experiment gives it (the
    other free parameters at their starts), with the overrides and each group's values (a group's own start
    of a ``per: group`` parameter): a start or bound that puts a block parameter out of its declared bounds
    (``A_o: {initial: "-5 mm^2"}`` feeding an orifice's area) is the experiment's error, located at the entry,
    before any run. It used to run to exit 0 with every run of the fit failing. The fit may go to a bound, so
    a bound the netlist cannot take is refused too; a bound taken from the block itself is its own."""
    if not free:
        return
    labels = list(groups) + sorted({g for f in free for g in f.starts if g not in groups})
    for label in labels or [None]:
        base = {**overrides, **groups.get(label, {})}
        try:
            circuit.vectors(base)
        except (NetlistError, ParameterError):
            continue  # the netlist's own values (or the group's, refused by check_values) fail: not the free's
        with_group = f" and the values of group {label}" if len(labels) > 1 else ""

        def problem(values: dict) -> str | None:
            try:
                circuit.vectors({**base, **values})
            except (NetlistError, ParameterError) as exc:
                return _blamed(getattr(exc, "message", str(exc)), circuit.flat.parameters.entries)
            return None

        starts = {f.name: f.starts.get(label, f.initial) for f in free}
        for f in free:
            fs = spec.free[f.name]
            start = f.starts.get(label, f.initial)
            found = problem({f.name: start})
            if found:
                own = label is not None and label in f.starts
                raw = fs.initial[_key_of(fs.initial, label)] if own else fs.initial
                written = _written(raw, start)
                raise located.error(("free", f.name) + (("initial", _key_of(fs.initial, label)) if own else
                                                        ("initial",) if fs.initial is not None else ()),
                                    f"free.{f.name}: with the start {written}{with_group}, {found}")
        found = problem(starts)
        if found:
            raise located.error(("free",), f"free: with the starts of the free parameters together{with_group}, "
                                           f"{found}")
        for f in free:
            fs = spec.free[f.name]
            for key, raw, bound in (("lower", fs.lower, f.lower), ("upper", fs.upper, f.upper)):
                if raw is None or not np.isfinite(bound):
                    continue
                found = problem({**starts, f.name: bound})
                if found:
                    others = " (the other free parameters at their starts)" if len(free) > 1 else ""
                    raise located.error(("free", f.name, key), f"free.{f.name}: at its {key} bound "
                                        f"{_written(raw, bound)}{others}{with_group}, {found}; the fit may go "
                                        f"there: give {'a lower' if key == 'lower' else 'an upper'} bound the netlist "
                                        f"can take")


def _key_of(mapping, label: str):
    """The key of ``mapping`` (a per-group start as written: 1 or "1") that is the group ``label``."""
    return next(k for k in mapping if str(k) == label)


def _written(raw, value: float) -> str:
    """A value as the experiment wrote it ("-5 mm^2"), else as a number."""
    return raw.strip() if isinstance(raw, str) else f"{value:g}"


def _blamed(message: str, entries) -> str:
    """A block's complaint about a value, with the parameter qualified: 'orif: A = -5e-06 m^2 is below ...'
    -> 'orif.A = -5e-06 m^2 is below ...' (an override's 'override orif.Cd: Cd = 2 ...' likewise)."""
    import re

    m = re.match(r"^(?:override \S+: )?(?P<comp>[\w.]+): (?P<param>\w+) = ", message)
    if m and f"{m['comp']}.{m['param']}" in entries:
        return f"{m['comp']}.{m['param']} = " + message[m.end():]
    m = re.match(r"^override (?P<name>\S+): (?P<param>\w+) = ", message)
    if m and m["name"].endswith("." + m["param"]):
        return f"{m['name']} = " + message[m.end():]
    return message


def is_signal_level(table, name: str) -> bool:
    """Whether the netlist parameter ``name`` is read, as it stands, by a breakpoint of an array parameter
    (a profile's values) or by a signal block's parameter (of any unit, e.g. a constant's value): what a
    latent level of a command must be. A net's volume or a component's physical parameter is not."""
    for reader, items in table.readers(name):
        for item in items:
            if reader.scope.get(item.tree.id if isinstance(item.tree, ast.Name) else None) == name \
                    and (reader.elements is not None or reader.unit == GENERIC):
                return True
    return False
