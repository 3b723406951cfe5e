"""Tests for the compiled Rodas4P2 integrator (blocks/solve/rosenbrock.py) and the module
builder (blocks/solve/generated.py).

All problems live in ONE generated module (the rhs switches on theta[0]), so the whole
file pays for a single cold numba compilation (~8 s here); everything else runs warm.
"""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from blocks.solve.generated import FOOTER, HEADER, build_module

REPO = Path(__file__).resolve().parents[2]

# Problem bank: theta[0] selects the problem, theta[1:] are its parameters.
BANK = textwrap.dedent('''
    @njit(cache=True)
    def rhs(t, x, theta, dx):
        p = int(theta[0])
        n = x.shape[0]
        if p == 0:      # decay, x' = -k x
            for i in range(n):
                dx[i] = -theta[1] * x[i]
        elif p == 1:    # logistic, x' = r x (1 - x)
            for i in range(n):
                dx[i] = theta[1] * x[i] * (1.0 - x[i])
        elif p == 2:    # Robertson chemical kinetics
            dx[0] = -0.04 * x[0] + 1e4 * x[1] * x[2]
            dx[2] = 3e7 * x[1] * x[1]
            dx[1] = -dx[0] - dx[2]
        elif p == 3:    # linear, x' = A x with A row-major in theta[1:]
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += theta[1 + i * n + j] * x[j]
                dx[i] = s
        elif p == 4:    # 1-D diffusion + cubic sink, zero Dirichlet ends (tridiagonal)
            D = theta[1]
            for i in range(n):
                left = x[i - 1] if i > 0 else 0.0
                right = x[i + 1] if i < n - 1 else 0.0
                dx[i] = D * (left - 2.0 * x[i] + right) - x[i] ** 3
        elif p == 5:    # blow-up at t = 1/x0
            for i in range(n):
                dx[i] = x[i] * x[i]
        elif p == 6:    # harmonic oscillator, omega = theta[1]
            dx[0] = x[1]
            dx[1] = -theta[1] * theta[1] * x[0]
        elif p == 7:    # Prothero-Robinson x' = lam (x - sin t) + cos t, exact x = sin t
            dx[0] = theta[1] * (x[0] - math.sin(t)) + math.cos(t)
        elif p == 8:    # derivative is NaN once x < 0 (x' = -sqrt(x) - 1)
            dx[0] = -math.sqrt(x[0]) - 1.0
        elif p == 10:   # pulse: x' = q on [t_a, t_b), else 0 (theta = q, t_a, t_b)
            dx[0] = theta[1] if theta[2] <= t < theta[3] else 0.0
        else:           # always NaN
            for i in range(n):
                dx[i] = math.nan


    @njit(cache=True)
    def observe(t, x, theta, y):
        for i in range(y.shape[0]):
            y[i] = 2.0 * x[i % x.shape[0]] + t
''')

DECAY, LOGISTIC, ROBERTSON, LINEAR, DIFFUSION, BLOWUP, OSCILLATOR, PROTHERO, SQRT_NAN, ALL_NAN, PULSE = range(11)


def _call(mod, prob, x0, params, t_out, rtol=1e-6, atol=1e-9, h0=0.0, h_max=0.0,
          max_steps=100_000, fixed_h=0.0, pattern=None, groups=None, n_obs=1, t_stops=()):
    x0 = np.ascontiguousarray(x0, dtype=np.float64)
    n = x0.shape[0]
    theta = np.array([prob, *np.ravel(params)], dtype=np.float64)
    # np.array(..., copy) keeps every array writable and C-contiguous: a read-only array
    # (e.g. a broadcast view) is a different numba signature and costs a second compilation
    atol = np.array(np.broadcast_to(np.asarray(atol, dtype=np.float64), (n,)))
    if pattern is None:
        pattern = np.ones((n, n), dtype=np.bool_)
        groups = np.arange(n, dtype=np.int64)
    n_groups = int(groups.max()) + 1 if n else 0
    out = mod.integrate(x0, theta, np.ascontiguousarray(t_out, dtype=np.float64),
                        np.array(t_stops, dtype=np.float64), float(rtol),
                        atol, float(h0), float(h_max), int(max_steps), float(fixed_h),
                        np.ascontiguousarray(pattern, dtype=np.bool_),
                        np.ascontiguousarray(groups, dtype=np.int64), n_groups, int(n_obs))
    names = ("status", "t", "x", "X", "Y", "x_min", "x_max", "stats", "bad")
    return SimpleNamespace(**dict(zip(names, out)))


