"""The largest normalised residuals of the final fit, each at its data file and line, and the ones beyond
what their number makes plausible.

A gross error in one reading (a typo, 23.6 bar logged for 20.6; 2.3e30 for 2.31) pulls every estimate of a
least-squares fit, and the lack-of-fit tests show it only as "unexplained discrepancy remains", as a misfit
of the model would. Its residual is what singles it out. For N residuals z_k of a model that is right, each
about N(0, 1), the chance that any |z_k| exceeds

    c = Phi^-1(1 - 0.005 / N)

is at most 1 % (Bonferroni, two-sided: N * 2 * 0.005 / N): 3.71 for 48 residuals, 4.31 for 600, 4.79 for
6000. A residual beyond c is named in the verdict with its file and line, to be checked before any effect
found is read. (A fitted residual varies a little less than its noise, the parameters absorbing part of it,
so the bound is on the safe side.) N counts every residual row that ran, the imposed inputs' readings
included (chi^2 counts them); rows whose run failed hold a penalty, not a residual, and are left out (the
verdict says so on its own).

Nothing here changes the fit: it reads the final fit's residuals, fitted value = reading + z * sigma (the
model's prediction of the reading, sensor corrections included).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy import stats as sps

from blocks.calibrate.fit import ran_rows

FAMILY_ALPHA = 0.01  # two-sided, for all the residuals together
SHOWN = 10  # rows of the report's table
NAMED = 3  # rows the verdict names


def bound(n: int) -> float:
    """|z| beyond which one of ``n`` N(0, 1) residuals is implausible at FAMILY_ALPHA for the family."""
    return float(sps.norm.isf(FAMILY_ALPHA / 2.0 / max(n, 1)))


def row_places(exp, data) -> list[tuple[str, int | None]]:
    """(data file, line in it) of each point or sample of ``data``, in the data's order (the files' rows
    joined in order; the first file's lines kept by the reader, the others' read again); (file, None) where
    the line is not known."""
    from blocks.datafile import read_table

    files = [Path(f) for f in (exp.data_files or [exp.data])]
    names = [f.name for f in files] if len({f.name for f in files}) == len(files) else [str(f) for f in files]
    out: list[tuple[str, int | None]] = []
    for k, (file, name) in enumerate(zip(files, names)):
        try:
            table = data.table if k == 0 else (read_table(file, group=exp.spec.group) if exp.spec.group
                                               else read_table(file))
        except Exception:  # read once already; if it no longer reads, the lines are not known
            table = None
        if table is None or table.lines is None:
            return [(names[0] if len(files) == 1 else "", None)] * data.n
        out += [(name, line) for line in table.lines]
    return out if len(out) == data.n else [("", None)] * data.n


def where(place: tuple[str, int | None], point: int) -> str:
    file, line = place
    return f"{file}:{line}" if line is not None else f"{file + ' ' if file else ''}row {point + 1}"


def largest(exp, data, stage, shown: int = SHOWN) -> dict:
    """The ``shown`` largest |z| of ``stage``'s fit (channel, its data file and line, measured and fitted in
    the channel's display unit, z) with the bound for their number and how many lie beyond it."""
    from blocks.units import UnitError, display_factor

    model, res = stage.model, stage.fit
    used = np.nonzero(res.rows)[0]
    used = used[ran_rows(res.r[used])]
    z = res.r[used]
    n = int(used.size)
    c = bound(n)
    order = np.argsort(-np.abs(z), kind="stable")
    places = row_places(exp, data)
    groups = len(data.groups) > 1
    rows = []
    for j in order[:shown]:
        row = int(used[j])
        ch = model.channels[int(model.row_channel[row])]
        point = int(model.row_point[row])
        try:
            f = display_factor(ch.unit)
        except UnitError:
            f = 1.0
        measured, sigma = float(model.measured[row]), float(model.row_sigma[row])
        fitted = measured + float(res.r[row]) * sigma
        if 4.0 * np.finfo(float).eps * max(abs(measured), abs(fitted)) > 1e-3 * sigma:
            fitted = None  # lost in the rounding beside a reading of 1e30 (the residual itself is exact)
        file, line = places[point]
        rows.append({"channel": ch.name, "role": ch.role, "file": file, "line": line,
                     "where": where(places[point], point),
                     "point": point, "t": float(data.t[point]) if data.kind == "time" else None,
                     "group": data.labels[point] if groups else None, "unit": ch.unit,
                     "measured": measured / f, "fitted": None if fitted is None else fitted / f, "z": float(res.r[row]),
                     "beyond_bound": bool(abs(res.r[row]) > c)})
    return {"fit": "final", "residuals": n, "family_alpha": FAMILY_ALPHA, "bound": c,
            "beyond_bound": int(np.sum(np.abs(z) > c)), "rows": rows}


def gross_residuals(cal) -> list[str]:
    """The verdict's line on the final fit's residuals beyond the bound, by file and line (none: [])."""
    return verdict_line(largest(cal.exp, cal.data, cal.final)) if cal.final is not None else []


def verdict_line(info: dict) -> list[str]:
    """The verdict's line on residuals beyond the bound (none: [])."""
    k = info["beyond_bound"]
    if k == 0:
        return []
    beyond = [r for r in info["rows"] if r["beyond_bound"]][:NAMED]
    bound_said = (f"beyond the {info['bound']:.3g} sigma that {info['residuals']} residuals make plausible "
                  f"(two-sided, 1 % for them all)")
    checks = ", ".join(dict.fromkeys(r["where"] for r in beyond))
    if k == 1:
        r = beyond[0]
        return [f"gross residual: {r['channel']} at {r['where']} is {abs(r['z']):.3g} sigma off the final fit "
                f"(measured {r['measured']:.6g}" + ("" if r["fitted"] is None else f", fitted {r['fitted']:.6g}")
                + f"{_unit(r['unit'])}), {bound_said}: the fit may be pulled "
                f"by it; check the data at {checks}; a gross error pulls every estimate"]
    named = "; ".join(f"{r['channel']} at {r['where']} ({abs(r['z']):.3g} sigma)" for r in beyond)
    more = f" and {k - len(beyond)} more (the report's table of the largest residuals)" if k > len(beyond) else ""
    many = (" (with so many, a misfit of the model is as likely as bad readings: compare with fit.png)"
            if k > NAMED else "")
    return [f"{k} gross residuals, {bound_said}: {named}{more}{many}: the fit may be pulled by them; check the data "
            f"at {checks}; a gross error pulls every estimate"]


def _unit(unit: str) -> str:
    return f" {unit}" if unit not in ("", "1", "SI") else ""
