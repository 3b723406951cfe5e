"""Known statistical results behind the fit, the selection and the outlier bound (blocks/calibrate/fit.py,
selection.py, outliers.py), each against a closed form written here: BIC = chi^2 + p ln n on nu = n - p,
the covariance (J^T J)^-1 of a linear least-squares problem (exact, whatever the columns' scales),
the inflation max(1, chi^2/nu), dBIC = dchi^2 + ln n of one parameter more, the z of an effect, the 95 %
point of chi^2_1 that a score must pass to be refitted, and the Bonferroni bound of the largest residual.

Added from a mutation-testing pass (session 26): each test failed on a mutant the existing tests let
through."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats as sps

from blocks.calibrate import outliers, selection
from blocks.calibrate.fit import FitResult, covariance, misfit_inflation, summarise
from blocks.calibrate.model import FAILED_RESIDUAL
from blocks.calibrate.screening import Score


def _result(chi2, n, p):
    return FitResult(np.zeros(p), np.ones(p, bool), np.ones(n, bool), np.zeros(n), np.zeros((n, p)), chi2, n, p,
                     np.eye(p), np.ones(p), 0, "", 0, [])


def test_bic_nu_and_reduced_chi2_of_a_fit():
    """BIC = chi^2 + p ln n (known noise); nu = n - p, never below 1; chi^2/nu on it."""
    res = _result(37.5, 40, 3)
    assert res.bic() == pytest.approx(37.5 + 3 * np.log(40), rel=1e-14)
    assert res.nu == 37 and res.reduced == pytest.approx(37.5 / 37, rel=1e-14)
    exact = _result(0.0, 3, 3)
    assert exact.nu == 1 and exact.reduced == 0.0


def test_covariance_of_linear_least_squares_with_columns_1e15_apart():
    """For r = J x - y the covariance of the estimate is (J^T J)^-1 exactly. The columns differ in scale by
    1e15 (a leakage conductance beside a pressure in SI): the column scaling must cancel out. rtol 1e-8:
    np.linalg.inv of the well-conditioned scaled problem, unscaled, agrees to ~1e-12; 1e-8 leaves room."""
    rng = np.random.default_rng(7)
    base = rng.normal(size=(30, 3))
    scales = np.array([1e-9, 1.0, 1e6])
    J = base * scales
    expected = np.linalg.inv(base.T @ base) / np.outer(scales, scales)
    assert np.allclose(covariance(J), expected, rtol=1e-8, atol=0)


def test_covariance_is_infinite_where_the_data_do_not_fix_a_direction():
    """Two equal columns: a and b are fixed only in their sum, both get infinite variance; a third, independent
    column keeps its finite (J^T J)^-1 entry for the identifiable part. A zero column: infinite too."""
    rng = np.random.default_rng(8)
    c = rng.normal(size=20)
    d = rng.normal(size=20)
    cov = covariance(np.column_stack([c, c, d]))
    assert np.isinf(cov[0, 0]) and np.isinf(cov[1, 1]) and np.isfinite(cov[2, 2])
    cov = covariance(np.column_stack([c, np.zeros(20)]))
    assert np.isinf(cov[1, 1])
    assert cov[0, 0] == pytest.approx(1.0 / (c @ c), rel=1e-12)


def test_covariance_of_one_parameter_and_the_1e_10_cut_of_singular_values():
    """One column: var = 1 / (c . c). Three unit columns a, a + 1e-3 b, a + 1e-3 b + 5e-12 c (a, b, c
    orthonormal): singular values about 1.7, 8e-4 and 3e-12; the last is below 1e-10 of the largest, so the
    direction it spans is not fixed by the data and the parameters in it get infinite variance (had the cut
    been taken against the second singular value, 8e-14, it would have been kept)."""
    rng = np.random.default_rng(13)
    c = rng.normal(size=25)
    assert covariance(c[:, None])[0, 0] == pytest.approx(1.0 / (c @ c), rel=1e-12)
    a, b, e = np.linalg.qr(rng.normal(size=(25, 3)))[0].T
    cols = [a, a + 1e-3 * b, a + 1e-3 * b + 5e-12 * e]
    J = np.column_stack([v / np.linalg.norm(v) for v in cols])
    sv = np.linalg.svd(J, compute_uv=False)
    assert sv[2] < 1e-10 * sv[0] and sv[2] > 1e-10 * sv[1]
    cov = covariance(J)
    assert np.isinf(cov[1, 1]) and np.isinf(cov[2, 2])


def test_misfit_inflation_is_chi2_over_nu_of_the_rows_that_ran():
    """max(1, chi^2 / (n_ran - p)); rows holding FAILED_RESIDUAL count in neither chi^2 nor n."""
    r = np.array([3.0, -2.0, 1.0, 2.5, -3.0, 2.0])
    chi2 = float(r @ r)
    assert misfit_inflation(r, 2) == pytest.approx(chi2 / 4, rel=1e-14)
    assert misfit_inflation(np.append(r, FAILED_RESIDUAL), 2) == pytest.approx(chi2 / 4, rel=1e-14)
    assert misfit_inflation(0.1 * r, 2) == 1.0  # a fit better than the noise is not deflated
    assert misfit_inflation(r, 6) == pytest.approx(chi2 / 1, rel=1e-14)  # nu floored at 1


def test_standard_errors_of_a_weighted_line_are_the_closed_form():
    """summarise(): se = sqrt(diag((J^T J)^-1) * max(1, chi^2/nu)) for a line fitted by weighted least squares
    (J = X / sigma, r = (X theta - y) / sigma), with a misfit (inflated) and without (not deflated)."""
    rng = np.random.default_rng(12)
    t = np.linspace(0.0, 2.0, 15)
    sigma = np.linspace(0.5, 2.0, 15)
    X = np.column_stack([np.ones_like(t), t])
    for spread in (0.3, 4.0):
        y = 1.0 + 3.0 * t + spread * sigma * rng.normal(size=t.size)
        J = X / sigma[:, None]
        theta = np.linalg.lstsq(J, y / sigma, rcond=None)[0]
        r = J @ theta - y / sigma
        chi2 = float(r @ r)
        expected = np.sqrt(np.diag(np.linalg.inv(J.T @ J)) * max(1.0, chi2 / (t.size - 2)))
        model = SimpleNamespace(data=SimpleNamespace(kind="time"), failures=[])
        res = summarise(model, theta, np.array([True, True]), np.ones(t.size, bool), r, J)
        assert res.chi2 == pytest.approx(chi2, rel=1e-14) and (res.n, res.p) == (15, 2)
        assert np.allclose(res.se, expected, rtol=1e-10, atol=0)


def test_z_score_of_an_effect():
    """|phi - zero| / SE; 0 when the SE is zero, negative, infinite or NaN (no usable SE)."""
    assert selection.z_score(7.0, 1.0, 2.0) == 3.0
    assert selection.z_score(-5.0, 1.0, 2.0) == 3.0
    for se in (0.0, -1.0, np.inf, np.nan):
        assert selection.z_score(7.0, 1.0, se) == 0.0


def test_a_score_is_refitted_only_beyond_the_95_percent_point_of_chi2_1():
    """T > 3.84 (chi^2_1's 95 % point, 3.8415): a score of 3.85 is refitted, 3.83 is not; the best ``top``
    first; only screened scores."""
    assert sps.chi2.ppf(0.95, 1) == pytest.approx(3.84, abs=2e-3)
    scores = [Score(SimpleNamespace(key=k), status, T=T) for k, status, T in (
        ("a", "screened", 3.83), ("b", "screened", 3.85), ("c", "screened", 40.0), ("d", "not identifiable", 90.0),
        ("e", "screened", 12.0))]
    assert [s.place.key for s in selection.candidates_to_refit(scores, 5)] == ["c", "e", "b"]
    assert [s.place.key for s in selection.candidates_to_refit(scores, 2)] == ["c", "e"]


def _refit_of(chi2, n, p, phi, se, plausible=(0.0, 10.0), zero=0.0):
    fit = SimpleNamespace(x=np.array([phi]), se=np.array([se]), chi2=chi2, n=n, p=p)
    score = Score(SimpleNamespace(key="k", zero=zero, plausible=plausible), "screened")
    return selection._refit_result(score, None, fit, 0, base_chi2=100.0, base_failed_rows=0)


def test_dbic_of_one_parameter_more_is_the_chi2_drop_plus_ln_n():
    """dBIC = chi^2_new - chi^2_base + ln n (one parameter more, known noise); the plausible range is closed."""
    rf = _refit_of(60.0, 50, 4, 2.0, 0.5)
    assert rf.dchi2 == -40.0 and rf.dbic == pytest.approx(-40.0 + np.log(50), rel=1e-14)
    assert rf.z == 4.0 and rf.plausible
    assert _refit_of(60.0, 50, 4, 10.0, 0.5).plausible and _refit_of(60.0, 50, 4, 0.0, 0.5).plausible
    assert not _refit_of(60.0, 50, 4, 10.0 + 1e-9, 0.5).plausible


def test_refit_tests_z_over_3_dbic_under_minus_10_and_a_dof_left():
    """passes_fit_tests: z > 3 (strict), dBIC < -10 (strict), plausible, a degree of freedom left (n > p)."""
    def rf(chi2=60.0, n=50, p=4, phi=2.0, se=0.5):
        r = _refit_of(chi2, n, p, phi, se)
        r.fit.run_failure = lambda beyond=0: ""
        return r

    assert rf().passes_fit_tests
    assert not rf(se=2.0 / 3.0).passes_fit_tests  # z exactly 3
    assert rf(se=2.0 / 3.0 * 0.999).passes_fit_tests
    edge = 100.0 - 10.0 - np.log(50)  # chi^2 at which dBIC is exactly -10
    assert not rf(chi2=edge + 1e-9).passes_fit_tests and rf(chi2=edge - 1e-6).passes_fit_tests
    assert not rf(n=4, p=4, chi2=0.0).passes_fit_tests and rf(n=5, p=4, chi2=0.0).passes_fit_tests
    # only_implausible: every fit test but the plausible range (phi = 12 outside [0, 10])
    assert rf(phi=12.0).only_implausible and not rf(phi=12.0).passes_fit_tests and not rf().only_implausible
    assert not rf(phi=12.0, chi2=edge + 1e-9).only_implausible and not rf(phi=12.0, se=4.0).only_implausible


def test_better_start_needs_a_drop_over_25_beyond_z_squared_of_the_raw_se():
    """A refit under 3 SE whose chi^2 is over 25 below the fit's beyond z_raw^2 (z with the SE before the
    misfit inflated it: z_raw = z sqrt(inflation)) shows a better minimum; the lowest such refit is returned."""
    def rf(chi2, z, inflation, se=1.0):
        fit = SimpleNamespace(chi2=chi2, inflation=inflation)
        return SimpleNamespace(run_failure="", se=se, z=z, fit=fit)

    base = 200.0
    # z = 2, inflation 4: z_raw^2 = 16; a drop of 16 + 25 is the edge
    assert selection.better_start([rf(base - 41.0 + 1e-6, 2.0, 4.0)], base) is None
    found = rf(base - 41.5, 2.0, 4.0)
    lower = rf(base - 60.0, 1.0, 1.0)
    assert selection.better_start([found], base) is found
    assert selection.better_start([found, lower], base) is lower
    assert selection.better_start([rf(base - 100.0, 3.5, 1.0)], base) is None  # significant: its own drop
    for se in (0.0, np.inf):  # no usable SE (z reads 0 then): no conclusion from its drop
        assert selection.better_start([rf(base - 100.0, 0.0, 1.0, se=se)], base) is None


@pytest.mark.parametrize("n", [1, 48, 600, 6000])
def test_outlier_bound_is_bonferroni_at_1_percent_two_sided(n):
    """c = Phi^-1(1 - 0.005 / N): the chance that any of N independent N(0,1) residuals exceeds |c| is
    1 - (1 - 0.01/N)^N, at most 1 % and over 0.995 % for every N (the module docstring's 3.71, 4.31, 4.79)."""
    c = outliers.bound(n)
    assert c == pytest.approx(sps.norm.ppf(1.0 - 0.005 / n), rel=1e-12)
    family = 1.0 - (1.0 - 2.0 * sps.norm.sf(c)) ** n
    assert 0.00995 <= family <= 0.01 + 1e-12
    said = {48: 3.71, 600: 4.31, 6000: 4.79}
    if n in said:
        assert c == pytest.approx(said[n], abs=5e-3)


def test_separate_names_the_unmeasured_signal_the_two_fits_disagree_on_most_relative_to_its_size():
    """Two fits of a time series: pA differs by up to 5 bar on 30 bar (17 %), q by up to 30 l/min on 60 l/min
    (50 %), v is measured (not a suggestion): q is named, its difference in its display unit (l/min)."""
    t = np.arange(3)
    sig_a = np.column_stack([np.array([1e6, 2e6, 3e6]), np.array([1e-3, 5e-4, 2e-4]), t * 0.1])
    sig_b = np.column_stack([np.array([1e6, 2.5e6, 2.9e6]), np.array([5e-4, 5e-4, 2e-4]), t * 0.1 + 5.0])
    outputs = [SimpleNamespace(name="pA", display_unit="bar"), SimpleNamespace(name="q", display_unit="l/min"),
               SimpleNamespace(name="v", display_unit="m/s")]

    def refit(key, signals):
        model = SimpleNamespace(signals=lambda x: signals, circuit=SimpleNamespace(outputs=outputs),
                                channels=[SimpleNamespace(name="v", signal="v", role="output")],
                                data=SimpleNamespace(kind="time"), layout=SimpleNamespace(inputs=[]))
        return SimpleNamespace(score=SimpleNamespace(place=SimpleNamespace(key=key)), fit=SimpleNamespace(x=None),
                               model=model)

    # v, measured already, differs most of all (by 5 m/s): it is no suggestion
    (line,) = selection.separate(refit("A", sig_a), refit("B", sig_b))
    assert line == "A vs B: measuring 'q' would separate them (the two fits predict it up to 30 l/min apart)"
