"""The report of a job: markdown with the best parameters and the cost history, and its plots.

Optimisation (``<output>/``): ``report.md``; ``convergence.png`` (every evaluation's cost and the best so
far against its number on the method's path); ``best_signals.png`` (the best design re-simulated: each cost term's
signal against its reference, or the high-passed signal, per load case); ``best.json`` (the best
parameters in SI (``parameters``, their SI units in ``units``) and as shown (``shown``: name -> value and
unit), the cost terms, the job's fixed ``set:`` values and each load case's overrides (SI), and per load
case the ``vphs run`` command line that simulates the best design again); ``best_<case>.csv``
(the best run's logged signals). The free parameters alone do not reproduce a cost: the simulation also
had the fixed values and the load case's, so the report gives the whole command line.
The report covers the method's path only (:mod:`blocks.optimise.runner`): candidates evaluated ahead and
discarded are counted, not shown.
Beside the best, the report gives the cost of the netlist's own design (evaluated first, off the path) and
warns when the best found is not better than it (:func:`netlist_comparison`, also on the console).
Sweep (``<output>/sweep/``): ``report.md`` with the table of every point, ``sweep.csv`` and ``sweep.png``
(the cost and each term against the parameter; a map of the cost over a two-parameter grid). sweep.csv
ends with each point's ``status``, ``error`` and ``warnings`` (the run's warnings joined by "; ": a
range_check's limit broken, a cavity), so that the CSV alone says which points are not to be trusted.

Parameters are shown in the units the job wrote them in (:mod:`blocks.optimise.display`): the tables of
report.md, sweep.csv (columns ``name [unit]``, values in that unit) and the plots' axes; the ``vphs run``
lines stay SI.

Every file is written atomically (a temporary file renamed into place), so a report is either the old
one or the new one, never half of each.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import shlex
from pathlib import Path

import numpy as np

from blocks.optimise.costs import combine
from blocks.optimise.display import in_unit, shown
from blocks.provenance import environment, environment_line
from blocks.result import atomic_write_figure, atomic_write_text


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _fmt(v, digits: int = 6) -> str:
    if v is None:
        return "-"
    if isinstance(v, bool):
        return str(v).lower()
    if isinstance(v, float) and not math.isfinite(v):
        return str(v)
    return f"{v:.{digits}g}" if isinstance(v, (int, float)) else str(v)


def _param(job, name: str, value: float) -> str:
    """An SI value of parameter ``name`` as text in the unit it is shown in (:mod:`blocks.optimise.display`)."""
    return shown(value, job.units.get(name, "")) if math.isfinite(value) else f"{value}"


def _value(job, name: str, value: float) -> float:
    """An SI value of parameter ``name`` in the unit it is shown in (a number, for tables and plots)."""
    return in_unit(value, job.units.get(name, ""))


def _column(job, name: str) -> str:
    """A column's or an axis's title: ``name [unit]``, the name alone for a plain number."""
    unit = job.units.get(name, "")
    return f"{name} [{unit}]" if unit else name


# ---- optimisation -----------------------------------------------------------------------------------------
def on_path_number(records: list[dict], record: dict) -> int:
    """A record's number on the method's path (0 first): what a one-worker run numbers it. The log's
    ``index`` also counts the evaluations discarded on the way, so it depends on the number of workers."""
    return next(k for k, r in enumerate(records) if r is record)


def write_optimise_report(summary) -> Path:
    job, folder = summary.job, Path(summary.folder)
    records = sorted(summary.records, key=lambda r: r["index"])  # the path, in order
    best = summary.best
    _convergence_plot(records, folder / "convergence.png", job.name)
    signals_png = None
    if best is not None:
        results = _resimulate(job, best["parameters"])
        summary.step_checks = [f"load case '{case}': {r.step_check}" if len(results) > 1 else r.step_check
                               for case, r in results.items() if r is not None and r.step_check]
        signals_png = folder / "best_signals.png"
        number = on_path_number(records, best)
        _signals_plot(job, results, signals_png, f"{job.name}: best design (evaluation {number})")
        for case, result in results.items():
            if result is not None:
                result.write_csv(folder / f"best_{case}.csv")
        atomic_write_text(folder / "best.json", json.dumps(
            {"job": job.file, "evaluation": number, "log_index": best["index"], "cost": best["cost"],
             "parameters": best["parameters"], "units": {k: job.si_units.get(k, "") for k in best["parameters"]},
             "shown": {k: {"value": _value(job, k, v), "unit": job.units.get(k, "")}
                       for k, v in best["parameters"].items()},
             "cases": best["cases"],
             "set": job.fixed, "load_cases": dict(job.cases),
             "commands": run_commands(job, best["parameters"]), "environment": environment()}, indent=2) + "\n")
    text = _optimise_markdown(summary, records, signals_png is not None)
    path = folder / "report.md"
    atomic_write_text(path, text)
    return path


def run_commands(job, parameters: dict) -> dict[str, str]:
    """Per load case, the ``vphs run`` command line that simulates the design ``parameters`` as the job
    did: every override of that case (the free parameters, the job's ``set:``, the case's values; SI, full
    precision), the netlist relative to the working directory if it lies under it."""
    from blocks.optimise.evaluate import case_overrides

    spec = job.spec()
    netlist = os.path.relpath(job.netlist)
    if netlist.startswith(os.pardir):
        netlist = job.netlist
    commands = {}
    for case in spec.cases:
        overrides = case_overrides(spec, parameters, case)
        ordered = {**{k: overrides[k] for k in parameters}, **overrides}  # the free parameters first
        commands[case[0]] = " ".join(["vphs run", shlex.quote(netlist)]
                                     + [f"--set {shlex.quote(f'{k}={v!r}')}" for k, v in ordered.items()])
    return commands


def netlist_comparison(summary) -> tuple[str, bool]:
    """The netlist's own design against the best found, as one sentence, and whether it is a warning (the
    best found is not better, or the netlist's design could not be compared)."""
    job, best, start = summary.job, summary.best, summary.netlist_design
    if summary.netlist_skipped:
        return f"the netlist's own design was not evaluated: {summary.netlist_skipped}", False
    if start is None:
        return "", False
    if start["status"] != "ok":
        return f"the netlist's own design failed ({start.get('error')})", True
    if best is None:
        return f"the netlist's own design costs {_fmt(start['cost'])}; no design of the method worked", True
    if best["cost"] >= start["cost"]:
        return (f"the best design found (cost {_fmt(best['cost'])}) is NOT better than the netlist's own design "
                f"(cost {_fmt(start['cost'])}): keep the netlist's values, or give the method more evaluations "
                f"or other bounds"), True
    return (f"the netlist's own design costs {_fmt(start['cost'])}; the best found is "
            f"{_fmt(100 * (1 - best['cost'] / start['cost']), 3)} % lower" if start["cost"] > 0 else
            f"the netlist's own design costs {_fmt(start['cost'])}"), False


