"""The calibration report: ``report.md`` (for people), ``report.json`` (the same numbers for programs),
``residuals.png`` (residuals against the variable the found effect depends on, before and after) and
``fit.png`` (the declared and final models against the data, each output's misfit beneath), all written
atomically into the output folder beside the screening and augmented netlists. Every path in ``report.json`` (the experiment, netlist and data
files, the calibrated, round, exchange and elimination netlists) is absolute, whatever folder the run was
started from and however the files were named on its command line.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from blocks.calibrate.candidates.sensor_offset import shown as shown_offset
from blocks.calibrate.fit import ran_rows
from blocks.calibrate.outliers import largest
from blocks.calibrate.selection import LINEARISED, several_minima
from blocks.calibrate.verdict import final_effects
from blocks.provenance import environment, environment_line
from blocks.result import atomic_write_figure, atomic_write_text
from blocks.units import UnitError, display_factor


def _factor(unit: str) -> float:
    try:
        return display_factor(unit)
    except UnitError:
        return 1.0


def _path(path) -> str | None:
    """A path as report.json gives it: absolute (None stays None)."""
    return None if path is None else str(Path(path).resolve())


def _bic(value) -> str:
    """A BIC as the report prints it: two decimals, the same for every fit (BIC is compared by differences, so
    '151.19' beside '89.10', not beside '89.0987')."""
    return "-" if value is None or not np.isfinite(value) else f"{value:.2f}"


def _changed(cal) -> bool:
    """Whether the final model differs from the declared one: an effect was accepted and not removed again by
    the elimination check."""
    removed = {t.key for t in cal.removals if t.removed}
    return any(place.key not in removed for place, _ in final_effects(cal))


def _g(value, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "-"
    return f"{value:.{digits}g}"


def _in_unit(cal, key: str, value, se, unit: str):
    """(value, SE, unit) of the effect ``key`` as the markdown shows them: a sensor offset in its channel's
    unit (blocks.calibrate.candidates.sensor_offset.shown), the rest in SI; the JSON keeps SI."""
    factor, shown = shown_offset(cal.exp, key, 1.0, unit)
    return (None if value is None else value * factor), (None if se is None else se * factor), shown


def _unit(shown: str, si: str) -> str:
    """' bar' after a value in a table without a unit column (its values in SI), where it was converted."""
    return f" {shown}" if shown != si else ""


def channel_table(cal) -> list[dict]:
    first, final = cal.initial, cal.final
    rows = []
    for ch in cal.exp.channels:
        f = _factor(ch.unit)
        row = {"channel": ch.name, "role": ch.role, "unit": ch.unit, "noise": cal.data.sigma[ch.name] / f,
               "noise_source": cal.data.noise_notes[ch.name]}
        for tag, stage in (("before", first), ("after", final)):
            cs = next((c for c in stage.lof.channels if c.name == ch.name), None) if stage else None
            row[f"rmse_{tag}"] = cs.rmse / f if cs else None
            row[f"chi2nu_{tag}"] = cs.reduced if cs else None
            if cs and cs.ljung_box_p is not None:
                row[f"ljung_box_p_{tag}"] = cs.ljung_box_p
                row[f"xcorr_{tag}"] = cs.xcorr_max
            if cs and cs.structure is not None:
                row[f"structure_{tag}"] = {"chi2": cs.structure, "dof": cs.structure_dof, "p_value": cs.structure_p}
            ho = stage.heldout if stage else None
            row[f"heldout_rmse_{tag}"] = (ho.rmse.get(ch.name) / f) if ho and ch.name in ho.rmse else None
            row[f"heldout_chi2n_{tag}"] = ho.chi2n.get(ch.name) if ho else None
        rows.append(row)
    return rows


def parameter_table(cal) -> list[dict]:
    first, final = cal.initial, cal.final
    rows = []
    for k, g in enumerate(final.model.layout.globals):
        f = _factor(g.unit)
        row = {"name": g.name, "kind": g.kind, "unit": g.unit or "SI", "final": final.fit.x[k] / f,
               "final_se": final.fit.se[k] / f}
        try:
            j = first.model.layout.index(g.name)
            row.update({"start": first.model.layout.globals[j].initial / f, "declared_fit": first.fit.x[j] / f,
                        "declared_se": first.fit.se[j] / f})
        except KeyError:
            row.update({"start": None, "declared_fit": None, "declared_se": None})
        rows.append(row)
    return rows


def drift_table(cal) -> dict:
    out = {}
    for tag, stage in (("before", cal.initial), ("after", cal.final)):
        for name, d in (stage.lof.drift if stage else {}).items():
            unit = next((g.unit for g in stage.model.layout.globals if g.name == name), "")
            f = _factor(unit)
            out.setdefault(name, {"unit": unit or "SI"})[tag] = {
                "groups": d["groups"], "estimates": [e / f for e in d["estimates"]], "se": [s / f for s in d["se"]],
                "at_bound": d.get("at_bound", [False] * len(d["groups"])),
                "spread": d["spread"] / f, "chi2": d.get("chi2"), "dof": d.get("dof"), "p_value": d.get("p_value")}
    return out


def screening_rows(rnd) -> list[dict]:
    rows = []
    order = {"screened": 0, "not identifiable": 1, "no effect": 2}
    for s in sorted(rnd.scores, key=lambda s: (order.get(s.status, 3), -s.T)):
        p = s.place
        rows.append({"candidate": p.candidate, "key": p.key, "where": p.where, "status": s.status,
                     "score": s.T, "p_value": s.p_value, "estimate": s.phi, "unit": p.unit,
                     "absorbed": s.absorbed, "absorbed_by": s.absorbed_by, "note": s.note})
    return rows


def refit_rows(rnd) -> list[dict]:
    return [{"key": r.score.place.key, "value": r.phi, "se": r.se, "z": r.z, "unit": r.score.place.unit,
             "dchi2": r.dchi2, "dbic": r.dbic, "plausible": r.plausible,
             "heldout_error": r.heldout.error if r.heldout else None,
             "heldout_score": r.heldout.score if r.heldout else None, "accepted": r.accepted, "reasons": r.reasons,
             "converged": r.fit.converged, "evaluations": r.fit.nfev,
             "starts": [{"start": label, "chi2": chi2} for label, chi2 in r.starts],
             "several_minima": several_minima(r), "meaning": r.score.place.meaning}
            for r in rnd.decision.refits]


def latent_traces(cal) -> list[dict]:
    """Per ``latent: trace`` input (and run, with several): its profile and the final knots (time s, value
    SI), in time order."""
    out = []
    knots = cal.final.model.trace_knots(cal.final.fit.x)
    for ch in cal.exp.inputs:
        if ch.trace is None:
            continue
        profile = ch.trace.rsplit(".", 1)[0]
        for (of_profile, run), (times, values) in knots.items():
            if of_profile == profile:
                out.append({"column": ch.name, "profile": profile, "run": run,
                            "knots": [[float(t), float(v)] for t, v in zip(times, values)]})
    return out


def build(cal) -> dict:
    exp, data = cal.exp, cal.data
    return {
        "experiment": _path(exp.file), "netlist": _path(exp.netlist),
        "data": [_path(f) for f in exp.data_files] if len(exp.data_files) > 1 else _path(exp.data),
        "kind": data.kind, "points": data.n, "groups": list(data.groups),
        "verdict": cal.verdict, "unexplained_discrepancy": cal.unexplained,
        "calibrated_netlist": _path(cal.calibrated) if cal.calibrated else None,
        "imposed_exactly": [{"column": column, "parameter": param} for column, param in exp.exact_columns],
        "latent_traces": latent_traces(cal),
        "effects": [{"key": k, "title": t, "where": w, "parameter": p, "value": v, "se": s, "unit": u,
                     "superseded": not abs(v) > 3.0 * s} for k, t, w, p, v, s, u in cal.accepted],
        "overall": {tag: ({"chi2": st.lof.chi2, "n": st.lof.n, "p": st.lof.p, "nu": st.lof.nu,
                           "chi2_nu": st.lof.reduced, "p_value": st.lof.p_value, "bic": st.fit.bic(),
                           "heldout_error": st.heldout.error if st.heldout else None,
                           "heldout_score": st.heldout.score if st.heldout else None,
                           "heldout_knots_propagated": st.heldout.knots if st.heldout else 0,
                           "heldout_scheme": st.heldout.scheme if st.heldout else None,
                           "heldout_unconverged_folds": st.heldout.unconverged if st.heldout else [],
                           "unsettled_points": st.fit.unsettled, "failed_runs": st.fit.failures[:5],
                           "lengthened_runs": {str(k + 1): t for k, t in sorted(st.model.run_end.items())},
                           "fit_evaluations": st.fit.nfev, "fit_converged": st.fit.converged,
                           "block_means_chi2": st.lof.blocks_chi2, "block_means_dof": st.lof.blocks_dof,
                           "block_means_p": st.lof.blocks_p}
                          if st else None)
                    for tag, st in (("before", cal.initial), ("after", cal.final))},
        "channels": channel_table(cal),
        "parameters": parameter_table(cal) if cal.final else [],
        "drift": drift_table(cal),
        "rounds": [{"round": r.index, "netlist": _path(r.stage.netlist), "screening_netlist": _path(r.screening_file),
                    "screening_reproduces_fit_within_sigma": r.consistency,
                    "augmented_netlist": _path(r.augmented_file) if r.augmented_file else None,
                    "notes": r.notes, "stopped": r.stopped, "screening": screening_rows(r), "refits": refit_rows(r),
                    "ambiguous": r.decision.ambiguous, "separation": r.decision.separation,
                    "choice_moves": r.decision.depends,
                    "heldout_error": r.stage.heldout.error if r.stage.heldout else None,
                    "heldout_score": r.stage.heldout.score if r.stage.heldout else None}
                   for r in cal.rounds],
        "exchanges": [{"out": ex.out_key, "round": ex.round, "in": ex.in_key, "dbic": ex.dbic, "value": ex.phi,
                       "se": ex.se, "z": ex.z, "plausible": ex.plausible, "made": ex.made, "reasons": ex.reasons,
                       "netlist": _path(ex.netlist) if ex.netlist else None} for ex in cal.exchanges],
        "removals": [{"effect": t.key, "round": t.round, "check": t.check, "z": t.z, "dbic": t.dbic,
                      "refitted": t.refitted, "removed": t.removed, "reasons": t.reasons,
                      "netlist": _path(t.netlist) if t.netlist else None} for t in cal.removals],
        "simulations": cal.simulations, "equilibria": cal.equilibria, "seconds": cal.seconds,
        "environment": environment(),
        "largest_residuals": largest(exp, data, cal.final) if cal.final else None,
        "se_scale": {tag: (float(np.sqrt(st.fit.inflation)) if st else None)
                     for tag, st in (("before", cal.initial), ("after", cal.final))},
    }


def markdown(cal, info: dict) -> str:
    exp, data = cal.exp, cal.data
    L = [f"# Calibration: {Path(exp.file).name}", ""]
    if exp.spec.description:
        L += [exp.spec.description.strip(), ""]
    L += [f"- netlist: `{exp.netlist}`", f"- data: {', '.join(f'`{f}`' for f in (exp.data_files or [exp.data]))} ({data.n} "
          + ("steady points" if data.kind == "steady" else "samples of a time series")
          + (f" in {'groups' if data.kind == 'steady' else 'runs'} {', '.join(data.groups)}"
             if len(data.groups) > 1 else "") + ")",
          (f"- imposed inputs: {', '.join(c.name for c in exp.inputs)} (errors-in-variables: the true inputs are "
           f"fitted as latent values)" if exp.inputs else "- imposed inputs: none")
          + f"; compared: {', '.join(c.name for c in exp.outputs)}"]
    for tr in info["latent_traces"]:
        of_run, suffix = ("", "") if tr["run"] is None else (f" in run {tr['run']}", f"[{tr['run']}]")
        L.append(f"- latent trace of {tr['column']}{of_run}: the recording is taken as a noisy reading of a linear "
                 f"spline through {len(tr['knots'])} knots, chosen from the recording, their times and values "
                 f"fitted (`{tr['profile']}.times[knot j]{suffix}`, `{tr['profile']}.values[knot j]{suffix}` under "
                 f"Parameters; `latent_trace.png`); knots at t = "
                 f"{', '.join(f'{t:.4g}' for t, _ in tr['knots'])} s")
    if exp.exact_columns:
        L.append("- imposed exactly, read from the data by the netlist (their noise is not accounted for): "
                 + ", ".join(f"{column} -> `{param}`" for column, param in exp.exact_columns))
    L.append("")
    L += ["## Verdict", ""] + [f"- {v}" if not v.startswith("  ") else f"  - {v.strip()}" for v in cal.verdict] + [""]
    ov = info["overall"]
    L += fit_lines(cal, ov, data.kind == "steady")
    L += ["", "| channel | unit | noise | RMSE before | chi^2/nu before | RMSE after | chi^2/nu after | "
              "held-out RMSE before | held-out chi^2/n before | held-out RMSE after | held-out chi^2/n after |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in info["channels"]:
        L.append(f"| {r['channel']} ({r['role']}) | {r['unit']} | {_g(r['noise'], 3)} | {_g(r['rmse_before'], 3)} | "
                 f"{_g(r['chi2nu_before'], 3)} | {_g(r['rmse_after'], 3)} | {_g(r['chi2nu_after'], 3)} | "
                 f"{_g(r['heldout_rmse_before'], 3)} | {_g(r['heldout_chi2n_before'], 3)} | "
                 f"{_g(r['heldout_rmse_after'], 3)} | {_g(r['heldout_chi2n_after'], 3)} |")
    L += ["", "Held-out: each fold predicted by the model refitted without it; chi^2/n is the mean squared "
              "residual over the noise (1 for a model that predicts to the noise; a prediction fits nothing, so "
              "n, not nu). The held-out error above (and in the screening rounds' refit tables) is that mean over "
              "every held-out row of the compared outputs together."]
    L.append("")
    L.append("Noise: " + "; ".join(f"{r['channel']}: {r['noise_source']}" for r in info["channels"]) + ".")
    if data.kind == "time":
        for tag in ("before", "after"):
            o = ov[tag]
            if o and o["block_means_chi2"] is not None:
                L.append(f"- {tag}: block means of the output residuals chi^2 = {_g(o['block_means_chi2'])} on "
                         f"{o['block_means_dof']} (p = {_g(o['block_means_p'], 2)}): a slow misfit shows here first")
        L += ["", "Residual whiteness and correlation with the inputs (outputs):", "",
              "| channel | Ljung-Box p before | after | max cross-correlation before | after |", "|---|---|---|---|---|"]
        for r in info["channels"]:
            if r["role"] == "output":
                L.append(f"| {r['channel']} | {_g(r.get('ljung_box_p_before'), 2)} | {_g(r.get('ljung_box_p_after'), 2)} "
                         f"| {_g(r.get('xcorr_before'), 2)} | {_g(r.get('xcorr_after'), 2)} |")
    if data.kind == "steady" and any(r.get("structure_before") or r.get("structure_after") for r in info["channels"]):
        L += ["", "Residuals against the fitted value (outputs; the score test of a cubic in the channel's fitted "
                  "value after the free parameters absorb what they can: a smooth misfit that chi^2/nu is too "
                  "coarse to show):", "", "| channel | chi^2 (dof) before | p before | chi^2 (dof) after | p after |",
              "|---|---|---|---|---|"]
        for r in info["channels"]:
            if r["role"] == "output":
                cells = []
                for tag in ("before", "after"):
                    t = r.get(f"structure_{tag}")
                    cells += [f"{_g(t['chi2'], 3)} ({t['dof']})", _g(t["p_value"], 2)] if t else ["-", "-"]
                L.append(f"| {r['channel']} | " + " | ".join(cells) + " |")
    L += conventions(info, data.kind)
    L += residual_table(info["largest_residuals"], data.kind == "time", len(data.groups) > 1, exp.spec.group)
    L += ["", "## Effects found", ""]
    if info["effects"]:
        L += ["| effect | where | parameter | value | SE | unit | in the final fit |", "|---|---|---|---|---|---|---|"]
        for e in info["effects"]:
            value, se, unit = _in_unit(cal, e["key"], e["value"], e["se"], e["unit"])
            L.append(f"| {e['title']} | {e['where']} | `{e['parameter']}` | {_g(value)} | {_g(se, 2)} | "
                     f"{unit} | {'superseded (within 3 SE of 0)' if e['superseded'] else 'over 3 SE from 0'} |")
        if any(e["key"].split("@")[0] in ("sensor_offset", "sensor_gain") for e in info["effects"]):
            L += ["", "Sensor corrections (offset, gain) act on the logged signal in post-processing, not in the "
                      "netlist; they are written to `experiment_augmented.yaml` under `corrections:`."]
    else:
        L.append("None accepted.")
    if info["calibrated_netlist"]:
        one_run = data.kind == "time" and len(data.groups) <= 1
        L += ["", f"Calibrated netlist: `{info['calibrated_netlist']}`, the final model with every fitted parameter "
                  f"at its final value" + ((" and the fitted command" if cal.exp.fits_inputs else
                                            " and the netlist's own command (no input is fitted)")
                                           + ": `vphs run` reproduces the fit (sensor corrections aside)."
                                           if one_run else
                                           ": `vphs run` simulates the calibrated model at the netlist's own "
                                           "inputs (the experiment's differ point by point or run by run).")
              + " It sets every digit of each value; its header lists them for reading, each to the digits its "
                "standard error warrants plus 2 (at least 4 significant), with the SE."]
    L += ["", "## Parameters: how they moved", "",
          "| parameter | kind | unit | start | declared fit | SE | final | SE |", "|---|---|---|---|---|---|---|---|"]
    for p in info["parameters"]:
        L.append(f"| `{p['name']}` | {p['kind']} | {p['unit']} | {_g(p['start'])} | {_g(p['declared_fit'])} | "
                 f"{_g(p['declared_se'], 2)} | {_g(p['final'])} | {_g(p['final_se'], 2)} |")
    if cal.exp.spec.drift and not info["drift"]:
        L += ["", f"Drift of {', '.join(cal.exp.spec.drift)}: not tested (it needs two groups or runs at least; "
                  f"the data have {len(cal.data.groups)})."]
    if info["drift"]:
        L += ["", "## Drift: parameters refitted per group", ""]
        for name, d in info["drift"].items():
            L.append(f"`{name}` [{d['unit']}]:")
            L.append("")
            groups = d.get("before", d.get("after"))["groups"]
            L += ["| group | " + " | ".join(groups) + " | spread | homogeneity chi^2 (dof), p |",
                  "|---" * (len(groups) + 3) + "|"]
            for tag in ("before", "after"):
                if tag in d:
                    t = d[tag]
                    cells = [f"{_g(e)} (at its bound)" if b else f"{_g(e)} +- {_g(s, 2)}"
                             for e, s, b in zip(t["estimates"], t["se"], t["at_bound"])]
                    test = (f"{_g(t['chi2'], 3)} ({t['dof']}), p = {_g(t['p_value'], 2)}" if t["chi2"] is not None
                            else "not testable (estimates on a bound)")
                    L.append(f"| {tag} | " + " | ".join(cells) + f" | {_g(t['spread'], 3)} | {test} |")
            L.append("")
    for r in info["rounds"]:
        L += [f"## Round {r['round']}: screening", "",
              f"Model: `{r['netlist']}`. Screening netlist `{r['screening_netlist']}` (every candidate at every "
              f"place, parameters at zero) " + (f"reproduces the fit within "
                                                f"{r['screening_reproduces_fit_within_sigma']:.3g} sigma" if
                                                not r["stopped"] else f"**does not reproduce the fit**: "
                                                f"{r['stopped']}; the scores below are not to be read")
              + ". Score T: the first-order drop of chi^2 after the free parameters absorb what they can "
              "(~chi^2_1 if the candidate is absent); p is its tail, halved (one-sided) for a candidate whose "
              "parameter takes one sign only (a loss, a leakage), whole for one of either sign (an offset, a gain).",
              ""]
        for note in r["notes"]:
            L.append(f"- {note}")
        L += ["", "| rank | candidate | where | status | score T | p | linear estimate | unit | absorbed | note |",
              "|---|---|---|---|---|---|---|---|---|---|"]
        rank = 0
        for s in r["screening"]:  # only screened candidates are ranked; absorbed or ineffective ones are not
            rank += s["status"] == "screened"
            shown = str(rank) if s["status"] == "screened" else "-"
            score = _g(s["score"], 4) if s["status"] == "screened" else "-"
            estimate, _, unit = _in_unit(cal, s["key"], s["estimate"], 0.0, s["unit"])
            L.append(f"| {shown} | {s['candidate']} | {s['where']} | {s['status']} | {score} | "
                     f"{_g(s['p_value'], 2) if s['status'] == 'screened' else '-'} | {_g(estimate, 3)} | "
                     f"{unit} | {100 * s['absorbed']:.1f} % | {s['note']} |")
        L += ["", "Refitted (ranked by BIC):", ""] + ([
              "| candidate | value | SE | |value|/SE | dBIC | plausible | held-out error | held-out score | accepted "
              "| why not |",
              "|---|---|---|---|---|---|---|---|---|---|"] if r["refits"] else [
              "None: the trace stopped." if r["stopped"] else "None: no candidate's score T is over 3.84 (p < 5 %)."])
        for f in r["refits"]:
            dbic = _g(f["dbic"], 4) + ("" if f["converged"] else " (refit stopped at its evaluation limit: an upper "
                                                                 "bound)")
            value, se, unit = _in_unit(cal, f["key"], f["value"], f["se"], f["unit"])
            L.append(f"| {f['key']} | {_g(value)}{_unit(unit, f['unit'])} | {_g(se, 2)} | {_g(f['z'], 3)} | {dbic} | "
                     f"{f['plausible']} | {_g(f['heldout_error'], 3)} | {_g(f['heldout_score'], 4)} | {f['accepted']} | "
                     f"{'; '.join(f['reasons'])} |")
        several = [f for f in r["refits"] if f["several_minima"]]
        if several:
            L += ["", "Refits whose starts ended at different chi^2 (several minima; the lowest counts above):"]
            L += [f"- {f['key']}: " + ", ".join(f"from {s['start']} {_g(s['chi2'], 5)}" for s in f["starts"])
                  for f in several]
        moved = [f for f in r["refits"] if f["starts"] and f["starts"][0]["start"] != LINEARISED]
        if moved:
            L += ["", "Refits started nearer the candidate's zero than its linearised estimate:"]
            L += [f"- {f['key']}: from {f['starts'][0]['start']}" for f in moved]
        if r["ambiguous"]:
            L += ["", "Ambiguous: " + ", ".join(r["ambiguous"])] + [f"- {s}" for s in r["separation"]]
            L += [f"- what the choice changes: {s}" for s in r["choice_moves"]]
        if r["augmented_netlist"]:
            L += ["", f"Augmented netlist: `{r['augmented_netlist']}`"]
        L.append("")
    if info["exchanges"]:
        L += ["## Exchange check", "",
              "Each effect accepted before the last round, swapped for an alternative that passed the fit tests in "
              "its round, the final model refitted (dBIC: the exchanged model's BIC minus the final model's):", "",
              "| taken out (round) | put in | value | SE | |value|/SE | dBIC | plausible | made | why not |",
              "|---|---|---|---|---|---|---|---|---|"]
        for ex in info["exchanges"]:
            value, se, unit = _in_unit(cal, ex["in"], ex["value"], ex["se"], "")
            L.append(f"| {ex['out']} ({ex['round']}) | {ex['in']} | {_g(value)}{_unit(unit, '')} | {_g(se, 2)} | "
                     f"{_g(ex['z'], 3)} | {_g(ex['dbic'], 4)} | {ex['plausible']} | {ex['made']} | "
                     f"{'; '.join(ex['reasons'])} |")
        L.append("")
    if info["removals"]:
        L += ["## Elimination check", "",
              "Each effect of the final model held to the tests it was accepted by, beside all the others: it stays "
              "if taking it out raises BIC by over 10 and it is over 3 SE from zero (dBIC: the model without it "
              "minus the model with it; not refitted: the Wald estimate z^2 - ln n, far above the bar). A removal "
              "is followed by another pass over the effects left.", "",
              "| pass | effect (round) | |value|/SE | dBIC without it | refitted | removed | why kept |",
              "|---|---|---|---|---|---|---|"]
        for t in info["removals"]:
            L.append(f"| {t['check']} | {t['effect']} ({t['round']}) | {_g(t['z'], 3)} | {_g(t['dbic'], 4)} | "
                     f"{t['refitted']} | {t['removed']} | {'; '.join(t['reasons'])} |")
        L.append("")
    L += ["## Plots", ""] + (["![model against data](fit.png)", "",
                              "`fit.png`: the model against the data, declared (dashed) and final (solid): "
                              + ("each compared output's reading and both models' simulated traces against t."
                                 if data.kind == "time" else
                                 f"each compared output against {exp.inputs[0].name if exp.inputs else 'the point'}"
                                 f", the readings with error bars of one noise sigma, each model's fitted values at "
                                 f"the points' fitted inputs.") + " Beneath each, its misfit, data - model, in the "
                              "output's unit (declared: open markers or dashed; final: filled or solid), over the "
                              "shaded band of one noise sigma.", ""] if cal.initial and cal.final else []) + [
          "![residuals](residuals.png)", "",
          f"Runs: {cal.simulations} simulations, {cal.equilibria} equilibrium solves; time: "
          + ", ".join(f"{k} {v:.1f} s" for k, v in cal.seconds.items()), "", environment_line(), ""]
    return "\n".join(L)


def fit_lines(cal, ov: dict, steady: bool) -> list[str]:
    """The heading and overall lines of the report's fit section: the declared model before and the augmented
    one after; when no effect was added (or every one was removed again), the model is said to be unchanged,
    and a final fit that is the declared fit itself is given once. The held-out error is said to be a mean
    chi^2 per held-out reading where it is first shown."""
    changed = _changed(cal)
    L = ["## Fit, before (declared model) and after (augmented model)" if changed else
         "## Fit of the declared model (unchanged: no effect was added)", ""]
    tags = ("before", "after") if changed or cal.final is not cal.initial else ("before",)
    said = "the mean chi^2 per held-out reading of the outputs; "  # at its first use only
    for tag in tags:
        o = ov[tag]
        if o:
            L.append(f"- {tag if len(tags) > 1 else 'fit'}: chi^2 = {_g(o['chi2'])} on nu = {o['nu']} (chi^2/nu = "
                     f"{_g(o['chi2_nu'], 3)}, p = {_g(o['p_value'], 2)}), BIC = {_bic(o['bic'])}, held-out error "
                     f"{_g(o['heldout_error'], 3)}"
                     + (f" (score {_g(o['heldout_score'], 4)}, with the uncertainty of "
                        f"{o['heldout_knots_propagated']} knot times and values of the recorded command, summed "
                        f"over the held-out blocks)"
                        if o["heldout_knots_propagated"] else "")
                     + f" ({said}{o['heldout_scheme']}"
                     + (f"; folds whose refit did not converge: {', '.join(o['heldout_unconverged_folds'])}"
                        if o["heldout_unconverged_folds"] else "") + ")"
                     + (f"; unsettled points: {o['unsettled_points']}" if steady else "")
                     + _lengthened(o['lengthened_runs'])
                     + ("" if o["fit_converged"] else f"; the fit stopped at its limit of {o['fit_evaluations']} "
                                                      f"evaluations before converging"))
            said = ""
    return L


def conventions(info: dict, kind: str) -> list[str]:
    """How the report's numbers are made: standard errors, chi^2/nu per channel, the screening's absorbed
    share, unsettled points (steady)."""
    scale = info["se_scale"]
    said = "; ".join(f"{'declared' if tag == 'before' else 'final'} fit: x {scale[tag]:.3g}"
                     + (" (not scaled: chi^2/nu <= 1)" if scale[tag] <= 1.0 else "")
                     for tag in ("before", "after") if scale.get(tag) is not None)
    L = ["", "## How to read the numbers", "",
         "- Standard errors (SE): from the fit's Jacobian of the normalised residuals, (J^T J)^-1, multiplied by "
         "chi^2/nu whenever chi^2/nu is over 1 (significant or not), so every SE is multiplied by sqrt(chi^2/nu) "
         "and a misfit never makes a parameter look better determined than the data say; below 1 they are not "
         "shrunk. chi^2/nu here is over the rows whose runs ran. " + (f"Here: {said}. " if said else "")
         + "Each refit in the screening tables, and each per-group drift estimate, is scaled by its own fit's "
         "chi^2/nu.",
         "- chi^2/nu per channel: the channel's chi^2 over its share of the degrees of freedom, chi^2_c / (n_c nu "
         "/ n): nu = n - p (residual rows less fitted parameters, the latent inputs' included) shared out in "
         "proportion to each channel's rows n_c; so the channels' shares add up to nu and each is ~1 for a model "
         "that fits to the noise. The overall chi^2/nu is chi^2 / nu.",
         "- The screening tables' 'absorbed' column: the share of the candidate's effect on the normalised "
         "residuals (its squared sensitivity, |s|^2) that the free parameters already fitted (declared, latent "
         "inputs, effects accepted earlier) can reproduce, 1 - |s_perp|^2 / |s|^2; its score T is what is left. "
         "Over 99.9 % the candidate is 'not identifiable' and the parameters that absorb it are named in its note."]
    if kind == "steady":
        L.append("- Unsettled points: steady points read at the end of a settling run (no usable equilibrium, or "
                 "steady.method: settle) whose compared signals still moved by more than steady.settle_tol times "
                 "their noise over its last 20 %, the run lengthened up to steady.t_max; they are still used, and "
                 "counted so that they are not taken for steady.")
    return L


def residual_table(info: dict | None, time: bool, groups: bool, group: str | None) -> list[str]:
    """The markdown of the final fit's largest normalised residuals (blocks.calibrate.outliers)."""
    if not info or not info["rows"]:
        return []
    n, c, k = info["residuals"], info["bound"], info["beyond_bound"]
    L = ["", "## Largest normalised residuals (final model)", "",
         f"The {len(info['rows'])} largest of the final fit's {n} residuals (outputs and imposed inputs' readings; "
         f"residual / sigma = (fitted - measured) / noise). For {n} residuals of a right model, |residual / sigma| "
         f"over {c:.3g} comes by chance in 1 % of experiments (Phi^-1(1 - 0.005/{n}): two-sided, Bonferroni over "
         f"all {n}); "
         + ("none is beyond it." if k == 0 else
            f"{k} {'is' if k == 1 else 'are'} beyond it: check {'that reading' if k == 1 else 'those readings'} "
            f"(file:line) before reading the fit, since a gross error pulls every estimate."), "",
         "| channel | data file:line | " + ("t [s] | " if time else "") + (f"{'run' if time else group or 'group'} | "
                                                                              if groups else "")
         + "measured | fitted | unit | residual / sigma |",
         "|---|---|" + ("---|" if time else "") + ("---|" if groups else "") + "---|---|---|---|"]
    for r in info["rows"]:
        L.append(f"| {r['channel']}{' (imposed)' if r['role'] == 'input' else ''} | {r['where']} | "
                 + (f"{_g(r['t'], 6)} | " if time else "") + (f"{r['group']} | " if groups else "")
                 + f"{_g(r['measured'], 6)} | {_g(r['fitted'], 6)} | {r['unit'] or '1'} | {r['z']:+.3g}"
                 + (" **beyond**" if r["beyond_bound"] else "") + " |")
    return L