@pytest.fixture(scope="session")
def bank(tmp_path_factory):
    cache = tmp_path_factory.mktemp("rosenbrock_cache")
    t0 = time.perf_counter()
    mod = build_module(BANK, cache, "rosbank")
    t1 = time.perf_counter()
    _call(mod, DECAY, [1.0], [1.0], [0.0, 1.0])     # compiles (cold: empty cache dir)
    t2 = time.perf_counter()
    return SimpleNamespace(mod=mod, cache=cache, import_s=t1 - t0, cold_call_s=t2 - t1,
                           run=lambda *a, **k: _call(mod, *a, **k))


# --------------------------------------------------------------------------- builder
def test_build_module(bank):
    src = FOOTER
    assert "def integrate(" in src
    assert "def rhs(" not in src and "def observe(" not in src
    files = sorted(bank.cache.glob("rosbank_*.py"))
    assert len(files) == 1
    stem = files[0].stem
    assert len(stem.split("_")[-1]) == 16
    text = files[0].read_text()
    assert text.startswith(HEADER) and text.endswith(src) and BANK in text
    mtime = files[0].stat().st_mtime_ns
    again = build_module(BANK, bank.cache, "rosbank")
    assert again is bank.mod
    assert files[0].stat().st_mtime_ns == mtime        # not rewritten
    assert not list(bank.cache.glob("*.tmp"))
    # the compiled code was cached on disk next to the generated file
    assert list((bank.cache / "__pycache__").glob(f"{stem}.rhs_c-*.nbi"))


