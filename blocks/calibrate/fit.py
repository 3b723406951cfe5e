"""Weighted least squares on the normalised residuals: scipy's trust-region reflective method with the
model's own absolute-step finite-difference Jacobian, bounds on every parameter.

The solver works on each fitted parameter divided by its own size, max(|start|, finite-difference step), so
that every variable it sees is of order 1. In SI the parameters differ by 18 orders of magnitude (a leakage
conductance of 2e-11 m^3/(s*Pa) beside a latent pressure of 3e6 Pa), and two of the solver's rules are
absolute or taken over the whole vector: its step tolerance, |dx| < xtol * |x|, then ignores whatever the
small parameters still do (a conductance of 2e-12 beside latent pressures of 1e7 Pa, started at 0.3 of its
minimum, was reported converged at 2.8 times it: tests/calibrate/test_fit_scaling.py), and it moves a start
closer than 1e-10 to a bound to 1e-10 from it (a leakage started at 2e-11 was started at 1e-10 instead, and
a held-out refit then did not converge in 100 evaluations).

Standard errors: cov = (J^T J)^-1 at the solution (the residuals are already divided by the noise, so this
is the covariance when the model is right), inflated by max(1, chi^2/nu) when the fit is worse than the
noise allows: a misfit never makes a parameter look better determined than the data say. Rows whose run
failed at the solution hold a penalty (FAILED_RESIDUAL; it keeps chi^2 and BIC honest about a model that does
not run there), not a residual: they take no part in either, or one point the model cannot run would inflate
every SE of the fit by about FAILED_RESIDUAL / sqrt(nu).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from blocks.calibrate.model import FAILED_RESIDUAL, Model


@dataclass
class FitResult:
    x: np.ndarray  # the full parameter vector
    active: np.ndarray  # bool: which entries were fitted
    rows: np.ndarray  # bool: which residual rows were used
    r: np.ndarray  # all residual rows at x (0 outside the computed points)
    J: np.ndarray  # d r[rows] / d x[active]
    chi2: float
    n: int
    p: int
    cov: np.ndarray  # of x[active], inflated by max(1, chi2/nu) over the rows that ran
    se: np.ndarray  # full length, NaN where not fitted
    nfev: int
    message: str
    unsettled: int
    failures: list[str]
    converged: bool = True  # False: stopped at the evaluation limit (max_nfev) before a tolerance was met

    @property
    def nu(self) -> int:
        return max(self.n - self.p, 1)

    @property
    def reduced(self) -> float:
        return self.chi2 / self.nu

    def bic(self) -> float:
        """chi^2 + p ln n: -2 log-likelihood up to a constant (known noise) plus the BIC penalty."""
        return self.chi2 + self.p * np.log(self.n)

    @property
    def inflation(self) -> float:
        """What the covariance was inflated by: max(1, chi^2/nu) over the rows that ran."""
        return misfit_inflation(self.r[self.rows], self.p)

    @property
    def ran(self) -> np.ndarray:
        """Which rows of J ran at the fit's end (the others hold the failure value)."""
        return ran_rows(self.r[self.rows])

    @property
    def failed_rows(self) -> int:
        """Residual rows of the fit whose run failed at its end (they hold FAILED_RESIDUAL, not a misfit)."""
        return int(np.sum(self.r[self.rows] == FAILED_RESIDUAL))

    def run_failure(self, beyond: int = 0) -> str:
        """What a report says when more rows than ``beyond`` (those that fail already without the change being
        judged) hold the failure value at the fit's end; '' otherwise."""
        if self.failed_rows <= beyond:
            return ""
        return (f"the model does not run at the fit's end ({self.failed_rows} of {self.n} rows failed"
                + (f", {beyond} without it" if beyond else "")
                + (f"; the last solver message in the fit: {self.failures[-1]}" if self.failures else "") + ")")


def points_of(model: Model, rows: np.ndarray):
    """The steady points whose rows are used (None: all, or a time series)."""
    if model.data.kind != "steady":
        return None
    pts = np.unique(model.row_point[rows])
    return None if pts.size == model.data.n else pts


