"""Held-out error: refit without a fold, predict the fold, pool the errors over the folds.

Schemes (``heldout:`` of the experiment):
- ``leave_one_group_out`` (steady data with groups): each group in turn is left out; its points are
  predicted from their *measured* inputs (their latent inputs are not fitted: the fold's outputs must not
  inform its prediction).
- ``leave_one_experiment_out`` (steady points from several data files): each file in turn, predicted
  from its measured inputs as above.
- ``kfold_experiments`` (steady points from several data files): the files dealt into k folds at random
  (``seed``), each fold's files left out together and predicted as above; with k at least the number of
  files it is leave one experiment out.
- ``kfold``: steady points dealt into k folds at random (``seed``); a time series cut into k contiguous
  blocks of samples (the measured input stays in the fit for every sample: it is what is imposed; the
  knots of a latent trace that start inside the block start the refit from the recording alone, as a
  steady fold's latent inputs do from their readings: the fold's outputs must not have placed them).
  A time series of several runs (a grouping column, or one data file per run) is held out one run at a
  time by ``leave_one_group_out`` or ``leave_one_experiment_out``: the run's input stays in the fit, its
  latent levels start the refit from the netlist's values and its trace's knots from its recording alone
  (its outputs must not have placed them), and its outputs are predicted.
Without groups (or with one data file), the group and experiment schemes fall back to kfold (said in the
result, and by ``vphs calibrate`` as a warning: :func:`fallbacks`).

A parameter fitted per group (``per: group``: a run's initial state, a group's own setting) has, for a group
held out whole, nothing outside the group to fix it. The fold's refit leaves the group's own values out;
they are then fitted to the group's held-out outputs alone, everything else held at the refit
(:func:`fit_own_values`), and the held-out error is what remains. That prediction is conditional on those
few values (a run's start taken from its own samples); every model compared gets the same.

Each fold's refit runs to convergence: it is given ``max_nfev`` evaluations and, when it stops at that
limit, continued from where it stopped, up to ``attempts`` times in all. A fold still not converged then is
named in the result (``unconverged``): a refit cut short predicts worse than the model can, and its error
would count against the model (leave-one-group-out on the relief rig: one fold's refit of a 4-parameter
model stopped at 20 evaluations with a held-out error of 12.7 where the converged refit gives 0.72; that
refit was slow because the fit moved a leakage's start to 1e-10, which blocks/calibrate/fit.py no longer
does, but a refit can still need more than one attempt's evaluations).

The held-out error is the mean of the squared normalised residuals of the held-out output rows (1 for a
model that predicts to the noise); per output channel the same mean (chi^2/n: a prediction fits nothing, so
n, not nu) and the RMSE in SI.

The held-out score, which the acceptance test compares, is the mean predictive deviance of the held-out
rows. Where the prediction's inputs are known (steady points from their measured inputs, an imposed
command) it is the held-out error itself. Where a held-out block's latent command is known only by its
recording (the knots of a latent trace that start inside the block, placed by the recording alone), the
prediction carries the knots' uncertainty, and a model whose outputs are more sensitive to the command
(a friction near standstill) predicts worse from a noisy recording even when it is the right model. The
score then uses the linearised predictive distribution of the block's outputs, r ~ N(0, S) with

    S = I + J_k C_k J_k^T

(J_k = d r / d knots over the block's output rows; C_k the knots' covariance from the fold's refit, whose
rows are the recording and the other blocks' outputs, each knot time given a prior of the variance of a
uniform spread over its bounds, (hi - lo)^2 / 12, which bounds that of a time the recording cannot place, a
step between two samples), and is

    score = sum over folds (r^T S^-1 r + ln det S) / n

(the Gaussian log score, -2 ln p(r), up to a constant: 1 for a model that predicts to the noise, and a
proper scoring rule, so the right model wins in expectation). Parameter uncertainty is left out on
purpose: what estimating more parameters costs is what the held-out test is there to charge. Knots that start
before the block are left out too, though their uncertainty reaches its first samples through the state: the
outputs before the block helped place them, and each costs two more simulations per fold.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from blocks.calibrate.fit import FitResult, covariance, fit
from blocks.calibrate.levels import level_read
from blocks.calibrate.model import Model


@dataclass
class HeldOut:
    scheme: str
    error: float  # mean squared normalised residual over the held-out output rows
    rmse: dict  # output channel -> RMSE (SI)
    n: int
    folds: list = field(default_factory=list)  # (name, n rows, error)
    chi2n: dict = field(default_factory=dict)  # output channel -> mean squared normalised residual
    unconverged: list = field(default_factory=list)  # folds whose refit stopped at its limit
    score: float = float("nan")  # mean predictive deviance (the error itself where the inputs are known)
    knots: int = 0  # knots whose uncertainty the score propagates, summed over the folds
    whitened: float = float("nan")  # mean r^T S^-1 r: about 1 when S is the residuals' true spread

    @property
    def measure(self) -> str:
        """What the acceptance test compares: the held-out error, or the score where it differs from it."""
        return "score" if self.knots else "error"


def make_folds(model: Model, spec) -> tuple[str, list[tuple[str, np.ndarray]]]:
    return folds_of(model.data, spec)


def folds_of(data, spec) -> tuple[str, list[tuple[str, np.ndarray]]]:
    """The scheme as run (with what it fell back to, or how k was cut, in brackets) and its folds: (label,
    row indices of the data's points or samples)."""
    groups = data.groups
    if spec.scheme == "leave_one_group_out" and data.kind == "steady" and len(groups) >= 2:
        return "leave one group out", [(label, idx) for label, idx in groups.items()]
    files = list(dict.fromkeys(data.sources or []))  # in order of appearance
    if spec.scheme in ("leave_one_experiment_out", "kfold_experiments") and data.kind == "steady" \
            and len(files) >= 2:
        sources = np.array(data.sources)
        if spec.scheme == "leave_one_experiment_out" or spec.k >= len(files):
            cut = f" (k = {spec.k} cut to the {len(files)} data files)" if spec.scheme == "kfold_experiments" \
                and spec.k > len(files) else ""
            return f"leave one experiment out{cut}", [(f, np.nonzero(sources == f)[0]) for f in files]
        dealt = np.array_split(np.random.default_rng(spec.seed).permutation(len(files)), spec.k)
        folds = []
        for part in dealt:
            members = [files[i] for i in sorted(part)]
            folds.append((" + ".join(members), np.nonzero(np.isin(sources, members))[0]))
        return f"{spec.k}-fold over experiments", folds
    k = min(spec.k, data.n)
    cut = f" (k = {spec.k} cut to the {data.n} {'points' if data.kind == 'steady' else 'samples'})" if k < spec.k \
        else ""
    if data.kind == "steady":
        order = np.random.default_rng(spec.seed).permutation(data.n)
        parts = np.array_split(order, k)
        note = "" if spec.scheme == "kfold" else (
            " (no groups: leave_one_group_out fell back to kfold)" if spec.scheme == "leave_one_group_out"
            else f" (one data file: {spec.scheme} fell back to kfold)")
        return f"{k}-fold over points{note}{cut}", [(f"fold {i + 1}", np.sort(p)) for i, p in enumerate(parts)]
    if spec.scheme in ("leave_one_group_out", "leave_one_experiment_out") and len(groups) >= 2:  # runs
        return "leave one run out", [(label, idx) for label, idx in groups.items()]
    parts = np.array_split(np.arange(data.n), k)
    note = "" if spec.scheme == "kfold" else (
        " (one run: leave_one_group_out fell back to kfold)" if spec.scheme == "leave_one_group_out"
        else f" ({spec.scheme} needs steady points: it fell back to kfold)")
    return f"{k} contiguous blocks of the time series{note}{cut}", [(f"block {i + 1}", p)
                                                                    for i, p in enumerate(parts)]


def fallbacks(data, spec, grouped: bool = True) -> list[str]:
    """What the held-out test does other than the experiment asks (:func:`folds_of`), one line each: a scheme
    the data cannot run (leave one group out of one group, leave one experiment out of one file), or a k cut to
    the points, samples or files there are. ``vphs calibrate`` prints them as warnings: they change what the
    held-out test means. ``grouped``: the experiment names a grouping column."""
    scheme, _ = folds_of(data, spec)
    instead = scheme.split(" (")[0]
    steady = data.kind == "steady"
    groups, files = len(data.groups), len(dict.fromkeys(data.sources or []))
    what = "points" if steady else "samples"
    asked = getattr(spec, "model_fields_set", {"k"})
    out = []
    if spec.scheme == "leave_one_group_out" and groups < 2:
        kind = "groups" if steady else "runs"
        out.append(f"heldout: leave_one_group_out needs 2 {kind} or more, the data have 1"
                   + (" (no grouping column)" if steady and not grouped else "") + f": {instead} instead")
    elif spec.scheme in ("leave_one_experiment_out", "kfold_experiments") and steady and files < 2:
        out.append(f"heldout: {spec.scheme} needs 2 data files or more, the data have 1: {instead} instead")
    elif spec.scheme == "leave_one_experiment_out" and not steady and groups < 2:
        out.append(f"heldout: leave_one_experiment_out needs 2 runs (data files) or more, the data have 1: {instead} "
                   f"instead")
    elif spec.scheme == "kfold_experiments" and not steady:
        out.append(f"heldout: kfold_experiments needs steady points from several data files: {instead} instead")
    elif "k" in asked and spec.scheme == "kfold_experiments" and spec.k > files:
        out.append(f"heldout: k = {spec.k} is more than the {files} data files: {instead} instead")
    elif "k" in asked and spec.scheme == "kfold" and spec.k > data.n:
        out.append(f"heldout: k = {spec.k} is more than the {data.n} {what}: {instead} instead")
    return out


def read_by_its_run(model: Model, level) -> bool:
    """Whether an input sample of the level's run reads the latent command level (its run's ``<name>[run]``
    global): in a held-out refit the run's outputs are out, so a level its input samples do not read (one
    in force before them; it acts only on the state they start from) has nothing to fix it, and drifted
    (to -1872 on the drive line split at 1.7 s, which refused the right friction). Such a level is held at
    its start, the netlist's value, in the refit."""
    name = level.name.split("[", 1)[0]
    over = dict(model.exp.overrides, **model.exp.groups.get(level.run, {}))
    return level_read(model.circuit.flat.parameters, over, name, model.data.t[model.data.groups[level.run]])


def knot_in_block(model: Model, knot, idx: np.ndarray) -> bool:
    """Whether a latent trace's knot (its value's or its time's global) starts within the time span that
    the held-out samples ``idx`` cover in the knot's run (the whole series for a series of one run)."""
    if knot.run is not None:
        idx = idx[np.isin(idx, model.data.groups[knot.run])]
    if idx.size == 0:
        return False
    start = knot.initial if knot.at is None else knot.at
    return bool(model.data.t[idx[0]] <= start <= model.data.t[idx[-1]])


def heldout(model: Model, res: FitResult, spec, max_nfev: int = 20, attempts: int = 5) -> HeldOut:
    scheme, folds = make_folds(model, spec)
    outputs = model.output_rows()
    errors = np.zeros(model.n_rows)
    held_rows = np.zeros(model.n_rows, dtype=bool)
    per_fold, unconverged = [], []
    quadratic, log_det, propagated = 0.0, 0.0, 0
    for name, idx in folds:
        fold_rows = model.rows_of_points(idx)
        x0 = res.x.copy()
        active = res.active.copy()
        whole = {label for label, rows in model.data.groups.items() if np.isin(rows, idx).all()}
        own = [j for j, g in enumerate(model.layout.globals) if g.kind == "declared" and g.run in whole]
        x0[own] = [model.layout.globals[j].initial for j in own]
        fitted_own = active[own].copy()
        active[own] = False  # nothing outside the fold fixes them: fitted to the fold below
        if model.data.kind == "steady":
            train = res.rows & ~fold_rows
            for k in idx:
                for i, ch in enumerate(model.layout.inputs):
                    j = model.layout.latent_index(int(k), i)
                    active[j] = False
                    x0[j] = model.data.measured[ch][int(k)]
        else:
            train = res.rows & ~(fold_rows & outputs)
            restarted = [j for j, g in enumerate(model.layout.globals)
                         if g.kind in ("trace", "trace_time") and knot_in_block(model, g, idx)
                         or g.run in whole and g.kind != "declared"]
            x0[restarted] = [model.layout.globals[j].initial for j in restarted]
            for j in restarted:  # a level no input sample of the held-out run reads: nothing left to fix it
                g = model.layout.globals[j]
                if g.kind == "latent" and not read_by_its_run(model, g):
                    active[j] = False
        f = fit_to_convergence(model, x0, active, train, max_nfev, attempts)
        if not f.converged:
            unconverged.append(name)
        sel = fold_rows & outputs & res.rows
        own_fitted = [j for j, a in zip(own, fitted_own) if a]
        pred = fit_own_values(model, f, own_fitted, sel, max_nfev, attempts) if own_fitted else f
        r = model.residuals(pred.x, idx) if model.data.kind == "steady" else pred.r
        errors[sel] = r[sel]
        knots = [] if model.data.kind == "steady" else \
            [j for j in restarted if f.active[j] and model.layout.globals[j].kind in ("trace", "trace_time")]
        A = knot_spread(model, f, knots, sel, pred)
        fold_quadratic, fold_log_det = gaussian_deviance(r[sel], A)
        quadratic, log_det, propagated = quadratic + fold_quadratic, log_det + fold_log_det, propagated + len(knots)
        held_rows |= sel
        per_fold.append((name, int(sel.sum()), float(np.mean(r[sel] ** 2)) if sel.any() else float("nan")))
    rmse, chi2n = {}, {}
    for ci, ch in enumerate(model.channels):
        if ch.role != "output":
            continue
        sel = held_rows & (model.row_channel == ci)
        if sel.any():
            rmse[ch.name] = float(np.sqrt(np.mean((errors[sel] * model.sigma[ci]) ** 2)))
            chi2n[ch.name] = float(np.mean(errors[sel] ** 2))
    err = float(np.mean(errors[held_rows] ** 2)) if held_rows.any() else float("nan")
    n = int(held_rows.sum())
    score, whitened = ((quadratic + log_det) / n, quadratic / n) if n else (float("nan"), float("nan"))
    return HeldOut(scheme, err, rmse, n, per_fold, chi2n, unconverged, score, propagated, whitened)


def fit_own_values(model: Model, f: FitResult, own: list[int], rows: np.ndarray, max_nfev: int,
                   attempts: int) -> FitResult:
    """The held-out groups' own values of the parameters fitted per group (``per: group``; indices ``own``
    into x), fitted to the held-out output rows ``rows`` with everything else held at the fold's refit ``f``:
    a run's initial state or a group's own setting is known from nowhere else. That is a conditional
    prediction (a few values against the fold's many rows, the same for every model compared); the fold's
    refit ``f`` decides convergence, as the shared parameters are what the held-out error judges."""
    active = np.zeros(len(f.x), dtype=bool)
    active[own] = True
    return fit_to_convergence(model, f.x, active, rows, max_nfev, attempts)


def fit_to_convergence(model: Model, x0: np.ndarray, active: np.ndarray, rows: np.ndarray, max_nfev: int,
                       attempts: int) -> FitResult:
    """A fit given ``max_nfev`` evaluations, continued from where it stopped while it has not converged, up
    to ``attempts`` fits in all (the module docstring: a fold's refit cut short predicts worse than it can)."""
    f = fit(model, x0, active, rows, max_nfev=max_nfev)
    for _ in range(attempts - 1):
        if f.converged:
            break
        f = fit(model, f.x, active, rows, max_nfev=max_nfev)
    return f


def knot_covariance(model: Model, f: FitResult, knots: list[int]) -> np.ndarray:
    """The covariance of the knots ``knots`` (indices into x) after the fold's refit ``f``: (J^T J + P)^-1
    of all its fitted parameters, with P the precision of a uniform spread over each knot time's bounds,
    inflated as the fit's own covariance is (max(1, chi^2/nu), both over the rows that ran); the rows of
    ``knots``. Where a direction of the other parameters is not determined and reaches the knots (an infinite
    variance), the knots' own block, the others held, (J_k^T J_k + P_k)^-1, is used instead: finite, and
    smaller, never larger."""
    cols = np.nonzero(f.active)[0]
    lo, hi = model.bounds()
    width = hi[cols] - lo[cols]
    times = [k for k, c in enumerate(cols)
             if model.layout.globals[c].kind == "trace_time" and np.isfinite(width[k]) and width[k] > 0]
    P = np.zeros((len(times), cols.size))  # rows sqrt(12) / width: variance width^2 / 12
    P[np.arange(len(times)), times] = np.sqrt(12.0) / width[times]
    where = [int(np.nonzero(cols == j)[0][0]) for j in knots]
    J = f.J[f.ran]
    C = covariance(np.vstack([J, P]))[np.ix_(where, where)]
    if not np.all(np.isfinite(C)):
        C = covariance(np.vstack([J, P])[:, where])
    C = 0.5 * (C + C.T)
    return C * f.inflation


def knot_spread(model: Model, f: FitResult, knots: list[int], sel: np.ndarray, at: FitResult) -> np.ndarray:
    """A = J_k C_k^1/2 over the rows ``sel``, C_k from the fold's refit ``f``, J_k at the prediction ``at``
    (the refit, with the held-out groups' own values fitted: :func:`fit_own_values`) (S = I + A A^T; no
    columns without knots)."""
    if not knots:
        return np.zeros((int(sel.sum()), 0))
    w, V = np.linalg.eigh(knot_covariance(model, f, knots))
    return model.jacobian(at.x, knots, None, at.r)[sel] @ (V * np.sqrt(np.maximum(w, 0.0)))


def gaussian_deviance(r: np.ndarray, A: np.ndarray) -> tuple[float, float]:
    """(r^T S^-1 r, ln det S) for S = I + A A^T, through Woodbury in the small dimension of A's columns:
    r^T S^-1 r = r^T r - b^T M^-1 b with b = A^T r, M = I + A^T A, and det S = det M."""
    M = np.eye(A.shape[1]) + A.T @ A
    b = A.T @ r
    _sign, log_det = np.linalg.slogdet(M)
    return float(r @ r - b @ np.linalg.solve(M, b)), float(log_det)
