"""Lack-of-fit statistics of a fit: per channel chi^2/nu and RMSE; for a time series the residuals'
whiteness (Ljung-Box) and their cross-correlation with the inputs; the drift of a parameter that should
be constant, refitted group by group (steady points, or the runs of a time series).

- chi^2/nu per channel: chi^2_c / (n_c * nu / n), the degrees of freedom nu = n - p shared out in
  proportion to the channel's rows (the latent inputs' rows and parameters cancel in the count);
  p-value of the whole chi^2 with nu degrees of freedom.
- Ljung-Box: Q = n (n + 2) sum_{k=1..h} rho_k^2 / N_k, h = min(20, n/5), against chi^2_h, with
  rho_k = sum e_i e_{i+k} / sum e_i^2 over the N_k pairs k samples apart *within one run* (one run:
  N_k = n - k, the textbook form; several runs: a pair never straddles a run's end, whose neighbours are
  not k samples apart in time, and var(rho_k) = N_k / n^2 under white residuals keeps Q chi^2_h).
- Block means (time series): a misfit that is slow compared with the sampling spreads its chi^2 over
  thousands of samples, where chi^2/nu barely moves and the autocorrelations stay small; the means of the
  normalised residuals over blocks of m consecutive samples gather it: z_b = sum_{k in b} r_k / sqrt(m) is
  N(0, 1) for white residuals, and chi^2_blocks = sum over blocks and output channels of z_b^2 is tested
  against chi^2 with (blocks x channels - p) degrees of freedom; m = max(5, n // 64); blocks are cut run by
  run (a run's last m' < m samples are in no block).
- Cross-correlation of the residual with each measured input: rho(l) for |l| <= h samples, against the
  99 % bound 2.58/sqrt(n) of white residuals (the input is not prewhitened: a strongly coloured input
  widens the true bound; read it as a pointer, not a test); lagged pairs within one run, as for Ljung-Box.
- Structure (steady outputs): the residuals of an output channel against its own fitted value y. A misfit
  that the chi^2 of a few dozen points cannot show (it grows by 20 on nu = 40: p = 0.02) is often a smooth
  function of y (a curved sensor, a characteristic of the wrong shape). The score test of adding the
  Legendre polynomials P_1..P_3 of u = (2 y - y_max - y_min)/(y_max - y_min) on that channel's rows:
      Z_perp = Z - U U^T Z     (U: orthonormal basis of the fit's Jacobian; what the parameters absorb)
      T = |V^T r|^2           (V: orthonormal basis of Z_perp without its directions of singular value
                               below sqrt(1e-3): what the parameters absorb to 99.9 % tests nothing)
  is chi^2 with rank(V) degrees of freedom when the model is right (Ramsey's RESET test with the latent
  inputs and every free parameter in the null model).
- Drift (``drift:`` parameters): the parameter refitted on each group alone (the other parameters held
  at the global fit, the group's latent inputs, or the run's latent levels, free), with the homogeneity chi^2 =
  sum_g (theta_g - theta_w)^2 / se_g^2 on G - 1 degrees of freedom (theta_w the inverse-variance mean)
  and the spread max - min. An estimate that ends on a bound of the parameter is marked and left out of
  the test (its standard error means nothing there): a drift that pushes a parameter to its bound is
  reported as such.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats as sps

from blocks.calibrate.fit import FitResult, column_space, fit
from blocks.calibrate.model import Model


@dataclass
class ChannelStats:
    name: str
    role: str
    n: int
    rmse: float  # SI
    sigma: float  # SI
    chi2: float
    reduced: float  # chi2 / (n * nu / n_total)
    ljung_box: float | None = None
    ljung_box_p: float | None = None
    xcorr_max: float | None = None
    xcorr_lag: float | None = None
    xcorr_bound: float | None = None
    structure: float | None = None  # steady outputs: T of the residuals against the fitted value
    structure_dof: int | None = None
    structure_p: float | None = None


@dataclass
class LackOfFit:
    chi2: float
    n: int
    p: int
    nu: int
    reduced: float
    p_value: float
    channels: list[ChannelStats] = field(default_factory=list)
    drift: dict = field(default_factory=dict)
    blocks_chi2: float | None = None  # time series: chi^2 of the block means of the output residuals
    blocks_dof: int | None = None
    blocks_p: float | None = None

    def overstated_noise(self, alpha: float = 1e-3) -> list[ChannelStats]:
        """The output channels whose residuals are far smaller than the noise given: chi^2/nu below 1/2 (the
        noise overstated by over 40 %) and chi^2 in the lower tail of its distribution (chi^2 on the channel's
        share of nu) below alpha / (number of outputs). A noise overstated (a unit slip, 0.2 m for 0.2 mm)
        makes every test lenient: a missing effect goes unseen. Not the imposed inputs: their latent true
        values take up most of their own rows' degrees of freedom, which the share of nu does not know."""
        outputs = [c for c in self.channels if c.role == "output"]
        level = alpha / max(len(outputs), 1)
        out = []
        for c in outputs:
            dof = c.chi2 / c.reduced if c.reduced > 0 else float("inf")
            if c.reduced < 0.5 and (c.chi2 == 0 or sps.chi2.cdf(c.chi2, dof) < level):
                out.append(c)
        return out

    def significant(self, alpha: float = 0.01) -> list[str]:
        """Reasons the misfit is significant (empty: consistent with the noise). Every test made (chi^2,
        block means, Ljung-Box per output channel, structure per output channel, drift per parameter) is
        held at alpha / (number of tests) (Bonferroni), so that a model that is right is called wrong in at
        most alpha of the cases."""
        tests = 1 + (self.blocks_p is not None) + sum(c.ljung_box_p is not None for c in self.channels) \
            + sum(d.get("p_value") is not None for d in self.drift.values()) \
            + sum(c.structure_p is not None for c in self.channels)
        level = alpha / tests
        out = []
        if self.p_value < level:
            worst = max(self.channels, key=lambda c: c.reduced, default=None)
            where = "" if worst is None else (
                f"; worst channel: {worst.name}" + (" (an imposed input: its measured values disagree with what "
                                                    "the model imposes)" if worst.role == "input" else "")
                + f", chi^2/nu = {worst.reduced:.3g}")
            out.append(f"chi^2/nu = {self.reduced:.3g} (p = {self.p_value:.2g}){where}")
        if self.blocks_p is not None and self.blocks_p < level:
            out.append(f"slow misfit: block means of the residuals chi^2 = {self.blocks_chi2:.4g} on "
                       f"{self.blocks_dof} (p = {self.blocks_p:.2g})")
        for c in self.channels:
            if c.ljung_box_p is not None and c.ljung_box_p < level:
                out.append(f"{c.name}: residuals not white (Ljung-Box p = {c.ljung_box_p:.2g})")
        for c in self.channels:
            if c.structure_p is not None and c.structure_p < level:
                out.append(f"{c.name}: residuals follow its fitted value (a cubic in it takes chi^2 = "
                           f"{c.structure:.3g} on {c.structure_dof}, p = {c.structure_p:.2g})")
        for name, d in self.drift.items():
            if d.get("p_value") is not None and d["p_value"] < level:
                out.append(f"{name} drifts between groups (p = {d['p_value']:.2g})")
        return out