def warnings(summary) -> list[str]:
    """What the reader must not miss, as sentences, for the report and the console alike: the best found no
    better than the netlist's own design; working designs costlier than a failed one (the penalty too
    low); differential evolution with a budget that only samples its initial population; the best design's
    fixed step too long (checked when the report runs it again: the evaluations ran unchecked); a sweep's
    points with warnings."""
    from blocks.optimise.scipy_methods import de_generations

    job, out = summary.job, []
    comparison, warn = netlist_comparison(summary)
    if warn:
        out.append(comparison)
    if summary.above_penalty:
        out.append(f"{summary.above_penalty} working designs cost more than the penalty of a failed simulation "
                   f"({_fmt(job.penalty)}), so failures ranked as better than they; raise cost.penalty in the job")
    if summary.command == "optimise" and job.method == "differential_evolution" \
            and de_generations(job.settings, len(job.free)) == 0:
        size = job.settings.popsize * len(job.free)
        out.append(f"differential evolution only sampled: max_evaluations = {job.settings.max_evaluations} allows "
                   f"its initial population of popsize * n = {size} random designs and no generation after it, so "
                   f"the best is the best of those samples; give max_evaluations >= {2 * size} for it to evolve")
    out += [f"the best design, run again with its step checked: {line} (the evaluations ran with this step "
            f"unchecked, so their costs may be off too)" for line in summary.step_checks]
    if summary.command == "sweep":
        warned = [r for r in summary.records if r.get("warnings")]
        if warned:
            out.append(f"{len(warned)} of {len(summary.records)} points ran with warnings (the report's Warnings "
                       f"section lists them)")
    return out