def fit(model: Model, x0: np.ndarray, active: np.ndarray, rows: np.ndarray | None = None,
        max_nfev: int = 40, tol: float = 1e-8) -> FitResult:
    """Fit x[active] (others held at x0) to the residual rows ``rows`` (default: all)."""
    rows = np.ones(model.n_rows, dtype=bool) if rows is None else rows
    active = np.asarray(active, dtype=bool)
    cols = np.nonzero(active)[0]
    points = points_of(model, rows)
    lo, hi = model.bounds()
    x_base = np.array(x0, dtype=float)
    z0 = np.clip(x_base[cols], lo[cols], hi[cols])
    model.failures.clear()
    last = {}

    def full(z):
        x = x_base.copy()
        x[cols] = z
        return x

    def fun(z):
        x = full(z)
        r = model.residuals(x, points)
        last["x"], last["r"] = x, r
        return r[rows]

    def jac(z):
        x = full(z)
        r0 = last["r"] if "x" in last and np.array_equal(last["x"], x) else model.residuals(x, points)
        return model.jacobian(x, cols, points, r0)[rows]

    if cols.size:
        size = np.maximum(np.abs(z0), model.steps()[cols])  # the solver's variables are z / size, all O(1)
        size = np.where(size > 0, size, 1.0)
        res = least_squares(lambda u: fun(u * size), z0 / size, jac=lambda u: jac(u * size) * size,
                            bounds=(lo[cols] / size, hi[cols] / size), method="trf", x_scale="jac",
                            ftol=tol, xtol=tol, gtol=tol, max_nfev=max_nfev)
        x = full(res.x * size)
        nfev, message, converged = res.nfev, res.message, res.status != 0  # status 0: max_nfev reached
    else:
        x, nfev, message, converged = x_base, 0, "nothing to fit", True
    r = model.residuals(x, points)
    J = model.jacobian(x, cols, points, r)[rows] if cols.size else np.zeros((int(rows.sum()), 0))
    return summarise(model, x, active, rows, r, J, nfev, message, converged)


def summarise(model: Model, x, active, rows, r, J, nfev=0, message="", converged=True) -> FitResult:
    chi2 = float(np.sum(r[rows] ** 2))
    n, p = int(rows.sum()), int(np.sum(active))
    cov = covariance(J[ran_rows(r[rows])]) * misfit_inflation(r[rows], p)
    se = np.full(len(x), np.nan)
    se[np.nonzero(active)[0]] = np.sqrt(np.maximum(np.diag(cov), 0.0)) if p else []
    unsettled = len(model.unsettled) if model.data.kind == "steady" else 0
    return FitResult(x, np.asarray(active, bool), rows, r, J, chi2, n, p, cov, se, nfev, message, unsettled,
                     list(model.failures), converged)


def ran_rows(r_used: np.ndarray) -> np.ndarray:
    """Which of a fit's residual rows ran: a failed run's rows hold a penalty, not a misfit noise could explain."""
    return r_used != FAILED_RESIDUAL


def misfit_inflation(r_used: np.ndarray, p: int) -> float:
    """max(1, chi^2/nu) over the rows that ran, for p fitted parameters: what a misfit multiplies the
    covariance by."""
    ran = ran_rows(r_used)
    return max(1.0, float(np.sum(r_used[ran] ** 2)) / max(int(ran.sum()) - p, 1))


def covariance(J: np.ndarray) -> np.ndarray:
    """(J^T J)^-1 through the SVD of the column-scaled Jacobian (parameters differ in scale by 1e15 in SI),
    as a pseudo-inverse: a direction the data do not fix (singular value below 1e-10 of the largest) gets
    infinite variance on the parameters it involves rather than a silently small one."""
    if J.shape[1] == 0:
        return np.zeros((0, 0))
    norms = np.sqrt(np.sum(J * J, axis=0))
    scale = np.where(norms > 0, 1.0 / np.where(norms > 0, norms, 1.0), 1.0)
    Js = J * scale
    U, s, Vt = np.linalg.svd(Js, full_matrices=False)
    keep = s > s[0] * 1e-10 if s.size and s[0] > 0 else np.zeros_like(s, dtype=bool)
    inv = np.zeros_like(s)
    inv[keep] = 1.0 / s[keep] ** 2
    cov = (Vt.T * inv) @ Vt
    cov = cov * np.outer(scale, scale)
    for k in np.nonzero(~keep)[0]:
        for j in np.nonzero(np.abs(Vt[k]) > 1e-3)[0]:
            cov[j, j] = np.inf
    for j in np.nonzero(norms == 0)[0]:
        cov[j, j] = np.inf
    return cov


def column_space(J: np.ndarray, rel: float = 1e-9):
    """The SVD of J with its columns scaled to unit norm (zero columns dropped): (keep, Js, U, s, Vt) with
    only the singular triplets above ``rel`` times the largest kept. U is an orthonormal basis of what the
    fitted parameters can absorb; removing it from a vector leaves the part no parameter can take."""
    norms = np.sqrt(np.sum(J * J, axis=0))
    keep = norms > 0
    Js = J[:, keep] / norms[keep]
    U, s, Vt = np.linalg.svd(Js, full_matrices=False)
    rank = int(np.sum(s > s[0] * rel)) if s.size else 0
    return keep, Js, U[:, :rank], s[:rank], Vt[:rank]