def lack_of_fit(model: Model, res: FitResult) -> LackOfFit:
    rows = res.rows
    n_total = int(rows.sum())
    nu = res.nu
    chans = []
    r = res.r
    absorbable = column_space(res.J)[2] if res.J.size else np.zeros((n_total, 0))
    for ci, ch in enumerate(model.channels):
        sel = rows & (model.row_channel == ci)
        n_c = int(sel.sum())
        if n_c == 0:
            continue
        chi2_c = float(np.sum(r[sel] ** 2))
        sigma = model.sigma[ci]
        share = n_c * nu / n_total
        cs = ChannelStats(ch.name, ch.role, n_c, float(np.sqrt(np.mean((r[sel] * sigma) ** 2))), float(sigma),
                          chi2_c, chi2_c / share if share > 0 else np.nan)
        if model.data.kind == "time" and ch.role == "output":
            e = r[sel]
            runs = run_lengths(model, sel)
            cs.ljung_box, cs.ljung_box_p = ljung_box(e, runs=runs)
            best, lag, bound = 0.0, 0.0, 2.58 / np.sqrt(n_c)
            for inp in model.exp.inputs:
                u = model.data.measured[inp.name][model.row_point[sel]]
                rho, k = max_cross_correlation(e, u, runs=runs)
                if abs(rho) > abs(best):
                    best, lag = rho, k * float(np.median(np.diff(model.data.t)))
            cs.xcorr_max, cs.xcorr_lag, cs.xcorr_bound = best, lag, bound
        if model.data.kind == "steady" and ch.role == "output":
            cs.structure, cs.structure_dof, cs.structure_p = structure(model, res, ci, absorbable)
        chans.append(cs)
    lof = LackOfFit(res.chi2, n_total, res.p, nu, res.reduced, float(sps.chi2.sf(res.chi2, nu)), chans)
    if model.data.kind == "time":
        lof.blocks_chi2, lof.blocks_dof, lof.blocks_p = block_means(model, res)
    return lof