def test_new_process_loads_compiled_code_from_disk(bank):
    """A new process with the same cache dir compiles nothing: numba loads the circuit's C callbacks and
    the shared integrator from its disk cache (checked with numba's cache log, not with a timing)."""
    script = textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {str(REPO)!r})
        sys.path.insert(0, {str(Path(__file__).parent)!r})
        from test_rosenbrock import BANK, _call
        from blocks.solve.generated import build_module
        mod = build_module(BANK, {str(bank.cache)!r}, "rosbank")
        r = _call(mod, 0, [1.0], [1.0], [0.0, 1.0])
        assert r.status == 0
    """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1", "NUMBA_DEBUG_CACHE": "1"})
    assert out.returncode == 0, out.stderr
    assert "Cannot cache" not in out.stderr
    log = out.stdout
    assert "data saved" not in log, log
    assert "rhs_c" in log and "integrate" in log and "data loaded" in log, log


# --------------------------------------------------------------------------- accuracy
def test_exponential_decay(bank):
    t = np.linspace(0.0, 2.0, 21)
    r = bank.run(DECAY, [1.0, 2.0], [0.7], t, rtol=1e-8, atol=1e-12, n_obs=2)
    assert r.status == 0 and r.bad == -1 and r.t == 2.0
    exact = np.exp(-0.7 * t)[:, None] * np.array([1.0, 2.0])
    assert np.max(np.abs(r.X - exact) / exact) < 1e-7
    assert np.allclose(r.x, r.X[-1], rtol=0, atol=0)
    np.testing.assert_allclose(r.Y, 2.0 * r.X + t[:, None], rtol=1e-15)
    n_acc, n_rej, n_rhs, n_jac, n_lu = r.stats
    assert 5 < n_acc < 200 and n_jac == n_acc and n_lu == n_acc + n_rej
    # f(t0) and the h0 heuristic (2), 5 stages per attempt, f at each accepted point,
    # and per Jacobian one call per column group (2) plus one for df/dt
    assert n_rhs == 2 + 5 * (n_acc + n_rej) + n_acc + 3 * n_jac


@pytest.mark.parametrize("prob,params,x0,T,exact,order", [
    (LOGISTIC, [1.0], [0.01], 8.0, lambda t: 1.0 / (1.0 + 99.0 * np.exp(-t)), 4.0),
    # non-autonomous: checks the h d_i f_t terms
    (PROTHERO, [-2.0], [0.0], 2.0, np.sin, 4.0),
    # stiff Prothero-Robinson: Rodas4 falls to order ~1 here, Rodas4P2 keeps ~3 (measured)
    (PROTHERO, [-1e4], [0.0], 2.0, np.sin, 3.0),
])
def test_convergence_order(bank, prob, params, x0, T, exact, order):
    hs = np.array([0.2, 0.1, 0.05, 0.025])
    errs, dense_errs = [], []
    for h in hs:
        t = np.linspace(0.0, T, 4 * int(round(T / h)) + 1)       # 3 outputs inside each step
        r = bank.run(prob, x0, params, t, fixed_h=h)
        assert r.status == 0 and r.stats[0] == round(T / h) and r.stats[1] == 0 and r.t == T
        errs.append(abs(r.x[0] - exact(T)))
        dense_errs.append(np.max(np.abs(r.X[:, 0] - exact(t))))
    p = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    p_dense = np.polyfit(np.log(hs), np.log(dense_errs), 1)[0]
    print(f"\nmeasured order (problem {prob}, {params}): end point {p:.2f}, dense output "
          f"{p_dense:.2f}; end-point errors {np.array(errs)}")
    assert abs(p - order) < 0.5
    assert p_dense > 3.5           # order-3 interpolant: local error O(h^4)


def test_fixed_step_lands_on_final_time(bank):
    r = bank.run(DECAY, [1.0], [1.0], [0.0, 0.5, 1.0], fixed_h=0.3)
    assert r.status == 0 and r.t == 1.0 and r.stats[0] == 4 and r.stats[1] == 0
    assert abs(r.x[0] - np.exp(-1.0)) < 1e-4


def test_a_pulse_between_steps_is_integrated_when_its_ends_are_stops(bank):
    # at rest the step grows to the run's length, and a pulse shorter than a step falls between its
    # stages: x stays 0. Ending steps on the pulse's ends integrates it exactly (x' is constant on it, and a
    # step ending on t_b evaluates its last stages just before t_b, where the pulse is still on).
    q, t_a, t_b = 3.0, 2.23, 2.235
    t = np.linspace(0.0, 5.0, 11)
    missed = bank.run(PULSE, [0.0], [q, t_a, t_b], t)
    assert missed.status == 0 and missed.x[0] == 0.0  # the failure the stops are for
    for stops in ([t_a, t_b], [-1.0, 0.0, t_a, t_a, t_b, 5.0, 7.0]):  # outside, at the ends, repeated
        r = bank.run(PULSE, [0.0], [q, t_a, t_b], t, t_stops=stops)
        assert r.status == 0 and r.t == 5.0
        assert r.x[0] == pytest.approx(q * (t_b - t_a), rel=1e-12)
        np.testing.assert_allclose(r.X[:, 0], q * np.clip(t - t_a, 0.0, t_b - t_a), rtol=1e-12, atol=1e-15)
        assert r.stats[0] < 40, r.stats  # the steps after a stop are not shortened by it


def test_a_step_ended_on_a_stop_keeps_its_accuracy_and_pace(bank):
    # a smooth problem with stops that mean nothing: the same answer, a few steps more
    t = np.linspace(0.0, 2.0, 21)
    plain = bank.run(DECAY, [1.0], [0.7], t, rtol=1e-8, atol=1e-12)
    stopped = bank.run(DECAY, [1.0], [0.7], t, rtol=1e-8, atol=1e-12, t_stops=np.linspace(0.1, 1.9, 7))
    assert stopped.status == 0 and np.max(np.abs(stopped.X[:, 0] - np.exp(-0.7 * t))) < 1e-8
    assert stopped.stats[0] <= plain.stats[0] + 7


def _robertson_reference(t_eval):
    from scipy.integrate import solve_ivp

    def f(t, y):
        return [-0.04 * y[0] + 1e4 * y[1] * y[2],
                0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] ** 2,
                3e7 * y[1] ** 2]

    def jac(t, y):
        return [[-0.04, 1e4 * y[2], 1e4 * y[1]],
                [0.04, -1e4 * y[2] - 6e7 * y[1], -1e4 * y[1]],
                [0.0, 6e7 * y[1], 0.0]]

    sol = solve_ivp(f, (0.0, t_eval[-1]), [1.0, 0.0, 0.0], method="Radau", rtol=1e-10,
                    atol=1e-14, t_eval=t_eval, jac=jac)
    assert sol.status == 0
    return sol.y.T


def test_robertson_vs_radau(bank):
    t = np.concatenate([[0.0], np.logspace(-5, 5, 41)])
    rtol, atol = 1e-6, np.array([1e-10, 1e-14, 1e-10])
    t0 = time.perf_counter()
    r = bank.run(ROBERTSON, [1.0, 0.0, 0.0], [], t, rtol=rtol, atol=atol)
    wall = time.perf_counter() - t0
    ref = _robertson_reference(t)
    assert r.status == 0 and r.t == 1e5
    print(f"\nRobertson to 1e5: stats {r.stats} (acc, rej, rhs, jac, lu), {wall * 1e3:.1f} ms")
    assert r.stats[0] + r.stats[1] < 400
    # global error within 10x the local tolerance, component-wise
    assert np.all(np.abs(r.X - ref) <= 10.0 * (rtol * np.abs(ref) + atol))
    assert np.max(np.abs(r.X.sum(axis=1) - 1.0)) < 1e-12     # linear invariant


def test_linear_stiff_2x2_vs_expm(bank):
    from scipy.linalg import expm
    lam1, lam2 = -1.0, -1e6
    A = 0.5 * np.array([[lam1 + lam2, lam1 - lam2], [lam1 - lam2, lam1 + lam2]])
    assert np.allclose(np.sort(np.linalg.eigvals(A)), [lam2, lam1])
    t = np.linspace(0.0, 5.0, 51)
    x0 = np.array([1.0, 0.0])
    r = bank.run(LINEAR, x0, A.ravel(), t, rtol=1e-6, atol=1e-10)
    exact = np.array([expm(A * tk) @ x0 for tk in t])
    assert r.status == 0
    print(f"\nstiff 2x2: stats {r.stats}, max error {np.max(np.abs(r.X - exact)):.2e}")
    assert np.max(np.abs(r.X - exact)) < 1e-6
    # an explicit method would need ~2.5e6 steps here. (The forward-difference Jacobian
    # loses ~7e-3 absolute to cancellation in A, which costs steps: 225 attempts measured;
    # central differences gave 91.)
    assert r.stats[0] + r.stats[1] < 1000


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 5))
def test_linear_random_vs_expm(bank, seed, n):
    from scipy.linalg import expm
    rng = np.random.default_rng(seed)
    B = rng.normal(size=(n, n))
    A = -(B @ B.T) - 0.1 * np.eye(n) + 0.5 * (rng.normal(size=(n, n)) - rng.normal(size=(n, n)))
    A -= np.eye(n) * max(0.0, np.max(np.linalg.eigvals(A).real) + 0.1)   # make it stable
    x0 = rng.normal(size=n)
    t = np.linspace(0.0, 3.0, 7)
    r = bank.run(LINEAR, x0, A.ravel(), t, rtol=1e-9, atol=1e-12)
    exact = np.array([expm(A * tk) @ x0 for tk in t])
    assert r.status == 0
    assert np.max(np.abs(r.X - exact)) < 1e-7 * max(1.0, np.max(np.abs(x0)))


# --------------------------------------------------------------------------- dense output
@pytest.mark.parametrize("prob,params,x0,exact,tol", [
    (DECAY, [1.0], [1.0], lambda t: np.exp(-t), 2e-6),
    # stiff, driven by sin(t): the step-end error estimate does not see the interpolation
    # error, so with ~30 steps over [0, 10] the dense output is ~30x the tolerance (measured
    # 2.8e-5; Rodas4 gave 9e-5 with 631 steps)
    (PROTHERO, [-1e3], [0.0], np.sin, 1e-4),
    (OSCILLATOR, [1.0], [1.0, 0.0], np.cos, 2e-5),
])
def test_dense_output(bank, prob, params, x0, exact, tol):
    t = np.linspace(0.0, 10.0, 10_001)           # outputs every 1e-3
    r = bank.run(prob, x0, params, t, rtol=1e-6, atol=1e-9)
    assert r.status == 0
    n_acc = r.stats[0]
    err = np.max(np.abs(r.X[:, 0] - exact(t)))
    print(f"\ndense output problem {prob}: {n_acc} steps for 10001 outputs, max error {err:.2e}")
    assert n_acc < 500                          # steps are not forced onto output times
    assert err < tol
    # extrema cover the interpolant, hence every logged sample
    assert np.all(r.x_min <= r.X.min(axis=0)) and np.all(r.x_max >= r.X.max(axis=0))
    np.testing.assert_allclose(r.Y[:, 0], 2.0 * r.X[:, 0] + t, rtol=1e-14)


def test_no_outputs_between_start_and_end(bank):
    r = bank.run(DECAY, [1.0], [1.0], [0.0, 0.0, 3.0], n_obs=0)
    assert r.status == 0 and r.Y.shape == (3, 0)
    assert r.X[0, 0] == r.X[1, 0] == 1.0
    assert abs(r.X[2, 0] - np.exp(-3.0)) < 1e-5


# --------------------------------------------------------------------------- sparsity
def test_sparse_jacobian_grouping(bank):
    n = 30
    xg = np.linspace(0.0, 1.0, n + 2)[1:-1]
    x0 = np.sin(np.pi * xg) + 0.5 * np.sin(3 * np.pi * xg)
    t = np.linspace(0.0, 0.5, 11)
    params = [(n + 1) ** 2 * 0.1]
    dense = bank.run(DIFFUSION, x0, params, t, rtol=1e-6, atol=1e-9)
    idx = np.arange(n)
    pattern = np.abs(idx[:, None] - idx[None, :]) <= 1
    groups = (idx % 3).astype(np.int64)
    sparse = bank.run(DIFFUSION, x0, params, t, rtol=1e-6, atol=1e-9, pattern=pattern,
                      groups=groups)
    assert dense.status == 0 and sparse.status == 0
    np.testing.assert_allclose(sparse.X, dense.X, rtol=1e-12, atol=1e-14)
    assert sparse.stats[0] == dense.stats[0] and sparse.stats[3] == dense.stats[3]
    n_jac = dense.stats[3]
    # n + 1 (df/dt) rhs calls per Jacobian when dense, 3 + 1 when grouped
    assert dense.stats[2] - sparse.stats[2] == n_jac * (n - 3)
    print(f"\ndiffusion n={n}: rhs calls dense {dense.stats[2]}, grouped {sparse.stats[2]}")


# --------------------------------------------------------------------------- failures
def test_blowup_reports_failure(bank):
    t = np.linspace(0.0, 2.0, 21)
    r = bank.run(BLOWUP, [1.0], [], t, rtol=1e-6, atol=1e-9)
    assert r.status != 0
    assert r.t < 1.0 and r.bad == 0
    assert np.isfinite(r.x[0]) and r.x[0] > 1e3
    assert np.all(np.isfinite(r.X[t <= r.t])) and np.all(np.isnan(r.X[t > r.t]))
    assert np.all(np.isnan(r.Y[t > r.t]))
    np.testing.assert_allclose(r.X[t <= r.t, 0], 1.0 / (1.0 - t[t <= r.t]), rtol=1e-4)


def test_max_steps(bank):
    t = np.linspace(0.0, 10.0, 11)
    r = bank.run(OSCILLATOR, [1.0, 0.0], [20.0], t, rtol=1e-8, max_steps=7)
    assert r.status == 2
    assert r.stats[0] + r.stats[1] == 7
    assert 0.0 < r.t < 10.0 and r.bad in (0, 1)
    assert np.all(np.isnan(r.X[t > r.t]))


def test_nonfinite_derivative(bank):
    r = bank.run(ALL_NAN, [1.0, 2.0], [], [0.0, 1.0])
    assert r.status == 3 and r.bad == 0 and r.t == 0.0
    r = bank.run(DECAY, [1.0, np.nan], [1.0], [0.0, 1.0])
    assert r.status == 3 and r.bad == 1
    # x' = -sqrt(x) - 1 reaches x = 0 near t = 0.6137; past that the derivative is NaN
    t = np.linspace(0.0, 1.0, 11)
    r = bank.run(SQRT_NAN, [1.0], [], t)
    assert r.status == 3 and r.bad == 0
    assert 0.55 < r.t < 0.62 and r.x[0] >= 0.0
    assert np.all(np.isnan(r.X[t > r.t]))


# --------------------------------------------------------------------------- extrema
def test_x_min_catches_dip_between_samples(bank):
    # period 1, sampled once per period: every sample sits at the maximum
    t = np.arange(0.0, 4.0 + 0.5, 1.0)
    r = bank.run(OSCILLATOR, [1.0, 0.0], [2.0 * np.pi], t, rtol=1e-7, atol=1e-10)
    assert r.status == 0
    assert np.all(r.X[:, 0] > 0.999)
    assert abs(r.x_min[0] + 1.0) < 1e-5 and abs(r.x_max[0] - 1.0) < 1e-5
    assert abs(r.x_min[1] + 2.0 * np.pi) < 1e-4 and abs(r.x_max[1] - 2.0 * np.pi) < 1e-4


def test_x_min_no_spurious_undershoot_on_stiff_decay(bank):
    # a fast monotone decay taken with large steps must not report a dip below 0
    A = np.diag([-1e5, -1.0])
    r = bank.run(LINEAR, [1.0, 1.0], A.ravel(), [0.0, 10.0], rtol=1e-4, atol=1e-8)
    assert r.status == 0
    assert r.x_min[0] > -1e-6 and r.x_max[0] == 1.0


# --------------------------------------------------------------------------- arguments
def test_h_max_and_h0(bank):
    r = bank.run(DECAY, [1.0], [1.0], [0.0, 1.0], h_max=0.01)
    assert r.status == 0 and r.stats[0] >= 100
    r = bank.run(DECAY, [1.0], [1.0], [0.0, 1.0], h0=1e-6, rtol=1e-8, atol=1e-12)
    assert r.status == 0 and abs(r.x[0] - np.exp(-1.0)) < 1e-8


def test_invalid_arguments_raise(bank):
    n = 6
    idx = np.arange(n)
    pattern = np.abs(idx[:, None] - idx[None, :]) <= 1
    with pytest.raises(ValueError, match="colouring"):
        bank.run(DIFFUSION, np.ones(n), [1.0], [0.0, 1.0], pattern=pattern,
                 groups=(idx % 2).astype(np.int64))
    with pytest.raises(ValueError, match="sorted"):
        bank.run(DECAY, [1.0], [1.0], [0.0, 2.0, 1.0])


def test_no_states(bank):
    r = bank.run(DECAY, np.zeros(0), [1.0], [0.0, 0.5, 1.0], n_obs=0)
    assert r.status == 0 and r.t == 1.0 and r.X.shape == (3, 0) and r.bad == -1