def _optimise_markdown(summary, records: list[dict], have_signals: bool) -> str:
    job, best = summary.job, summary.best
    s = job.settings
    settings = {k: v for k, v in s.__dict__.items() if v is not None} if s is not None else {}
    if summary.candidates is not None:
        settings["candidates"] = summary.candidates
    ok = [r for r in records if r["status"] == "ok"]
    lines = [f"# Optimisation: {job.name}", "",
             f"- job: `{job.file}`; netlist: `{job.netlist}`",
             f"- method: {job.method} ({', '.join(f'{k}={_fmt(v)}' for k, v in settings.items())}); seed {job.seed}",
             f"- evaluations: {len(records)} on the method's path{repeats_note(summary.path_repeats)}, "
             f"{len(records) - len(ok)} failed; "
             f"iterations: {summary.iterations}; stopped: {summary.reason}"
             + (f"; {len(summary.discarded)} more were evaluated ahead in parallel and discarded (not on the path, "
                f"not in this report; marked discarded in the log)" if summary.discarded else ""),
             f"- run: {summary.executor} executor, {summary.workers} worker(s); {summary.evaluated} evaluations "
             f"simulated in this run, {summary.repeated} repeats answered from the record, {summary.replayed} "
             f"from the log; {summary.seconds:.2f} s, {summary.rate:.1f} simulated evaluations/s in this run",
             f"- cost: {' + '.join(f'{_fmt(t.weight)}*{t.name}' for t in job.terms)} per load case, "
             f"combined by {job.combine} over {', '.join(c for c, _ in job.cases)}; failed simulation = {_fmt(job.penalty)}",
             f"- {environment_line()}", ""]
    for warning in warnings(summary):
        lines += [f"**Warning:** {warning[0].upper()}{warning[1:]}.", ""]
    comparison, warn = netlist_comparison(summary)
    if comparison and not warn:
        lines += [f"{comparison[0].upper()}{comparison[1:]}.", ""]
    if best is None:
        lines += ["**No evaluation succeeded.** The errors:", ""]
        lines += [f"- {e}" for e in _distinct_errors(records)] + [""]
        return "\n".join(lines)
    number = on_path_number(records, best)
    log = f" (in the log: {best['index']})" if best["index"] != number else ""
    lines += [f"## Best design: evaluation {number} of the path{log}, cost {_fmt(best['cost'])}", "",
              "| parameter | best | min | max | scale | netlist value |", "|---|---|---|---|---|---|"]
    for p in job.free:
        lines.append(f"| {p.name} | {_param(job, p.name, best['parameters'][p.name])} | {_param(job, p.name, p.lower)} | "
                     f"{_param(job, p.name, p.upper)} | {'log' if p.log else 'linear'} | "
                     f"{_param(job, p.name, job.start_values.get(p.name, float('nan')))} |")
    lines += ["", "| load case | " + " | ".join(f"{t.name} [{t.value_unit}]" for t in job.terms) + " | cost |",
              "|---|" + "---|" * (len(job.terms) + 1)]
    for case, values in best["cases"].items():
        lines.append(f"| {case} | " + " | ".join(_fmt(values["terms"].get(t.name)) for t in job.terms)
                     + f" | {_fmt(values['cost'])} |")
    lines += ["", "Weights: " + ", ".join(f"{t.name} {_fmt(t.weight)}" for t in job.terms), ""]
    if best.get("warnings"):
        lines += ["Warnings of the best run: " + "; ".join(best["warnings"]), ""]
    lines += ["To simulate the best design again, per load case (from the folder the job ran in; values in SI: "
              "the free parameters, the job's `set:` and the load case's values):", "", "```"]
    for case, command in run_commands(job, best["parameters"]).items():
        lines += [f"# {case}", command]
    lines += ["```", ""]
    lines += ["## Cost history", "", "![convergence](convergence.png)", "",
              "Each improvement of the best cost:", "",
              "| evaluation | step | cost | " + " | ".join(_column(job, p.name) for p in job.free) + " |",
              "|---|---|---|" + "---|" * len(job.free)]
    running = math.inf
    for number, r in enumerate(records):
        if r["status"] == "ok" and r["cost"] < running:
            running = r["cost"]
            lines.append(f"| {number} | {r.get('step', '')} | {_fmt(r['cost'])} | "
                         + " | ".join(_fmt(_value(job, p.name, r["parameters"][p.name])) for p in job.free) + " |")
    lines.append("")
    if have_signals:
        lines += ["## Best run", "", "![signals](best_signals.png)", ""]
    failed = [r for r in records if r["status"] != "ok"]
    if failed:
        lines += [f"## Failed evaluations ({len(failed)})", ""] + [f"- {e}" for e in _distinct_errors(records)] + [""]
    return "\n".join(lines)