def structure(model: Model, res: FitResult, channel: int, absorbable: np.ndarray,
              degree: int = 3) -> tuple[float | None, int | None, float | None]:
    """The score test of the residuals of output ``channel`` against its fitted value (module docstring);
    ``absorbable`` is an orthonormal basis of the fit's Jacobian columns (rows: the fit's used rows).
    (None, None, None) when the channel has too few points or its fitted values do not vary."""
    used = np.nonzero(res.rows)[0]
    mine = model.row_channel[used] == channel
    if int(mine.sum()) < degree + 3:
        return None, None, None
    y = model.measured[used][mine] + res.r[used][mine] * model.row_sigma[used][mine]
    lo, hi = float(np.min(y)), float(np.max(y))
    if not hi - lo > 1e-6 * float(np.median(model.row_sigma[used][mine])):  # the fitted value does not vary
        return None, None, None
    u = (2.0 * y - hi - lo) / (hi - lo)
    Z = np.zeros((used.size, degree))
    Z[mine] = np.polynomial.legendre.legvander(u, degree)[:, 1:]
    Z /= np.sqrt(np.sum(Z * Z, axis=0))
    Z -= absorbable @ (absorbable.T @ Z)
    V, sv, _ = np.linalg.svd(Z, full_matrices=False)
    V = V[:, sv > np.sqrt(1e-3)]  # a column the parameters absorb to 99.9 % tests nothing
    if V.shape[1] == 0:
        return None, None, None
    T = float(np.sum((V.T @ res.r[used]) ** 2))
    return T, int(V.shape[1]), float(sps.chi2.sf(T, V.shape[1]))


def run_lengths(model: Model, sel: np.ndarray) -> list[int]:
    """The lengths of the runs among the selected rows of one channel, in row order (a time series's rows
    follow its samples, and a run's samples are contiguous: :mod:`blocks.calibrate.data` checks it)."""
    run_of_point = np.empty(model.data.n, dtype=int)
    for j, points in enumerate(model.data.groups.values()):
        run_of_point[points] = j
    runs = run_of_point[model.row_point[sel]]
    if runs.size == 0:
        return []
    cuts = np.flatnonzero(np.diff(runs)) + 1
    return np.diff(np.concatenate([[0], cuts, [runs.size]])).tolist()


def _segments(n: int, runs: list[int] | None) -> list[slice]:
    if not runs:
        return [slice(0, n)]
    if sum(runs) != n:
        raise ValueError(f"run lengths add up to {sum(runs)}, not to the {n} residuals")
    ends = np.cumsum(runs)
    return [slice(int(end - length), int(end)) for length, end in zip(runs, ends)]


