"""``vphs calibrate``: declared fit, residual trace, augmentation, repeated at most twice more; then report.

    calibration = calibrate("netlists/experiments/relief_rig_steady.yaml", "out/calibrate/relief_rig")

Round k (k = 1, 2, 3):
1. fit the current model (the declared netlist, or the augmented one of the previous round, with the
   accepted parameters free beside the declared ones); lack-of-fit statistics, drift, held-out error;
2. write the screening netlist (every candidate at every place, parameters at zero), check it reproduces
   the fit, score every candidate (:mod:`blocks.calibrate.screening`), refit the best few and decide
   (:mod:`blocks.calibrate.selection`);
3. if one is accepted: write the augmented netlist ``round<k>/augmented.yaml`` (the original is never
   touched) with the effect as a real block or parameter, at its fitted value, and go on; else stop.
After the last round the final model is refitted from the written file (so what is reported is what the
file does). With two effects or more, the exchange check (:mod:`blocks.calibrate.exchange`) may then swap
an early one for an alternative of its round that fits better beside the later ones, and the elimination
check (:mod:`blocks.calibrate.elimination`) takes out one that no longer earns its place beside the
others (a later effect does its work). The verdict (:mod:`blocks.calibrate.verdict`): the effects found, the
ambiguities, and "unexplained discrepancy remains" when the final fit is still significantly worse than the
noise (chi^2, block means, residual whiteness or drift; p < 0.01 for the family of tests, Bonferroni), and
last the readings whose residual is beyond what their number makes plausible (:mod:`blocks.calibrate.outliers`).
A round whose refits show that its fit stopped in a local minimum is fitted again from there and traced again
(:func:`restart_if_short`).

Everything is written under ``out``; `vphs calibrate` runs this inside blocks.calibrate.output.replacing, so
that the folder holds one run's files or the previous run's, never a mix.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from blocks.calibrate.candidates import Context, registered
from blocks.calibrate.candidates.sensor_offset import shown_text
from blocks.calibrate.data import Dataset, load_data
from blocks.calibrate.elimination import Removal, try_removals
from blocks.calibrate.exchange import Exchange, file_name, free_of, try_exchanges
from blocks.calibrate.experiment import Experiment, Free, display_unit, load_experiment
from blocks.calibrate.fit import FitResult, fit
from blocks.calibrate.heldout import HeldOut, fallbacks, folds_of, heldout
from blocks.calibrate.latent_trace import choose_knots, knot_values
from blocks.calibrate.levels import level_read
from blocks.calibrate.model import Model
from blocks.calibrate.outliers import gross_residuals
from blocks.calibrate.patch import NetlistDoc, read_text, rounded, write_yaml, written
from blocks.calibrate.screening import Score, screen
from blocks.calibrate.selection import Decision, better_start, decide
from blocks.calibrate.stats import LackOfFit, drift, lack_of_fit
from blocks.calibrate.verdict import final_effects, verdict

# (the thesis's real data start at 29.5 with the flow force missing; a pressure read as a flow gave 1e6)
SCREENING_TOLERANCE = 1.0  # sigma: the screening netlist at zero is the fitted model; a larger difference in
# any residual (a run failed, or the solver is off) would make every score a score of the solver's error


@dataclass
class Stage:
    """A fitted model with its statistics."""

    netlist: Path
    model: Model
    fit: FitResult
    lof: LackOfFit
    heldout: HeldOut | None = None


@dataclass
class Round:
    index: int
    stage: Stage
    scores: list[Score]
    consistency: float
    decision: Decision
    notes: list[str]
    screening_file: Path
    augmented_file: Path | None = None
    smodel: Model | None = None
    stopped: str = ""  # why the trace stopped before judging any candidate ('' if it did not)


@dataclass
class Calibration:
    exp: Experiment
    data: Dataset
    out: Path
    rounds: list[Round] = field(default_factory=list)
    final: Stage | None = None
    initial: Stage | None = None
    verdict: list[str] = field(default_factory=list)
    unexplained: bool = False
    accepted: list = field(default_factory=list)  # (key, title, where, param, value, se, unit)
    seconds: dict = field(default_factory=dict)
    exchanges: list[Exchange] = field(default_factory=list)  # the exchange check after the trace
    removals: list[Removal] = field(default_factory=list)  # the elimination check after the exchange check
    simulations: int = 0  # settling runs and time-series runs
    equilibria: int = 0  # Newton solves of steady points
    calibrated: Path | None = None  # the final netlist with the fitted values (write_calibrated)
    held_levels: list = field(default_factory=list)  # command levels no sample reads (latent_globals)
    restarts: list = field(default_factory=list)  # verdict lines: fits restarted from a refit (better_start)


def calibrate(experiment: str | Path | Experiment, out: str | Path, progress=None, rounds: int | None = None,
              with_heldout: bool = True, warn=None) -> Calibration:
    """``progress``: a line at each step (``vphs calibrate`` prints them unless -q); ``warn``: a line about what
    the data allow (few degrees of freedom: :func:`degrees_of_freedom`), printed even with -q."""
    say = progress or (lambda message: None)
    clock = time.perf_counter()
    exp = experiment if isinstance(experiment, Experiment) else load_experiment(experiment)
    out = Path(out)
    refuse_to_overwrite_inputs(exp, out)
    data = load_data(exp)
    scheme, folds = folds_of(data, exp.spec.heldout) if with_heldout else ("", [])
    cal = Calibration(exp, data, out)
    globals_ = per_group_globals(exp, data) + latent_globals(exp, data, cal.held_levels)
    warnings = drift_untested(exp, data)  # said after the first fit (see below)
    if with_heldout and warn:  # the held-out test run other than asked (without warn: said as progress)
        warnings += fallbacks(data, exp.spec.heldout, exp.spec.group is not None)
    few = []  # the first model's degrees of freedom, when few (checked once it is built, before its fit)

    def count(model: Model) -> None:
        few[:] = [line for line in [degrees_of_freedom(exp, data, model, folds if with_heldout else None)] if line]
    netlist = exp.netlist
    x_prev: np.ndarray | None = None
    prev_model: Model | None = None
    n_rounds = rounds or exp.spec.trace.rounds
    for k in range(1, n_rounds + 1):
        t0 = time.perf_counter()
        stage = fit_stage(netlist, exp, data, globals_, x_prev, prev_model, before_fit=count if k == 1 else None)
        say(f"round {k}: fitted {len(globals_)} parameters, chi^2/nu = {stage.lof.reduced:.3g} "
            f"({stage.model.simulations} runs, {time.perf_counter() - t0:.1f} s)")
        if k == 1:
            cal.initial = stage
            if "(" in scheme and not warn:  # not the scheme asked for, or fewer folds than asked (after the first
                say(f"held out: {scheme}")  # fit: a bad input found there must be the one line printed)
            for line in few + warnings:  # vphs calibrate: said even with -q (the held-out fallbacks among them)
                (warn or say)(line)
        t1 = time.perf_counter()
        rnd = trace_round(k, stage, exp, data, globals_, out, with_heldout)
        stage, rnd = restart_if_short(cal, k, stage, rnd, netlist, globals_, with_heldout, say)
        stage.heldout = rnd.decision.base_heldout or (heldout(stage.model, stage.fit, exp.spec.heldout)
                                                       if with_heldout else None)
        cal.rounds.append(rnd)
        cal.simulations += stage.model.simulations  # the fit's, the trace's (screening, refits) and held-out
        cal.equilibria += stage.model.equilibria
        cal.seconds[f"round {k}"] = time.perf_counter() - t0
        acc = rnd.decision.accepted
        say(f"round {k}: screened {len(rnd.scores)} candidate places ({time.perf_counter() - t1:.1f} s): "
            + outcome(exp, rnd))
        if acc is None:
            break
        place = acc.score.place
        cal.accepted.append((place.key, registered()[place.candidate].title, place.where, place.param, acc.phi,
                             acc.se, place.unit))
        globals_ = globals_ + [free_of(place, acc.phi, acc.score.step)]
        if place.kind == "netlist":
            doc = NetlistDoc.read(netlist)
            doc.add_parameter(place.param, written(float(acc.phi), place.unit))
            registered()[place.candidate].patch(doc, place)
            target = out / f"round{k}" / "augmented.yaml"
            doc.write(target, header=augmented_header(exp, cal, netlist))
            rnd.augmented_file = target
            netlist = target
        prev_model = acc.model
        x_prev = acc.fit.x
        write_augmented_experiment(exp, cal, netlist, globals_, acc, out)
    if cal.rounds and cal.rounds[-1].decision.accepted is not None:
        # the last trace accepted an effect: fit the written augmented model once more (no trace after it)
        t0 = time.perf_counter()
        final = fit_stage(netlist, exp, data, globals_, x_prev, prev_model)
        cal.simulations += final.model.simulations
        cal.equilibria += final.model.equilibria
        cal.seconds["final fit"] = time.perf_counter() - t0
        cal.final = final
    else:
        cal.final = cal.rounds[-1].stage if cal.rounds else None
    globals_ = exchange(cal, globals_)
    eliminate(cal, globals_)
    if with_heldout and cal.final is not None and cal.final.heldout is None:
        # once, for the model that ended final (the final fit's, or a check's that replaced it)
        t0 = time.perf_counter()
        runs, solves = cal.final.model.simulations, cal.final.model.equilibria
        cal.final.heldout = heldout(cal.final.model, cal.final.fit, exp.spec.heldout)
        cal.simulations += cal.final.model.simulations - runs
        cal.equilibria += cal.final.model.equilibria - solves
        cal.seconds["held-out of the final model"] = time.perf_counter() - t0
    # the effects as the final model has them (a later effect can move an earlier one's value)
    for k, (key, title, where, param, value, se, unit) in enumerate(cal.accepted):
        j = cal.final.model.layout.index(param)
        cal.accepted[k] = (key, title, where, param, float(cal.final.fit.x[j]), float(cal.final.fit.se[j]), unit)
    cal.verdict, cal.unexplained = verdict(cal)
    cal.verdict[:0] = few
    cal.verdict += gross_residuals(cal)  # a line of its own after the verdict's (blocks.calibrate.outliers)
    cal.verdict += [f"the final model's run warns: {line}" for line in cal.final.model.run_warnings(cal.final.fit.x)] \
        if cal.final else []
    cal.calibrated = write_calibrated(cal)
    cal.seconds["total"] = time.perf_counter() - clock
    return cal


def drift_untested(exp: Experiment, data: Dataset) -> list[str]:
    """A warning when ``drift:`` names parameters but the data have one group (or run): nothing to refit them
    per group against, so the drift test is not made."""
    if not exp.spec.drift or len(data.groups) >= 2:
        return []
    kind = "group" if data.kind == "steady" else "run"
    return [f"drift: {', '.join(exp.spec.drift)} would be refitted per {kind} to test that "
            f"{'it stays' if len(exp.spec.drift) == 1 else 'they stay'} constant, but the data have one {kind}"
            + (" (no grouping column)" if exp.spec.group is None and data.kind == "steady" else "")
            + ": drift is not tested"]


FEW_DEGREES = 5  # below this many degrees of freedom a calibration is run, with a warning: its tests can hardly fail


def degrees_of_freedom(exp: Experiment, data: Dataset, model: Model, folds: list | None) -> str:
    """The declared fit's degrees of freedom, nu = readings - unknowns (``model``'s residual rows: every measured
    column at every point or sample; its parameters: the fitted ones and, for steady points, each point's true
    input values), checked before its first fit: an error when none is left (nu <= 0: the fit is exact whatever
    the model, chi^2 = 0, and no test can say anything) or when the data make fewer than 2 held-out folds (a
    refit without the only fold has nothing to fit); with few (nu < FEW_DEGREES) a warning, returned: the
    lack-of-fit and held-out tests then have almost no power."""
    globals_ = model.layout.globals
    readings, unknowns = model.n_rows, model.layout.size
    latent = unknowns - len(globals_)
    nu = readings - unknowns
    what = "point" if data.kind == "steady" else "sample"
    counted = (f"{readings} readings ({data.n} {what}{'s' * (data.n != 1)} x {len(exp.channels)} columns: "
               f"{', '.join(c.name for c in exp.channels)}) and {unknowns} unknowns ({len(globals_)} fitted "
               f"parameter{'s' * (len(globals_) != 1)}" + (f", {latent} true input value{'s' * (latent != 1)}, one "
                                                            f"per point and imposed input" if latent else "") + ")")
    if nu <= 0:
        raise exp.error(("data",), f"data: {counted}: nu = {nu}, no degree of freedom is left to test the fit with "
                                   f"(it would be exact whatever the model); more {what}s are needed")
    if folds is not None and len(folds) < 2:
        raise exp.error(("heldout",) if "heldout" in exp.spec.model_fields_set else ("data",),
                        f"heldout: the data ({data.n} {what}{'s' * (data.n != 1)}) make {len(folds)} held-out fold; "
                        f"the held-out test refits without each fold and needs 2 at least; more {what}s are needed")
    if nu < FEW_DEGREES:
        return (f"only nu = {nu} degree{'s' * (nu != 1)} of freedom ({counted}): the lack-of-fit and held-out tests "
                f"have almost no power, and what they find says little; more {what}s are needed to test the model")
    return ""


def write_calibrated(cal: Calibration) -> Path | None:
    """``calibrated.yaml``: the final model's netlist with every fitted parameter (the declared free ones,
    the effects found) at its final value, every digit of it, and the experiment's overrides in, so that
    ``vphs run`` simulates the calibrated model. Its header lists each fitted value for people, to the
    digits its standard error warrants plus 2 (:func:`blocks.calibrate.patch.rounded`), with the SE. A time
    series of one run gets its fitted command too (the latent levels, or the profile through a recorded
    trace's knots): run, it reproduces the final fit. Steady points and runs of several keep the netlist's
    own inputs and per-group values (the experiment's differ point by point, run by run), and so do
    parameters fitted per group (named in the header). Sensor corrections act on the data, not the netlist.
    A fitted parameter that is neither a netlist parameter nor a component's (one inside a subsystem) is
    listed in the header as not set."""
    if cal.final is None:
        return None
    doc = NetlistDoc.read(cal.final.netlist)
    x, se, layout = cal.final.fit.x, cal.final.fit.se, cal.final.model.layout
    one_run = cal.data.kind == "time" and len(cal.data.groups) <= 1  # its fitted inputs are the netlist's too
    kinds = ("declared", "candidate") + (("latent",) if one_run else ())
    fitted = [(k, g) for k, g in enumerate(layout.globals) if g.kind in kinds and g.run is None]
    values = [(name, value) for name, value in cal.exp.overrides.items()] + [
        (g.name, written(float(x[k]), g.unit)) for k, g in fitted]
    shown = {g.name: f"{rounded(float(x[k]), float(se[k]), g.unit)}{_se_text(float(se[k]), g.unit)}"
             for k, g in fitted}
    per_group = [g.name for g in layout.globals if g.kind == "declared" and g.run is not None]
    if one_run:  # a recorded command: the profile through the fitted knots instead of the recording
        for (profile, _run), (times, knots) in cal.final.model.trace_knots(x).items():
            values += [(f"{profile}.times", [float(t) for t in times]),
                       (f"{profile}.values", [float(v) for v in knots])]
    parameters, components, missed = doc.section("parameters"), doc.section("components"), []
    for name, value in values:
        component, _, param = name.rpartition(".")
        if name in parameters:
            parameters[name] = value
        elif component in components:
            doc.set_param(component, param, value)
        else:
            missed.append(name)
    listed = "".join(f"\n  {n} = {shown.get(n, v) if not isinstance(v, list) else f'({len(v)} knots)'}"
                     for n, v in values[len(cal.exp.overrides):]) or " none"
    inputs = (("The command is the fitted one (its latent levels or knots)" if cal.exp.fits_inputs else
               "The command is the netlist's own (no input is fitted)") + ": `vphs run` reproduces the fit, sensor "
              "corrections aside." if one_run else
              "The imposed inputs (each steady point's, or each run's command) and per-group values are the "
              "netlist's own: `vphs run` simulates the calibrated model at those.")
    target = cal.out / "calibrated.yaml"
    doc.write(target, header=f"Calibrated by vphs calibrate for {Path(cal.exp.file).name}: {cal.final.netlist.name} "
                             f"with the experiment's overrides and every fitted parameter at its final value "
                             f"(below to the digits its standard error warrants plus 2, with the SE; in the file "
                             f"every digit):{listed}"
                             f"\n{inputs}" + (f"\nNot set here (not a netlist or component parameter): "
                                               f"{', '.join(missed)}." if missed else "")
                             + (f"\nFitted per group, so not set here (the report gives each): "
                                f"{', '.join(per_group)}." if per_group else ""))
    return target


def _se_text(se: float, unit: str) -> str:
    """' +- 4.1e-05' after a value in calibrated.yaml's header (its display unit is the value's)."""
    from blocks.units import display_factor

    if not np.isfinite(se):
        return " (not fixed by the data)" if np.isinf(se) else ""
    return f" +- {se / (1.0 if unit in ('', '1', 'SI') else display_factor(unit)):.2g}"


def refuse_to_overwrite_inputs(exp: Experiment, out: Path) -> None:
    """The run writes its netlists and report under ``out``: an input there (continuing a calibration from
    its own experiment_augmented.yaml into the same folder) would be overwritten while it is being read."""
    from blocks.errors import VphsError

    folder = out.resolve()
    inputs = [Path(exp.file).resolve(), exp.netlist] + list(exp.data_files or [exp.data])
    if exp.spec.group_table is not None:
        inputs.append(exp.resolve(exp.spec.group_table.file))
    for path in inputs:
        if folder in path.parents:
            raise VphsError(f"{exp.file}: its input {path} is inside the output folder {out}, which this run "
                            f"writes into; give another folder (-o)")


def exchange(cal: Calibration, globals_: list[Free]) -> list[Free]:
    """The exchange check (blocks.calibrate.exchange); an exchange made becomes the final model, its
    netlist and experiment file the written ones. Returns the final model's free parameters."""
    t0 = time.perf_counter()
    cal.exchanges = try_exchanges(cal, globals_, _refitter(cal))
    _count_runs(cal, [ex.stage for ex in cal.exchanges])
    made = next((ex for ex in cal.exchanges if ex.made), None)
    if made is not None:
        place = made.place
        k = next(i for i, a in enumerate(cal.accepted) if a[0] == made.out_key)
        cal.accepted[k] = (place.key, registered()[place.candidate].title, place.where, place.param, made.phi,
                           made.se, place.unit)
        _adopt(cal, made.stage, made.netlist, made.globals_)
    if cal.exchanges:
        cal.seconds["exchange check"] = time.perf_counter() - t0
    return made.globals_ if made is not None else globals_


def eliminate(cal: Calibration, globals_: list[Free]) -> None:
    """The elimination check (blocks.calibrate.elimination); after a removal the model without the effect is
    the final one, its netlist and experiment file the written ones."""
    if cal.final is None:
        return
    t0 = time.perf_counter()
    cal.removals = try_removals(cal.final, final_effects(cal), globals_, cal.exp.netlist, cal.out, _refitter(cal))
    _count_runs(cal, [test.stage for test in cal.removals])
    removed = [test for test in cal.removals if test.removed]
    if removed:
        gone = {test.key for test in removed}
        cal.accepted = [a for a in cal.accepted if a[0] not in gone]
        _adopt(cal, removed[-1].stage, removed[-1].netlist, removed[-1].globals_)
    if any(test.refitted for test in cal.removals):
        cal.seconds["elimination check"] = time.perf_counter() - t0


def _refitter(cal: Calibration):
    """fit_stage(netlist, globals_, x_prev, prev_model) on the calibration's experiment and data."""
    return lambda netlist, g, x, model: fit_stage(netlist, cal.exp, cal.data, g, x, model)


def _count_runs(cal: Calibration, stages) -> None:
    for stage in stages:
        if stage is not None:
            cal.simulations += stage.model.simulations
            cal.equilibria += stage.model.equilibria


def _adopt(cal: Calibration, stage: Stage, netlist: Path, globals_: list[Free]) -> None:
    """A check's model becomes the final one: its netlist and experiment file are the written ones (its
    held-out error is computed once the checks are done, for the model that ends final)."""
    cal.final = stage
    write_augmented_experiment(cal.exp, cal, netlist, globals_, stage, cal.out)


def per_group_globals(exp: Experiment, data: Dataset) -> list[Free]:
    """The declared free parameters, each ``per: group`` one made a copy per group of the data,
    ``<name>[<group>]``, with the same bounds and step and its group's start (given per group, or the one
    start) (the groups: the grouping column's values, or the data files of a time series of several runs).
    An error naming the entry if the data have one group, or a start names a group the data do not have."""
    out = []
    for f in exp.free:
        if not f.per_group:
            out.append(f)
            continue
        if len(data.groups) < 2:
            raise exp.error(("free", f.name, "per"), f"free.{f.name}.per: group: the data have one group"
                            + (" (no grouping column, one data file)" if exp.spec.group is None else "")
                            + "; leave per: out to fit one value")
        unknown = [g for g in f.starts if g not in data.groups]
        if unknown:
            raise exp.error(("free", f.name, "initial", unknown[0]), f"free.{f.name}.initial: no group "
                            f"'{unknown[0]}' in the data (groups: {', '.join(data.groups)})")
        out += [replace(f, name=f"{f.name}[{label}]", run=label, per_group=False, starts={},
                        initial=f.starts.get(label, f.initial)) for label in data.groups]
    return out


def latent_globals(exp: Experiment, data: Dataset, held: list[str] | None = None) -> list[Free]:
    """The latent values of time-series inputs as free globals: the levels of a command profile (netlist
    parameters; with several runs, one set per run, ``<level>[<run>]``, starting at the run's netlist
    value), or the knots of a recorded trace (``latent: trace``, :mod:`blocks.calibrate.latent_trace`; with
    several runs, each run's own knots, chosen from its own recording; an error naming the input if a
    recording needs too many knots, or if the netlist reads the recording from a file of several runs).

    A level in force only after its run's last sample acts on no sample (the profile is the same up to then
    whatever the level) and is not fitted: nothing fixes it, and a fit let it drift (to -6e9 on the drive
    line cut at 2 s). It keeps the netlist's value; its name goes into ``held``. A level in force before the
    run's first sample is fitted: it acts on the state the samples start from (its held-out refit is another
    matter: blocks.calibrate.heldout)."""
    out = []
    if data.kind != "time":
        return out
    from blocks.circuit import Circuit

    circuit = Circuit.from_file(exp.netlist, compile=False)
    table = circuit.flat.parameters
    values = table.evaluate({})
    runs = list(data.groups) if len(data.groups) > 1 else [None]  # several runs: each its own levels
    for ch in exp.inputs:
        sigma = data.sigma[ch.name]
        for name in ch.latent:
            for run in runs:
                over = dict(exp.overrides, **exp.groups.get(run, {})) if run is not None else {}
                start = float(values[name] if run is None else table.evaluate(over)[name])
                label = name if run is None else f"{name}[{run}]"
                times = data.t if run is None else data.t[data.groups[run]]
                if not level_read(table, over, name, times, until=float(np.max(times))):
                    if held is not None:
                        held.append(label)
                    continue
                out.append(Free(label, start, -np.inf, np.inf, 0.1 * sigma,  # a bare level: its column's unit
                                display_unit(table.entries[name]) or ch.unit, "latent", run=run))
        if ch.trace is not None:
            times = np.asarray(values[ch.trace.rsplit(".", 1)[0] + ".times"], dtype=float)
            if runs != [None] and not np.all(np.diff(times) > 0):
                raise exp.error(("inputs", ch.name, "latent"), f"inputs.{ch.name}.latent: trace: the netlist's "
                                f"profile reads the times of a file of several runs, which go back at each run's "
                                f"start; give each run its own data file (data: [a.csv, b.csv]) and let the "
                                f"netlist read one of them (each run gets its own knots)")
            for run in runs:
                out += trace_globals(exp, data, ch, run, len(times))
    return out


def trace_globals(exp: Experiment, data: Dataset, ch, run: str | None, length: int) -> list[Free]:
    """The knots of a latent trace (:mod:`blocks.calibrate.latent_trace`) as free globals: each knot's value
    (``<profile>.values[knot j]``) and, but for the first and last, its time (``<profile>.times[knot j]``),
    bounded halfway to its neighbours' start times so that the knots keep their order. With several runs,
    ``run``'s knots, chosen from its samples alone and named ``<profile>.values[knot j][<run>]``. An error
    naming the input (and the run) if the recording needs more knots than the profile's ``length``
    breakpoints, or more than :data:`blocks.calibrate.latent_trace.MAX_KNOTS`."""
    idx = np.arange(data.n) if run is None else data.groups[run]
    t, measured, sigma = data.t[idx], data.measured[ch.name][idx], data.sigma[ch.name]
    of_run = "" if run is None else f" (run '{run}')"
    try:
        knots = choose_knots(t, measured, sigma)
    except ValueError as exc:
        raise exp.error(("inputs", ch.name, "latent"), f"inputs.{ch.name}.latent: trace{of_run}: {exc}; impose "
                        f"it exactly (no latent:) or model the command by its levels") from None
    profile = ch.trace.rsplit(".", 1)[0]
    if len(knots) > length:
        raise exp.error(("inputs", ch.name, "latent"), f"inputs.{ch.name}.latent: trace{of_run}: {len(knots)} "
                        f"knots, more than the {length} breakpoints of the profile '{profile}'")
    times = t[knots]
    gap = 1e-3 * float(np.min(np.diff(t)))
    middles = 0.5 * (times[:-1] + times[1:])
    suffix = "" if run is None else f"[{run}]"
    out = []
    for j, (at, z) in enumerate(zip(times, knot_values(t, measured, knots)), start=1):
        out.append(Free(f"{profile}.values[knot {j}]{suffix}", float(z), -np.inf, np.inf, 0.1 * sigma, "", "trace",
                        at=float(at), run=run))
        if 1 < j < len(times):
            out.append(Free(f"{profile}.times[knot {j}]{suffix}", float(at), float(middles[j - 2] + gap),
                            float(middles[j - 1] - gap), 0.05 * float(np.median(np.diff(t))), "s",
                            "trace_time", run=run))
    return out


def fit_stage(netlist: Path, exp: Experiment, data: Dataset, globals_: list[Free], x_prev, prev_model,
              before_fit=None) -> Stage:
    """``before_fit(model)``: a check of the model built, before any run (calibrate's degrees of freedom)."""
    from blocks.circuit import Circuit

    circuit = Circuit.from_file(netlist)
    model = Model(circuit, exp, data, globals_)
    if before_fit is not None:
        before_fit(model)
    x0 = model.initial()
    if x_prev is not None and prev_model is not None:
        x0 = prev_model.extend(x_prev, model)
    res = fit(model, x0, np.ones(model.layout.size, dtype=bool), max_nfev=60)
    lof = lack_of_fit(model, res)
    lof.drift = drift(model, res, list(exp.spec.drift))
    return Stage(Path(netlist), model, res, lof)


def context(stage: Stage, exp: Experiment, data: Dataset, doc: NetlistDoc) -> Context:
    from blocks.units import parse_unit

    circuit = stage.model.circuit
    of = {o.name: o.of for o in circuit.flat.outputs}
    logged = {of[c.signal] for c in exp.channels if c.signal and of.get(c.signal) in circuit.flat.nets}

    def channels_in(unit):
        return [c for c in exp.channels if c.si_unit not in ("", "1", "SI")
                and parse_unit(c.si_unit).same_dimension(parse_unit(unit))]

    flows = channels_in("m^3/s")
    q_ref = max((float(np.max(np.abs(data.measured[c.name]))) for c in flows), default=1e-3) or 1e-3
    pressures = channels_in("Pa")
    p_ref = min((data.sigma[c.name] for c in pressures), default=1e4)
    speeds = channels_in("rad/s")
    w_ref = max((float(np.max(np.abs(data.measured[c.name]))) for c in speeds), default=10.0) or 10.0
    velocities = channels_in("m/s")
    v_ref = max((float(np.max(np.abs(data.measured[c.name]))) for c in velocities), default=0.1) or 0.1
    t_span = max(float(data.t[idx[-1]] - data.t[idx[0]]) for idx in data.groups.values()) if data.kind == "time" \
        else stage.model.settings.t_end
    values = circuit.vectors(dict(exp.overrides)).values
    return Context(doc, circuit.flat, circuit.structure, values, exp, data, logged, q_ref, p_ref, w_ref, t_span,
                   v_ref=v_ref)


def all_places(ctx: Context, spec, taken: set[str]):
    """Every place of every candidate asked for, except those whose parameter the model has already (an
    effect accepted in an earlier round, or written in by an earlier calibration)."""
    places = []
    for name, cand in registered().items():
        if spec.only is not None and name not in spec.only:
            continue
        if name in spec.exclude:
            continue
        places += [p for p in cand.places(ctx) if p.param not in taken]
    return places


def trace_round(k: int, stage: Stage, exp: Experiment, data: Dataset, globals_: list[Free], out: Path,
                with_heldout: bool) -> Round:
    from blocks.circuit import Circuit

    doc = NetlistDoc.read(stage.netlist)
    ctx = context(stage, exp, data, doc)
    taken = {g.name for g in globals_} | set(stage.model.circuit.flat.parameters.entries)
    places = all_places(ctx, exp.spec.trace, taken)
    sdoc = doc.copy()
    for place in places:
        if place.kind == "netlist":
            sdoc.add_parameter(place.param, place.zero)
            registered()[place.candidate].patch(sdoc, place)
    screening_file = out / f"round{k}" / "screening.yaml"
    sdoc.write(screening_file, header=f"Screening netlist of round {k}: {stage.netlist.name} with every candidate "
                                      f"at every place, parameters at zero (generated by vphs calibrate).")
    scircuit = Circuit.from_file(screening_file)
    extra = [free_of(p, p.zero) for p in places]
    smodel = Model(scircuit, exp, data, list(globals_) + extra)
    xs = stage.model.extend(stage.fit.x, smodel)
    column_of = {p.key: smodel.layout.index(p.param) for p in places}
    sbase = _carry(stage.fit, stage.model, smodel)
    scores, consistency = screen(smodel, xs, sbase, places, column_of)
    stage.model.simulations += smodel.simulations
    stage.model.equilibria += smodel.equilibria
    if consistency > SCREENING_TOLERANCE:
        stopped = (f"the screening netlist does not reproduce the fit (its residuals differ by up to "
                   f"{consistency:.3g} sigma" + (f"; the last solver message: {smodel.failures[-1]}"
                                                 if smodel.failures else "")
                   + "), so no candidate is judged on it: check the solver settings")
        return Round(k, stage, scores, consistency, Decision([], None, [], [], None), list(ctx.notes),
                     screening_file, smodel=smodel, stopped=stopped)
    lean: dict[str, Model] = {}

    def candidate_model(score: Score):
        """The current netlist with this one candidate: the file that would become the augmented netlist."""
        place = score.place
        if place.kind == "netlist":
            cdoc = doc.copy()
            cdoc.add_parameter(place.param, place.zero)
            registered()[place.candidate].patch(cdoc, place)
            file = cdoc.write(out / f"round{k}" / "candidates" / f"{file_name(place.key)}.yaml",
                              header=f"{stage.netlist.name} with the candidate {place.key} (parameter at zero)")
            circuit = Circuit.from_file(file)
        else:
            circuit = stage.model.circuit
        model = Model(circuit, exp, data, list(globals_) + [free_of(place, place.zero, score.step)])
        lean[place.key] = model
        return model, stage.model.extend(stage.fit.x, model), model.layout.index(place.param)

    decision = decide(scores, exp.spec.trace.top, exp.spec.heldout, stage.model, stage.fit, candidate_model,
                      with_heldout)
    for model in lean.values():
        stage.model.simulations += model.simulations
        stage.model.equilibria += model.equilibria
    return Round(k, stage, scores, consistency, decision, list(ctx.notes), screening_file, smodel=smodel)


def _carry(res: FitResult, model: Model, smodel: Model) -> FitResult:
    """The fit's result expressed in the screening model's parameter vector (new entries inactive)."""
    x = model.extend(res.x, smodel)
    active = np.zeros(smodel.layout.size, dtype=bool)
    names = smodel.layout.names()
    old = {n: k for k, n in enumerate(model.layout.names())}
    for j, n in enumerate(names):
        if n in old and res.active[old[n]]:
            active[j] = True
    se = np.full(smodel.layout.size, np.nan)
    for j, n in enumerate(names):
        if n in old:
            se[j] = res.se[old[n]]
    return FitResult(x, active, res.rows, res.r, res.J, res.chi2, res.n, res.p, res.cov, se, res.nfev, res.message,
                     res.unsettled, res.failures, res.converged)


RESTART_GAIN = 10.0
"""The fit restarted from there is kept if its chi^2 is lower by over this (the BIC margin of an effect)."""


def restart_if_short(cal: Calibration, k: int, stage: Stage, rnd: Round, netlist: Path, globals_: list[Free],
                     with_heldout: bool, say) -> tuple[Stage, Round]:
    """The round's fit and trace, or, when a refit shows that the fit stopped short of its best
    (:func:`blocks.calibrate.selection.better_start`), the fit restarted from that refit's values (without
    its candidate) and the round traced again from it, if that lowers chi^2 by over RESTART_GAIN; said in the
    verdict."""
    better = better_start(rnd.decision.refits, stage.fit.chi2)
    if better is None:
        return stage, rnd
    restarted = fit_stage(netlist, cal.exp, cal.data, globals_, better.fit.x, better.model)
    if not restarted.fit.chi2 < stage.fit.chi2 - RESTART_GAIN:
        _count_runs(cal, [restarted])
        return stage, rnd
    cal.restarts.append(
        f"round {k}: the fit had stopped short of its best (chi^2 {stage.fit.chi2:.5g}): the refit with "
        f"{better.score.place.key} reached chi^2 {better.fit.chi2:.5g} with that candidate {better.z:.2g} SE "
        f"from zero, so through the other parameters; refitted from there without it: chi^2 "
        f"{restarted.fit.chi2:.5g}, and the round was traced again from that fit")
    say(cal.restarts[-1])
    _count_runs(cal, [stage])  # the fit and trace it replaces
    if k == 1:
        cal.initial = restarted
    return restarted, trace_round(k, restarted, cal.exp, cal.data, globals_, cal.out, with_heldout)


def outcome(exp: Experiment, rnd: Round) -> str:
    """What a round's trace ended in, for its progress line: the effect accepted, its value in the unit the
    report shows it in (a sensor offset in its channel's unit, not in SI), or why none was."""
    acc = rnd.decision.accepted
    if acc is None:
        return f"stopped: {rnd.stopped}" if rnd.stopped else "nothing accepted"
    place = acc.score.place
    return f"accepted {place.key} = {shown_text(exp, place.key, acc.phi, acc.se, place.unit)}"


def augmented_header(exp: Experiment, cal: Calibration, netlist: Path) -> str:
    found = "; ".join(f"{t} {w} ({p} = {shown_text(exp, key, v, s, u)})" for key, t, w, p, v, s, u in cal.accepted)
    return (f"Augmented by vphs calibrate from {netlist.name} for {Path(exp.file).name}.\n"
            f"Added: {found}.\nThe original netlist is unchanged.")


def write_augmented_experiment(exp: Experiment, cal: Calibration, netlist: Path, globals_: list[Free], acc,
                               out: Path) -> Path:
    """The experiment file for the augmented model: same data, the new netlist, the accepted parameters
    free beside the declared ones (every free parameter starting at its fitted value: a declared one in the
    unit it is shown in, an effect's in SI), sensor corrections fixed at their fitted values (an offset in its
    channel's unit, as the data are: a bare number there is refused as one read in SI; a gain bare)."""
    import os

    data = dict(exp.located.data)
    target = out / "experiment_augmented.yaml"
    base = Path(exp.file).resolve().parent

    def rel(path: Path) -> str:
        return os.path.relpath(Path(path).resolve(), target.parent.resolve())

    data["netlist"] = rel(netlist)
    data["data"] = [rel(f) for f in exp.data_files] if isinstance(exp.spec.data, list) else rel(exp.data)
    if exp.spec.group_table is not None:
        gt = dict(data["group_table"])
        gt["file"] = rel(base / exp.spec.group_table.file)
        data["group_table"] = gt
    free = {name: dict(spec or {}) for name, spec in (data.get("free") or {}).items()}
    corrections = dict(data.get("corrections") or {})
    fitted = {g.name: float(acc.fit.x[k]) for k, g in enumerate(acc.model.layout.globals)}
    units = {g.name: g.unit for g in globals_}
    for name in free:  # start where this calibration ended, in the unit the parameter is shown in
        if name in fitted:
            free[name]["initial"] = written(fitted[name], units.get(name, ""))
    for g in globals_:
        value = fitted.get(g.name, float(g.initial))
        if g.kind == "candidate":  # in its SI unit, which a rerun shows it in
            free[g.name] = {key: written(v, g.unit) for key, v in
                            (("initial", value), ("lower", float(g.lower)), ("upper", float(g.upper)))}
        elif g.kind == "correction":
            what, ch = g.name.split(":", 1)
            unit = next(c.unit for c in exp.channels if c.name == ch) if what == "offset" else "1"
            corrections.setdefault(ch, {})[what] = written(value, unit)
    data["free"] = free
    if corrections:
        data["corrections"] = corrections
    write_yaml(target, data, read_text(exp.file), header="Written by vphs calibrate: the experiment with the "
                                                         "accepted effects.")
    return target
