"""Lack-of-fit statistics (blocks/calibrate/stats.py) against their definitions, written here independently:
the per-channel share of the degrees of freedom, the p-value of chi^2 on nu, the textbook Ljung-Box Q with
its default number of lags, the cross-correlation coefficient and its 99 % bound, the block means' size and
degrees of freedom, the Bonferroni level of ``significant`` and the drift's homogeneity chi^2.

Tests added from a mutation-testing pass (session 26): each one failed on a mutant of stats.py that the
existing tests let through. Every expected number comes from the formula (or scipy.stats), never from the
code's own output; the tolerances are rounding-level (rel 1e-12 on sums of a few hundred terms)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats as sps

from blocks.calibrate import stats as st
from blocks.calibrate.stats import ChannelStats, LackOfFit, block_means, lack_of_fit, ljung_box, max_cross_correlation

RTOL = 1e-12  # sums of at most a few hundred products in float64: rounding only


def _textbook_ljung_box(e: np.ndarray, h: int) -> float:
    """Q = n (n + 2) sum_{k=1..h} rho_k^2 / (n - k), rho_k = sum_i d_i d_{i+k} / sum_i d_i^2, d = e - mean."""
    n = e.size
    d = e - e.mean()
    q = 0.0
    for k in range(1, h + 1):
        rho = sum(d[i] * d[i + k] for i in range(n - k)) / sum(d * d)
        q += rho * rho / (n - k)
    return n * (n + 2) * q


def _rho(e: np.ndarray, u: np.ndarray, lag: int) -> float:
    """Sample cross-correlation of e(k) with u(k - lag), one run, normalised by the full sums of squares."""
    a, b = e - e.mean(), u - u.mean()
    n = e.size
    s = sum(a[k] * b[k - lag] for k in range(n) if 0 <= k - lag < n)
    return s / np.sqrt(np.sum(a * a) * np.sum(b * b))


@pytest.mark.parametrize("n, h", [(50, 10), (12, 2), (300, 20), (7, 1), (4, 1), (3, 1)])
def test_ljung_box_default_lags_are_min_20_and_n_over_5(n, h):
    """Without ``h``, Q uses h = max(1, min(20, n // 5)) lags (module docstring) and the p-value is chi^2 on
    h degrees of freedom: checked against the textbook Ljung-Box sum at that h."""
    e = np.random.default_rng(n).normal(size=n)
    q, p = ljung_box(e)
    expected = _textbook_ljung_box(e, h)
    assert q == pytest.approx(expected, rel=RTOL)
    assert p == pytest.approx(sps.chi2.sf(expected, h), rel=1e-10)


def test_ljung_box_of_a_constant_or_too_short_series_is_zero_with_p_one():
    """No variance (every residual equal), or fewer than 3 residuals: nothing to test, Q = 0 and p = 1."""
    assert ljung_box(np.full(10, 2.5)) == (0.0, 1.0)
    assert ljung_box(np.array([1.0, -1.0])) == (0.0, 1.0)


def test_cross_correlation_value_is_the_sample_correlation_coefficient():
    """The largest |rho(l)| is the sample cross-correlation by its definition (one run), with its lag in
    samples, negative as well as positive lags searched (e follows u by -2 samples here, sign flipped)."""
    rng = np.random.default_rng(11)
    u = rng.normal(size=80)
    e = -0.7 * np.roll(u, -2) + 0.5 * rng.normal(size=80)  # e(k) = -0.7 u(k + 2) + noise: lag -2, rho < 0
    rho, lag = max_cross_correlation(e, u)
    h = 16  # min(20, 80 // 5)
    by_lag = {l: _rho(e, u, l) for l in range(-h, h + 1)}
    best = max(by_lag, key=lambda l: abs(by_lag[l]))
    assert lag == best == -2
    assert rho == pytest.approx(by_lag[best], rel=RTOL) and rho < 0


def test_cross_correlation_of_a_short_series_still_searches_one_lag():
    """n = 4: h = max(1, 4 // 5) = 1, so lags -1, 0, 1 are searched; e(k) = u(k - 1) is found at lag +1."""
    u = np.array([0.0, 1.0, 0.0, 0.0])
    e = np.array([0.0, 0.0, 1.0, 0.0])
    rho, lag = max_cross_correlation(e, u)
    assert lag == 1 and rho == pytest.approx(_rho(e, u, 1), rel=RTOL)


def test_cross_correlation_with_a_constant_input_is_zero():
    """An input that does not vary (or residuals that do not) correlates with nothing: rho = 0 at lag 0."""
    e = np.random.default_rng(3).normal(size=30)
    assert max_cross_correlation(e, np.full(30, 4.0)) == (0.0, 0)
    assert max_cross_correlation(np.full(30, -1.0), e) == (0.0, 0)


def test_block_means_size_grows_with_n_and_dof_is_blocks_minus_p():
    """m = max(5, n // 64): 640 samples in one run give blocks of 10, 64 of them; chi^2 is the sum of the
    squared block sums / sqrt(m), on 64 - p degrees of freedom; the dof never goes below 1."""
    n = 640
    r = np.random.default_rng(2).normal(size=n) + 0.05
    model = SimpleNamespace(data=SimpleNamespace(n=n, groups={"all": np.arange(n)}),
                            channels=[SimpleNamespace(role="output")], row_channel=np.zeros(n, dtype=int),
                            row_point=np.arange(n))
    res = SimpleNamespace(rows=np.ones(n, dtype=bool), r=r, p=3)
    z = r.reshape(64, 10).sum(axis=1) / np.sqrt(10)
    chi2, dof, p = block_means(model, res)
    assert chi2 == pytest.approx(float(np.sum(z * z)), rel=RTOL)
    assert dof == 61 and p == pytest.approx(sps.chi2.sf(np.sum(z * z), 61), rel=1e-10)
    res.p = 100  # more parameters than blocks: one degree of freedom, not zero or negative
    assert block_means(model, res)[1] == 1


def test_block_means_count_a_run_that_holds_exactly_one_block():
    """Two runs of 7 samples, m = 5: one block in each (its last 2 samples in none), 2 blocks on 2 - p dof."""
    r = np.random.default_rng(5).normal(size=14)
    model = SimpleNamespace(data=SimpleNamespace(n=14, groups={"a": np.arange(7), "b": np.arange(7, 14)}),
                            channels=[SimpleNamespace(role="output")], row_channel=np.zeros(14, dtype=int),
                            row_point=np.arange(14))
    chi2, dof, _ = block_means(model, SimpleNamespace(rows=np.ones(14, dtype=bool), r=r, p=1))
    assert chi2 == pytest.approx((r[:5].sum() ** 2 + r[7:12].sum() ** 2) / 5, rel=RTOL) and dof == 1


def _time_model(e, u, sigma_y, sigma_u, dt, p):
    """A time series of one run: an output channel y (residuals e) and an imposed input u (measured values
    u, residuals 0.3 u / sigma), as lack_of_fit reads a Model and a FitResult."""
    n = e.size
    r = np.concatenate([e, 0.3 * u / sigma_u])
    model = SimpleNamespace(
        channels=[SimpleNamespace(name="y", role="output"), SimpleNamespace(name="u", role="input")],
        row_channel=np.repeat([0, 1], n), row_point=np.tile(np.arange(n), 2), sigma=np.array([sigma_y, sigma_u]),
        exp=SimpleNamespace(inputs=[SimpleNamespace(name="u")]),
        data=SimpleNamespace(kind="time", n=n, t=np.arange(n) * dt, groups={"run": np.arange(n)}, measured={"u": u}))
    chi2 = float(r @ r)
    J = np.random.default_rng(9).normal(size=(2 * n, p))
    res = SimpleNamespace(rows=np.ones(2 * n, dtype=bool), r=r, J=J, chi2=chi2, p=p, nu=2 * n - p,
                          reduced=chi2 / (2 * n - p))
    return model, res


def test_lack_of_fit_shares_nu_by_rows_and_reads_rmse_in_si():
    """Per channel: chi^2_c / (n_c nu / n), RMSE = sqrt(mean((r sigma)^2)) in SI; the whole fit's p-value is
    chi^2 on nu = n - p; the output's Ljung-Box is the textbook Q (one run, h = min(20, n // 5)), its
    cross-correlation with the input the sample coefficient, at a lag in seconds, against 2.58 / sqrt(n_c)."""
    rng = np.random.default_rng(4)
    n, p, dt = 60, 4, 0.02
    u = rng.normal(size=n)
    e = 0.8 * np.roll(u, 3) + rng.normal(size=n)  # e(k) follows u(k - 3): lag +3 samples
    model, res = _time_model(e, u, sigma_y=2e5, sigma_u=1e-4, dt=dt, p=p)
    lof = lack_of_fit(model, res)
    nu = 2 * n - p
    assert (lof.n, lof.p, lof.nu) == (2 * n, p, nu)
    assert lof.p_value == pytest.approx(sps.chi2.sf(res.chi2, nu), rel=1e-10)
    y, ui = lof.channels
    for c, rc, sigma in ((y, e, 2e5), (ui, 0.3 * u / 1e-4, 1e-4)):
        assert c.n == n and c.chi2 == pytest.approx(np.sum(rc ** 2), rel=RTOL)
        assert c.reduced == pytest.approx(np.sum(rc ** 2) / (n * nu / (2 * n)), rel=RTOL)
        assert c.rmse == pytest.approx(np.sqrt(np.mean((rc * sigma) ** 2)), rel=RTOL)
        assert c.sigma == sigma
    assert y.ljung_box == pytest.approx(_textbook_ljung_box(e, 12), rel=RTOL)
    assert y.ljung_box_p == pytest.approx(sps.chi2.sf(_textbook_ljung_box(e, 12), 12), rel=1e-10)
    assert y.xcorr_max == pytest.approx(_rho(e, u, 3), rel=RTOL)
    assert y.xcorr_lag == pytest.approx(3 * dt, rel=RTOL)
    assert y.xcorr_bound == pytest.approx(2.58 / np.sqrt(n), rel=RTOL)
    assert ui.ljung_box is None and ui.xcorr_max is None  # an imposed input is not tested for colour
    m = 5  # max(5, 60 // 64)
    z = e.reshape(n // m, m).sum(axis=1) / np.sqrt(m)
    assert lof.blocks_chi2 == pytest.approx(np.sum(z * z), rel=RTOL) and lof.blocks_dof == n // m - p


def test_significant_holds_every_test_at_alpha_over_their_number():
    """Bonferroni: chi^2, block means, Ljung-Box of 2 channels, structure of 1, drift of 1 = 6 tests, each held
    at 0.01 / 6 = 1.667e-3: a p of 1.6e-3 is a reason, one of 1.7e-3 is not (it would be at 0.01 / 5)."""
    a = ChannelStats("a", "output", 50, 1.0, 1.0, 50.0, 1.0, ljung_box=3.0, ljung_box_p=0.5)
    b = ChannelStats("b", "output", 50, 1.0, 1.0, 50.0, 1.0, ljung_box=3.0, ljung_box_p=0.5, structure=1.0,
                     structure_dof=2, structure_p=0.5)
    lof = LackOfFit(100.0, 100, 2, 98, 1.02, 0.5, [a, b], drift={"k": {"p_value": 0.5}}, blocks_chi2=10.0,
                    blocks_dof=8, blocks_p=0.5)
    assert lof.significant() == []
    for setter, word in ((lambda v: setattr(lof, "p_value", v), "chi^2/nu"),
                         (lambda v: setattr(lof, "blocks_p", v), "slow misfit"),
                         (lambda v: setattr(a, "ljung_box_p", v), "not white"),
                         (lambda v: setattr(b, "structure_p", v), "follow its fitted value"),
                         (lambda v: lof.drift["k"].update(p_value=v), "drifts")):
        setter(1.7e-3)
        assert lof.significant() == [], word
        setter(1.6e-3)
        (reason,) = lof.significant()
        assert word in reason
        setter(0.5)
    lof.drift["k"]["p_value"] = None  # a drift without a test (fewer than 2 usable groups) counts no test
    b.structure_p = 1.9e-3  # 5 tests: level 2e-3
    assert len(lof.significant()) == 1


def test_overstated_noise_uses_the_lower_tail_of_the_channels_share_of_nu():
    """A channel is named when chi^2/nu < 1/2 and chi^2 lies in the lower tail of chi^2 on its share of nu
    (chi^2 / (chi^2/nu)) below alpha / (number of outputs). Here 2 outputs, alpha 1e-3: the level is 5e-4.
    With dof 40 the cdf crosses 5e-4 near chi^2 = 15.2: chosen on either side from scipy's chi2.ppf."""
    level = 1e-3 / 2
    dof = 40
    edge = sps.chi2.ppf(level, dof)
    below, above = 0.97 * edge, 1.03 * edge  # cdf 3.6e-4 and 6.9e-4: 3 % either side is well clear of the edge

    def lof_with(chi2):
        x = ChannelStats("x", "output", dof, 1.0, 1.0, chi2, chi2 / dof)
        other = ChannelStats("o", "output", dof, 1.0, 1.0, float(dof), 1.0)
        return LackOfFit(0.0, 0, 0, 0, 1.0, 0.5, [x, other])

    assert sps.chi2.cdf(below, dof) < level < sps.chi2.cdf(above, dof)
    assert [c.name for c in lof_with(below).overstated_noise()] == ["x"]
    assert lof_with(above).overstated_noise() == []
    assert [c.name for c in lof_with(0.0).overstated_noise()] == ["x"]  # a channel fitted exactly
    x = ChannelStats("x", "output", 1000, 1.0, 1.0, 500.0, 0.5)  # exactly 1/2, far in the tail: not below 1/2
    assert sps.chi2.cdf(500.0, 1000) < 1e-30
    assert LackOfFit(0.0, 0, 0, 0, 1.0, 0.5, [x]).overstated_noise() == []


def _drift_model(groups, lo=-10.0, hi=10.0):
    """A model with one global k (entry 0) and no latent inputs, as drift() reads it."""
    layout = SimpleNamespace(index=lambda name: 0, inputs=[], globals=[SimpleNamespace(run=None)],
                             latent_index=lambda k, i: None)
    return SimpleNamespace(data=SimpleNamespace(groups=groups), layout=layout,
                           bounds=lambda: (np.array([lo]), np.array([hi])), rows_of_points=lambda pts: pts)


def test_drift_homogeneity_chi2_against_the_inverse_variance_mean(monkeypatch):
    """Each group's refit (replaced here by given estimates and SEs) enters chi^2 = sum (theta_g - theta_w)^2
    / se_g^2 with theta_w = sum(theta/se^2) / sum(1/se^2), on G - 1 dof; a group at a bound is left out."""
    est = {"a": (1.00, 0.10), "b": (1.30, 0.05), "c": (0.80, 0.20), "d": (10.0, 0.1)}  # d ends at the bound 10
    groups = {g: np.array([i]) for i, g in enumerate(est)}
    calls = iter(est.values())

    def fake_fit(model, x, active, rows, max_nfev=30):
        value, se = next(calls)
        return SimpleNamespace(x=np.array([value]), se=np.array([se]))

    monkeypatch.setattr(st, "fit", fake_fit)
    res = SimpleNamespace(x=np.array([1.1]), se=np.array([0.04]))
    d = st.drift(_drift_model(groups), res, ["k"])["k"]
    theta = np.array([1.0, 1.3, 0.8])
    se = np.array([0.1, 0.05, 0.2])
    w = 1 / se ** 2
    mean = np.sum(w * theta) / np.sum(w)
    chi2 = np.sum(w * (theta - mean) ** 2)
    assert d["at_bound"] == [False, False, False, True]
    assert d["weighted_mean"] == pytest.approx(mean, rel=RTOL)
    assert d["chi2"] == pytest.approx(chi2, rel=RTOL) and d["dof"] == 2
    assert d["p_value"] == pytest.approx(sps.chi2.sf(chi2, 2), rel=1e-10)
    assert d["spread"] == pytest.approx(10.0 - 0.8, rel=RTOL)  # the spread keeps every group, bound or not


def test_drift_marks_an_estimate_within_1e_6_of_the_span_from_a_bound(monkeypatch):
    """'At a bound': within 1e-6 of the bounds' span (20 here: 2e-5) of either bound; 1e-4 from it is not."""
    est = [(-10.0 + 1e-5, 0.1), (10.0 - 1e-4, 0.1), (0.5, 0.1), (10.0 - 1e-5, 0.1)]
    calls = iter(est)
    monkeypatch.setattr(st, "fit", lambda *a, **k: (lambda v: SimpleNamespace(x=np.array([v[0]]),
                                                                            se=np.array([v[1]])))(next(calls)))
    groups = {g: np.array([i]) for i, g in enumerate("abcd")}
    d = st.drift(_drift_model(groups), SimpleNamespace(x=np.array([0.0]), se=np.array([0.1])), ["k"])["k"]
    assert d["at_bound"] == [True, False, False, True]
    assert d["dof"] == 1


def _steady_model(y_fit, y_meas, sigma, extra=None):
    """A steady fit with output channel p (rows 0..n-1, fitted values y_fit) and, with ``extra``, a second
    output channel q measured at one point only (residual ``extra``)."""
    n = y_fit.size
    r = (y_fit - y_meas) / sigma
    channels = [SimpleNamespace(name="p", role="output")]
    row_channel, row_point, measured, row_sigma = np.zeros(n, int), np.arange(n), y_meas, np.full(n, sigma)
    if extra is not None:
        channels.append(SimpleNamespace(name="q", role="output"))
        row_channel, row_point = np.append(row_channel, 1), np.append(row_point, 0)
        measured, row_sigma, r = np.append(measured, 0.0), np.append(row_sigma, 1.0), np.append(r, extra)
    J = np.column_stack([np.ones(r.size), np.arange(r.size, dtype=float)])
    model = SimpleNamespace(channels=channels, row_channel=row_channel, row_point=row_point, measured=measured,
                            row_sigma=row_sigma, sigma=np.array([sigma, 1.0][:len(channels)]),
                            data=SimpleNamespace(kind="steady"))
    chi2 = float(r @ r)
    res = SimpleNamespace(rows=np.ones(r.size, bool), r=r, J=J, chi2=chi2, p=2, nu=r.size - 2,
                          reduced=chi2 / (r.size - 2))
    return model, res


def test_steady_lack_of_fit_tests_structure_and_keeps_a_channel_of_one_row():
    """Steady data: the output gets the structure test (6 points, degree + 3, is enough for the cubic) and
    no Ljung-Box; a channel measured at a single point is listed with its chi^2 on its share 1 * nu / n."""
    y = np.array([1.0, 1.4, 2.1, 2.9, 4.2, 5.0])
    meas = y + np.array([0.3, -0.2, 0.1, 0.25, -0.3, 0.05])
    model, res = _steady_model(y, meas, 0.2, extra=1.5)
    lof = lack_of_fit(model, res)
    p, q = lof.channels
    assert p.n == 6 and p.structure_dof is not None and p.ljung_box is None and lof.blocks_chi2 is None
    assert q.n == 1 and q.chi2 == 2.25 and q.reduced == pytest.approx(2.25 / (1 * 5 / 7), rel=RTOL)


def test_structure_test_reads_fitted_values_within_1e_6_sigma_as_constant():
    """Fitted values that span 1e-7 of the noise sigma (1e5 Pa) do not vary: no test; 1e-5 of it do."""
    from blocks.calibrate.fit import column_space
    from blocks.calibrate.stats import structure

    meas = 3e6 + 1e5 * np.random.default_rng(1).normal(size=9)
    for span, tested in ((1e-2, False), (1.0, True)):
        model, res = _steady_model(3e6 + span * np.linspace(0.0, 1.0, 9), meas, 1e5)
        assert (structure(model, res, 0, column_space(res.J)[2])[0] is not None) == tested, span