def block_means(model: Model, res: FitResult) -> tuple[float, int, float]:
    """chi^2 of the block means of the output residuals (module docstring): blocks of m samples, cut run by
    run."""
    n = model.data.n
    m = max(5, n // 64)
    total, blocks = 0.0, 0
    for ci, ch in enumerate(model.channels):
        if ch.role != "output":
            continue
        sel = res.rows & (model.row_channel == ci)
        r = res.r[sel]
        for seg in _segments(r.size, run_lengths(model, sel)):
            part = r[seg]
            k = part.size // m
            if k == 0:
                continue
            z = part[: k * m].reshape(k, m).sum(axis=1) / np.sqrt(m)
            total += float(np.sum(z * z))
            blocks += k
    dof = max(blocks - res.p, 1)
    return total, dof, float(sps.chi2.sf(total, dof))


def _lagged_sum(a: np.ndarray, b: np.ndarray, k: int, segments: list[slice]) -> tuple[float, int]:
    """sum of a[i + k] * b[i] over the pairs within one segment (k >= 0), and how many pairs."""
    total, pairs = 0.0, 0
    for seg in segments:
        x, y = a[seg], b[seg]
        if x.size > k:
            total += float(np.sum(x[k:] * y[:x.size - k]))
            pairs += x.size - k
    return total, pairs


def ljung_box(e: np.ndarray, h: int | None = None, runs: list[int] | None = None) -> tuple[float, float]:
    """Q and its p-value (module docstring); ``runs``: the lengths of consecutive runs in ``e`` (None: one)."""
    n = e.size
    h = h or max(1, min(20, n // 5))
    e = e - e.mean()
    denom = float(np.sum(e * e))
    if denom == 0.0 or n < 3:
        return 0.0, 1.0
    segments = _segments(n, runs)
    q, lags = 0.0, 0
    for k in range(1, h + 1):
        s, pairs = _lagged_sum(e, e, k, segments)
        if pairs == 0:
            break
        q += (s / denom) ** 2 / pairs
        lags += 1
    q *= n * (n + 2)
    return q, float(sps.chi2.sf(q, lags)) if lags else 1.0


def max_cross_correlation(e: np.ndarray, u: np.ndarray, h: int | None = None,
                          runs: list[int] | None = None) -> tuple[float, int]:
    """The largest |rho(l)| of e(k) against u(k - l), |l| <= h, and its lag l in samples; pairs within one
    run."""
    n = e.size
    h = h or max(1, min(20, n // 5))
    a, b = e - e.mean(), u - u.mean()
    sa, sb = np.sqrt(np.sum(a * a)), np.sqrt(np.sum(b * b))
    if sa == 0 or sb == 0:
        return 0.0, 0
    segments = _segments(n, runs)
    best, lag = 0.0, 0
    for k in range(-h, h + 1):
        s = _lagged_sum(a, b, k, segments)[0] if k >= 0 else _lagged_sum(b, a, -k, segments)[0]
        rho = s / (sa * sb)
        if abs(rho) > abs(best):
            best, lag = float(rho), k
    return best, lag


def drift(model: Model, res: FitResult, names: list[str]) -> dict:
    """Each ``names`` parameter refitted per group (steady points, or the runs of a time series): estimates,
    SEs, spread, homogeneity test."""
    out = {}
    groups = model.data.groups
    if len(groups) < 2:
        return out
    for name in names:
        j = model.layout.index(name)
        est, se, labels, bound = [], [], [], []
        lo, hi = model.bounds()
        for label, points in groups.items():
            active = np.zeros(len(res.x), dtype=bool)
            active[j] = True
            for k in points:
                for i in range(len(model.layout.inputs)):
                    active[model.layout.latent_index(int(k), i)] = True
            for k, g in enumerate(model.layout.globals):  # a run's latent levels
                active[k] |= g.run == label
            rows = model.rows_of_points(points)
            g = fit(model, res.x, active, rows, max_nfev=30)
            est.append(g.x[j])
            se.append(g.se[j])
            labels.append(label)
            span = hi[j] - lo[j] if np.isfinite(hi[j] - lo[j]) else abs(g.x[j]) + 1.0
            bound.append(bool(min(g.x[j] - lo[j], hi[j] - g.x[j]) < 1e-6 * span))
        est, se = np.array(est), np.array(se)
        ok = np.isfinite(se) & (se > 0) & ~np.array(bound)
        entry = {"groups": labels, "estimates": est.tolist(), "se": se.tolist(), "at_bound": bound,
                 "spread": float(est.max() - est.min()), "global": float(res.x[j]), "global_se": float(res.se[j])}
        if ok.sum() >= 2:
            w = 1.0 / se[ok] ** 2
            mean = float(np.sum(w * est[ok]) / np.sum(w))
            chi2 = float(np.sum((est[ok] - mean) ** 2 * w))
            entry.update({"weighted_mean": mean, "chi2": chi2, "dof": int(ok.sum() - 1),
                          "p_value": float(sps.chi2.sf(chi2, ok.sum() - 1))})
        out[name] = entry
    return out