def plot_residuals(cal, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    first, final = cal.initial, cal.final
    names = [c.name for c in first.model.channels]  # outputs, then the imposed inputs: chi^2 counts both
    outputs = [c for c in cal.exp.outputs] + [c for c in cal.exp.inputs if c.name in names and np.sum(
        first.model.row_channel == names.index(c.name)) == cal.data.n]
    against = "t" if cal.data.kind == "time" else (cal.exp.inputs[0].name if cal.exp.inputs else None)
    if cal.accepted:
        key = cal.accepted[0][0]
        for rnd in cal.rounds:
            acc = rnd.decision.accepted
            if acc is not None and acc.score.place.key == key:
                against = acc.score.place.plot_against
    fig, axes = plt.subplots(len(outputs), 2, figsize=(11, 2.4 + 2.2 * len(outputs)), squeeze=False, sharex="col")
    for col, (tag, stage) in enumerate((("before (declared model)", first), ("after", final))):
        for row, ch in enumerate(outputs):
            ax = axes[row, col]
            ci = [c.name for c in stage.model.channels].index(ch.name)
            sel = stage.model.row_channel == ci
            r = stage.fit.r[sel]
            x, xlabel = _axis(cal, against)
            if cal.data.kind == "steady" or len(cal.data.groups) > 1:  # by group (steady points, or runs)
                marker, size = ("o", 4) if cal.data.kind == "steady" else (".", 1.5)
                for label, idx in cal.data.groups.items():
                    ax.plot(x[idx], r[idx], marker, ms=size, label=f"{label}")
                if row == 0 and len(cal.data.groups) > 1:
                    ax.legend(fontsize="x-small", title=cal.exp.spec.group, title_fontsize="x-small",
                              markerscale=1 if cal.data.kind == "steady" else 4)
            else:
                ax.plot(x, r, ".", ms=1.5)
            ax.axhline(0, color="k", lw=0.6)
            for level in (-2, 2):
                ax.axhline(level, color="grey", lw=0.5, ls="--")
            ax.set_ylabel(f"{ch.name}{' (imposed)' if ch.role == 'input' else ''}: residual / sigma", fontsize="small")
            if row == 0:
                ax.set_title(f"{tag}: chi^2/nu = {stage.lof.reduced:.3g}", fontsize="small")
            if row == len(outputs) - 1:
                ax.set_xlabel(xlabel)
            ax.grid(True, alpha=0.3)
    import textwrap

    found = "; ".join(f"{t} {w}" for _, t, w, *_ in cal.accepted) or "no effect accepted"
    fig.suptitle(textwrap.fill(f"{Path(cal.exp.file).name}: normalised residuals. Found: {found}", 120),
                 fontsize="medium")
    fig.tight_layout()
    atomic_write_figure(fig, path)
    plt.close(fig)


FIT_RUNS = 4  # runs of a time series drawn in fit.png (one column each), the first ones


def _fitted(stage, name: str) -> np.ndarray:
    """A channel's fitted values at every point or sample (SI): the reading plus the residual times the noise,
    what the stage's model predicts of the reading (sensor corrections in); NaN where its run failed."""
    model, res = stage.model, stage.fit
    ci = [c.name for c in model.channels].index(name)
    sel = np.nonzero(model.row_channel == ci)[0]
    r = res.r[sel]
    out = model.measured[sel] + r * model.row_sigma[sel]
    return np.where(ran_rows(r), out, np.nan)


def plot_fit(cal, path: Path) -> None:
    """The model against the data, declared and final, from the fits' own values (no new simulation). Steady
    points: each compared output against the first imposed input, the readings with error bars of one noise
    sigma (both ways), each model's fitted values at the points' fitted (latent) inputs joined in order of
    them, a colour per group. A time series: each compared output's reading and both models' traces against
    t, a column per run (the first FIT_RUNS). Beneath each output's panel, on its x axis, its misfit
    (:func:`_misfit`): a panel scaled to the data's range hides one of 0.3 bar on a 50 bar signal."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    exp, data = cal.exp, cal.data
    stages = (("declared", cal.initial, "--"), ("final", cal.final, "-"))
    outputs = list(exp.outputs)
    heights = {"height_ratios": [2.0, 1.0] * len(outputs)}
    if data.kind == "time":
        runs = list(data.groups.items())[:FIT_RUNS]
        fig, axes = plt.subplots(2 * len(outputs), len(runs), figsize=(4.0 + 3.5 * len(runs), 1.2 + 3.6 * len(outputs)),
                                 squeeze=False, sharex="col", gridspec_kw=heights)
        for row, ch in enumerate(outputs):
            f = _factor(ch.unit)
            fitted = {tag: _fitted(stage, ch.name) / f for tag, stage, _ in stages}
            for col, (label, idx) in enumerate(runs):
                ax = axes[2 * row, col]
                t = data.t[idx]
                ax.plot(t, data.measured[ch.name][idx] / f, ".", ms=2, color="grey", label="measured")
                for tag, stage, style in stages:
                    ax.plot(t, fitted[tag][idx], style, lw=1.0, color="C1" if tag == "declared" else "C0",
                            label=f"{tag} model (chi^2/nu = {stage.lof.reduced:.3g})")
                if row == 0 and len(data.groups) > 1:
                    ax.set_title(f"run {label}", fontsize="small")
                _misfit(axes[2 * row + 1, col], t, data.measured[ch.name][idx] / f,
                        {tag: fitted[tag][idx] for tag in fitted}, _per_point(data.sigma[ch.name], idx) / f,
                        stages, None, legend=col == 0)
                if col == 0:
                    ax.set_ylabel(f"{ch.name} [{ch.unit or '1'}]")
                    axes[2 * row + 1, col].set_ylabel(f"{ch.name}: data - model [{ch.unit or '1'}]")
                ax.grid(True, alpha=0.3)
        for ax in axes[-1]:
            ax.set_xlabel("t [s]")
        axes[0, 0].legend(fontsize="x-small")
        shown = f" (the first {len(runs)} of {len(data.groups)} runs)" if len(data.groups) > len(runs) else ""
        title = f"{Path(exp.file).name}: measured and simulated{shown}"
    else:
        source = exp.inputs[0] if exp.inputs else None
        fig, axes = plt.subplots(2 * len(outputs), 1, figsize=(9, 1.2 + 4.5 * len(outputs)), squeeze=False,
                                 sharex="col", gridspec_kw=heights)
        groups = list(data.groups.items())
        colored = [(f"C{k % 10}" if len(groups) > 1 else "C0", idx) for k, (_, idx) in enumerate(groups)]
        for row, ch in enumerate(outputs):
            ax = axes[2 * row, 0]
            f = _factor(ch.unit)
            if source is not None:
                fx = _factor(source.unit)
                x, xerr = data.measured[source.name] / fx, data.sigma[source.name] / fx
                at = {tag: _fitted(stage, source.name) / fx for tag, stage, _ in stages}
            else:  # nothing imposed: the points in their order
                x, xerr = np.arange(data.n, dtype=float), None
                at = {tag: x for tag, _, _ in stages}
            y = {tag: _fitted(stage, ch.name) / f for tag, stage, _ in stages}
            for (label, _), (color, idx) in zip(groups, colored):
                ax.errorbar(x[idx], data.measured[ch.name][idx] / f, yerr=data.sigma[ch.name] / f, xerr=xerr, fmt="o",
                            ms=3, color=color, elinewidth=0.8, capsize=1.5,
                            label=f"{exp.spec.group or 'group'} {label}" if len(groups) > 1 else "measured (+- sigma)")
                for tag, stage, style in stages:
                    order = idx[np.argsort(at[tag][idx], kind="stable")]
                    ax.plot(at[tag][order], y[tag][order], style, marker="." if tag == "final" else None, ms=3,
                            lw=1.0, color=color, alpha=1.0 if tag == "final" else 0.6)
            _misfit(axes[2 * row + 1, 0], x, data.measured[ch.name] / f, y,
                    _per_point(data.sigma[ch.name], np.arange(data.n)) / f, stages, colored)
            ax.set_ylabel(f"{ch.name} [{ch.unit or '1'}]")
            axes[2 * row + 1, 0].set_ylabel(f"{ch.name}: data - model [{ch.unit or '1'}]")
            ax.grid(True, alpha=0.3)
        axes[-1, 0].set_xlabel(f"{source.name} [{source.unit or '1'}] (measured; models at their fitted values)"
                               if source is not None else "point")
        from matplotlib.lines import Line2D

        handles = axes[0, 0].get_legend_handles_labels()[0] + [
            Line2D([], [], ls=style, color="k", marker="." if tag == "final" else None, ms=3, lw=1.0,
                   label=f"{tag} model")
            for tag, _, style in stages]
        axes[0, 0].legend(handles=handles, fontsize="x-small", ncol=1 if len(groups) == 1 else 2)
        title = (f"{Path(exp.file).name}: measured and fitted, declared model (dashed, chi^2/nu = "
                 f"{cal.initial.lof.reduced:.3g}) and final (solid, {cal.final.lof.reduced:.3g})")
    import textwrap

    fig.suptitle(textwrap.fill(title, 110), fontsize="medium")
    fig.tight_layout()
    atomic_write_figure(fig, path)
    plt.close(fig)


def _per_point(sigma, idx) -> np.ndarray:
    """A channel's noise sigma at the points ``idx``: one value for all, or each point's."""
    sigma = np.asarray(sigma, dtype=float)
    return np.broadcast_to(sigma, np.shape(idx)) if sigma.ndim == 0 else sigma[idx]


def _misfit(ax, x, measured, fitted: dict, sigma, stages, groups, legend: bool = True) -> None:
    """A panel of the misfit, data - model, in the channel's unit against ``x``: the declared model's (open
    markers, or dashed) and the final one's (filled, or solid), each point's own (no line joins steady points:
    ``groups``, [(colour, indices)], colours them by group; None: a trace against t, joined), over the shaded
    band of one noise sigma (a model that fits leaves its residuals mostly inside it) and the zero line."""
    order = np.argsort(x, kind="stable")
    ax.fill_between(x[order], -sigma[order], sigma[order], color="grey", alpha=0.2, lw=0, label="+- noise sigma")
    ax.axhline(0.0, color="k", lw=0.6)
    for tag, _, style in stages:
        misfit = measured - fitted[tag]
        if groups is None:
            ax.plot(x, misfit, style, lw=1.0, color="C1" if tag == "declared" else "C0", label=f"{tag} model")
            continue
        for k, (color, idx) in enumerate(groups):
            ax.plot(x[idx], misfit[idx], "o" if tag == "declared" else ".", ms=3, ls="none", color=color,
                    mfc="none" if tag == "declared" else color, alpha=0.6 if tag == "declared" else 1.0,
                    label=None if k else f"{tag} model")
    ax.grid(True, alpha=0.3)
    if legend:
        ax.legend(fontsize="xx-small", ncol=3)


def _axis(cal, against: str | None) -> tuple[np.ndarray, str]:
    """The x values and label of a residual plot drawn against ``against`` (a Place's plot_against): t (or
    the point number), a measured channel, or the difference "a - b" of two (a pressure drop), in the first
    channel's display unit."""
    channels = {c.name: c for c in cal.exp.channels}
    parts = against.split(" - ") if against else []
    if not parts or not all(p in channels for p in parts):
        return ((cal.data.t, "t [s]") if cal.data.kind == "time" else (np.arange(cal.data.n), "point"))
    unit = channels[parts[0]].unit
    x = cal.data.measured[parts[0]] - (cal.data.measured[parts[1]] if len(parts) > 1 else 0.0)
    return x / _factor(unit), f"{against} [{unit}] (measured)"


def plot_latent_traces(cal, traces: list[dict], path: Path) -> None:
    """Per latent trace (and run): the recording, the fitted spline and its knots against t, and the
    recording's residual from the spline in its noise sigmas."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2 * len(traces), 1, figsize=(11, 5.0 * len(traces)), squeeze=False)
    for k, tr in enumerate(traces):
        ch = next(c for c in cal.exp.inputs if c.name == tr["column"])
        f = _factor(ch.unit) if ch.unit not in ("", "1") else 1.0
        knot_t, knot_u = np.array(tr["knots"]).T
        idx = np.arange(cal.data.n) if tr["run"] is None else cal.data.groups[tr["run"]]
        t, recorded = cal.data.t[idx], cal.data.measured[ch.name][idx]
        spline = np.interp(t, knot_t, knot_u)
        top, bottom = axes[2 * k, 0], axes[2 * k + 1, 0]
        top.plot(t, recorded / f, ".", ms=1.5, color="grey", label="recorded")
        top.plot(knot_t, knot_u / f, "-o", ms=3, lw=1.0, color="C3", label=f"latent spline ({len(knot_t)} knots)")
        top.set_ylabel(f"{ch.name} [{ch.unit or '1'}]")
        if tr["run"] is not None:
            top.set_title(f"run {tr['run']}", fontsize="small")
        bottom.sharex(top)
        top.legend(fontsize="small")
        bottom.plot(t, (recorded - spline) / cal.data.sigma[ch.name], ".", ms=1.5)
        for level in (-2, 2):
            bottom.axhline(level, color="grey", lw=0.5, ls="--")
        bottom.set_ylabel(f"{ch.name}: (recorded - spline) / sigma", fontsize="small")
        for ax in (top, bottom):
            ax.grid(True, alpha=0.3)
    for ax in axes[1::2, 0]:
        ax.set_xlabel("t [s]")
    fig.suptitle(f"{Path(cal.exp.file).name}: latent input traces, final fit", fontsize="medium")
    fig.tight_layout()
    atomic_write_figure(fig, path)
    plt.close(fig)


def write(cal, out: Path) -> dict[str, Path]:
    out = Path(out)
    info = build(cal)
    paths = {"json": out / "report.json", "markdown": out / "report.md", "plot": out / "residuals.png"}
    if cal.initial is not None and cal.final is not None:
        paths["fit"] = out / "fit.png"
    if info["latent_traces"]:
        paths["traces"] = out / "latent_trace.png"
    atomic_write_text(paths["json"], json.dumps(_finite(info), indent=1, default=_json_default) + "\n")
    plot_residuals(cal, paths["plot"])
    if "fit" in paths:
        plot_fit(cal, paths["fit"])
    if "traces" in paths:
        plot_latent_traces(cal, info["latent_traces"], paths["traces"])
    atomic_write_text(paths["markdown"], markdown(cal, info))
    return paths


def _finite(value):
    """NaN and infinities as null (strict JSON)."""
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    if isinstance(value, (float, np.floating)) and not np.isfinite(value):
        return None
    return value


def _json_default(value):
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    return str(value)


def _lengthened(runs: dict) -> str:
    """'; settling runs lengthened for points 3, 15 (up to 4 s)', or nothing."""
    if not runs:
        return ""
    return f"; settling runs lengthened for point{'s' if len(runs) > 1 else ''} {', '.join(runs)} " \
           f"(up to {_g(max(runs.values()), 3)} s)"