def repeats_note(repeats: int, budget: bool = True) -> str:
    """How many evaluations were repeats (:mod:`blocks.optimise.repeats`), as a parenthesis ("" if none);
    ``budget``: say that they count against max_evaluations (not for a sweep, which has no budget)."""
    if not repeats:
        return ""
    return (f" (of which {repeats} repeats of a design already evaluated, answered from its record, not simulated "
            f"again" + ("; they count against max_evaluations)" if budget else ")"))


def _distinct_errors(records: list[dict], limit: int = 8) -> list[str]:
    """Each distinct error once, at the first evaluation that gave it, numbered by its place in ``records``
    (the method's path, or the sweep's points, in order) as the rest of the report numbers them."""
    seen: dict[str, int] = {}
    for number, r in enumerate(records):
        if r["status"] != "ok":
            seen.setdefault(str(r.get("error")), number)
    return [f"evaluation {i}: {e}" for e, i in list(seen.items())[:limit]]


def _convergence_plot(records: list[dict], path: Path, title: str) -> None:
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 4.2))
    idx = np.arange(len(records))  # the number on the method's path (on_path_number), not the log's index
    cost = np.array([r["cost"] for r in records], float)
    ok = np.array([r["status"] == "ok" for r in records])
    if ok.any():
        ax.plot(idx[ok], cost[ok], ".", ms=3, color="0.6", label="each evaluation")
        best = np.minimum.accumulate(np.where(ok, cost, np.inf))
        ax.step(idx[np.isfinite(best)], best[np.isfinite(best)], where="post", color="C0", label="best so far")
        positive = cost[ok] > 0
        if positive.all() and cost[ok].max() > 100 * cost[ok].min():
            ax.set_yscale("log")
    if (~ok).any():
        top = cost[ok].max() if ok.any() else 1.0
        ax.plot(idx[~ok], np.full((~ok).sum(), top), "x", color="C3", label="failed (penalty, drawn at the top)")
    ax.set_xlabel("evaluation")
    ax.set_ylabel("cost")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    ax.set_title(title)
    fig.tight_layout()
    atomic_write_figure(fig, path)
    plt.close(fig)


def _resimulate(job, parameters: dict) -> dict:
    """The best design's runs, per load case (None for a case that fails now, or for every case when a file
    of the netlist has changed since the job read it)."""
    from blocks.errors import VphsError
    from blocks.optimise.evaluate import case_overrides, circuit_for

    spec = job.spec()
    try:
        circuit = circuit_for(job.netlist, spec.sources)
    except VphsError:
        return {case[0]: None for case in spec.cases}
    out = {}
    for case in spec.cases:
        try:
            out[case[0]] = circuit.simulate(case_overrides(spec, parameters, case))
        except VphsError:
            out[case[0]] = None
    return out


def error_label(term) -> str:
    """What a max_abs term plots: its signal minus its reference (a logged signal or a constant in the
    term's unit), or the signal alone when it has no reference (not "pA - 0")."""
    if term.reference is not None:
        return f"{term.signal} - {term.reference}"
    if term.offset != 0.0:
        return f"{term.signal} - {_fmt(term.offset / term.scale)} {term.unit}".rstrip()
    return term.signal


def _signals_plot(job, results: dict, path: Path, title: str) -> None:
    from blocks.optimise.costs import term_signal

    plt = _plt()
    terms = job.terms
    fig, axes = plt.subplots(len(terms), 1, sharex=True, figsize=(9, 2.0 + 2.0 * len(terms)), squeeze=False)
    for ax, term in zip(axes[:, 0], terms):
        for k, (case, result) in enumerate(results.items()):
            if result is None:
                continue
            colour = f"C{k % 10}"
            label = f" ({case})" if len(results) > 1 else ""
            t = result.t
            if term.kind == "hp_ise":
                ax.plot(t, term_signal(term, t, result), color=colour, lw=0.8,
                        label=f"{term.signal} high-passed{label}")
            elif term.kind == "max_abs":
                error = term_signal(term, t, result)
                ax.plot(t, error, color=colour, lw=0.9, label=f"{error_label(term)}{label}")
                k_max = int(np.argmax(np.abs(error)))
                ax.plot(t[k_max], error[k_max], "o", color=colour, label=f"max |error| {_fmt(abs(error[k_max]), 4)}")
            else:
                ax.plot(t, np.asarray(result[term.signal]) / term.scale, color=colour, label=f"{term.signal}{label}")
                if term.reference is not None:
                    ax.plot(t, np.asarray(result[term.reference]) / term.scale, "--", color=colour, lw=0.9,
                            label=f"{term.reference}{label}")
                elif term.offset != 0.0:
                    ax.axhline(term.offset / term.scale, ls="--", color=colour, lw=0.9)
        ax.set_ylabel(f"{term.name} [{term.unit or '1'}]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="x-small")
    axes[-1, 0].set_xlabel("t [s]")
    fig.suptitle(title)
    fig.tight_layout()
    atomic_write_figure(fig, path)
    plt.close(fig)


# ---- sweep ------------------------------------------------------------------------------------------------
def write_sweep_report(summary) -> Path:
    job, folder = summary.job, Path(summary.folder)
    records = sorted(summary.records, key=lambda r: r["index"])
    names = job.sweep_names
    cases = [c for c, _ in job.cases]
    header = [_column(job, n) for n in names]
    header += [f"{c}.{t.name} [{t.value_unit}]" if len(cases) > 1 else f"{t.name} [{t.value_unit}]"
               for c in cases for t in job.terms]
    header += ["cost", "status", "error", "warnings"]  # the last two: text, in sweep.csv only
    rows = []
    for r in records:
        row = [_value(job, n, r["parameters"][n]) for n in names]
        for c in cases:
            terms = r["cases"].get(c, {}).get("terms", {})
            row += [terms.get(t.name) for t in job.terms]
        row += [r["cost"] if r["status"] == "ok" else None, r["status"], r.get("error") or "",
                "; ".join(r.get("warnings") or [])]  # a point that broke a limit says so in the CSV alone too
        rows.append(row)
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    for row in rows:
        writer.writerow(["" if v is None else (f"{v:.10g}" if isinstance(v, float) else v) for v in row])
    atomic_write_text(folder / "sweep.csv", buffer.getvalue())
    _sweep_plot(job, records, folder / "sweep.png")
    ok = [r for r in records if r["status"] == "ok"]
    lines = [f"# Sweep: {job.name}", "", f"- job: `{job.file}`; netlist: `{job.netlist}`",
             f"- {len(records)} points over {', '.join(names)} ({job.sweep_combine})"
             f"{repeats_note(summary.path_repeats, budget=False)}; "
             f"{len(records) - len(ok)} failed; {summary.seconds:.2f} s, {summary.rate:.1f} simulated evaluations/s "
             f"({summary.executor}, {summary.workers} worker(s))",
             f"- cost: {' + '.join(f'{_fmt(t.weight)}*{t.name}' for t in job.terms)} per load case, combined by "
             f"{job.combine} over {', '.join(cases)}", f"- {environment_line()}", ""]
    if ok:
        best = min(ok, key=lambda r: r["cost"])
        lines += [f"Lowest cost {_fmt(best['cost'])} at " + ", ".join(f"{n} = {_param(job, n, best['parameters'][n])}" for n in names)
                  + f" (evaluation {best['index']}).", ""]
    lines += ["![sweep](sweep.png)", "", "| " + " | ".join(header[:-2]) + " |", "|" + "---|" * (len(header) - 2)]
    for row in rows:  # errors and warnings: in their sections below
        lines.append("| " + " | ".join(_fmt(v) for v in row[:-2]) + " |")
    lines.append("")
    failed = [r for r in records if r["status"] != "ok"]
    if failed:
        lines += [f"## Failed points ({len(failed)})", ""] + [f"- {e}" for e in _distinct_errors(records)] + [""]
    lines += _sweep_warnings(job, records)
    path = folder / "report.md"
    atomic_write_text(path, "\n".join(lines))
    return path


def _sweep_warnings(job, records: list[dict], shown_at_most: int = 50) -> list[str]:
    """The report's section listing the points that ran with warnings (a fixed step too long, a cavity), each
    with its values; [] if none did."""
    warned = [r for r in records if r.get("warnings")]
    if not warned:
        return []
    lines = [f"## Warnings ({len(warned)} {'point' if len(warned) == 1 else 'points'})", ""]
    for r in warned[:shown_at_most]:
        where = ", ".join(f"{n} = {_param(job, n, r['parameters'][n])}" for n in job.sweep_names)
        lines.append(f"- evaluation {r['index']} ({where}): " + "; ".join(r["warnings"]))
    if len(warned) > shown_at_most:
        lines.append(f"- and {len(warned) - shown_at_most} more points (their records in evaluations.jsonl)")
    return lines + [""]


def _sweep_plot(job, records: list[dict], path: Path) -> None:
    plt = _plt()
    names = job.sweep_names
    ok = [r for r in records if r["status"] == "ok"]
    columns = [("cost", None)] + [(t.name, t) for t in job.terms]
    cases = [c for c, _ in job.cases]
    grid2 = len(names) == 2 and len(records) == len({r["parameters"][names[0]] for r in records}) * \
        len({r["parameters"][names[1]] for r in records})
    if grid2 and ok:  # a map over the grid, one cell per point (axes by position: values may be uneven)
        from matplotlib.colors import LogNorm

        xs = sorted({r["parameters"][names[0]] for r in records})
        ys = sorted({r["parameters"][names[1]] for r in records})
        fig, axes = plt.subplots(1, len(columns), figsize=(4.2 * len(columns), 3.8), squeeze=False)
        for ax, (label, term) in zip(axes[0], columns):
            Z = np.full((len(ys), len(xs)), np.nan)
            for r in ok:
                i, j = ys.index(r["parameters"][names[1]]), xs.index(r["parameters"][names[0]])
                Z[i, j] = r["cost"] if term is None else _combined_term(r, term.name, cases, job.combine)
            finite = Z[np.isfinite(Z)]
            log = finite.size and finite.min() > 0 and finite.max() > 100 * finite.min()
            mesh = ax.imshow(Z, origin="lower", aspect="auto", norm=LogNorm() if log else None)
            fig.colorbar(mesh, ax=ax, label="cost" if term is None else f"{term.name} [{term.value_unit}]")
            ax.set_xticks(range(len(xs)), [_fmt(_value(job, names[0], v), 3) for v in xs], fontsize="small")
            ax.set_yticks(range(len(ys)), [_fmt(_value(job, names[1], v), 3) for v in ys], fontsize="small")
            ax.set_xlabel(_column(job, names[0]))
            ax.set_ylabel(_column(job, names[1]))
            ax.set_title(label + (f" ({_COMBINED[job.combine]} over the load cases)" if term is not None
                                  and len(cases) > 1 else ""), fontsize="small")
    else:
        fig, axes = plt.subplots(len(columns), 1, sharex=True, figsize=(8, 1.8 + 1.9 * len(columns)), squeeze=False)
        x_name = names[0]
        for ax, (label, term) in zip(axes[:, 0], columns):
            if len(names) == 1:
                x = [_value(job, x_name, r["parameters"][x_name]) for r in ok]
            else:
                x = [r["index"] for r in ok]
            if term is None:
                ax.plot(x, [r["cost"] for r in ok], "o-", ms=3)
            else:
                for k, case in enumerate(cases):
                    ax.plot(x, [r["cases"][case]["terms"].get(term.name) for r in ok], "o-", ms=3,
                            color=f"C{k % 10}", label=case if len(cases) > 1 else None)
                if len(cases) > 1:
                    ax.legend(fontsize="x-small")
            ax.set_ylabel(label if term is None else f"{label} [{term.value_unit}]")
            ax.grid(True, alpha=0.3)
        axes[-1, 0].set_xlabel(_column(job, x_name) if len(names) == 1 else
                               f"point ({', '.join(names)} in the table)")
    fig.suptitle(f"sweep: {job.name}")
    fig.tight_layout()
    atomic_write_figure(fig, path)
    plt.close(fig)


_COMBINED = {"sum": "summed", "mean": "mean", "worst": "worst"}


def _combined_term(record: dict, term: str, cases: list[str], how: str) -> float:
    """A cost term over the load cases, combined as the job combines its cost (sum, mean or worst)."""
    values = [record["cases"][c]["terms"].get(term) for c in cases]
    return combine(values, how) if None not in values else float("nan")
