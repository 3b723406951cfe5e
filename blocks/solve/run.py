"""Run a compiled circuit with the chosen solver and return the raw trajectories.

- ``rodas`` (default): the compiled Rosenbrock method of :mod:`blocks.solve.rosenbrock`, variable step,
  L-stable (hydraulic circuits are stiff), finite-difference Jacobian grouped by the netlist's sparsity.
- ``fixed``: the same method at a fixed step, no error control (its steps end on the breakpoints too, and
  the run's slices on its grid; :mod:`blocks.solve.step_check` repeats it at twice the step to warn).
- ``lsoda``, ``bdf``, ``radau``: scipy's ``solve_ivp`` on the same compiled rhs, for comparison; BDF and
  Radau receive the Jacobian's sparsity from the netlist graph.
The absolute tolerance of each state is ``atol`` times the state's nominal magnitude (1 bar for a
pressure, 1 rad/s for a speed...), so one number suits states of very different sizes. A generic signal
block's state (a filter's, an integrator's, declared "SI" with nominal 1) has the nominal of the quantity
its signal carries where the netlist fixes it (:mod:`blocks.compiler.signal_scale`, from the table
:data:`blocks.nominal.NOMINAL_MAGNITUDE`: a flow 1e-4 m^3/s, a pressure 1e5 Pa), else its declared one.
Every variable-step solver lands a step on each time an input jumps or kinks (``Circuit.breakpoints``: a
step's time, a profile's points): rodas ends a step there; the scipy solvers are restarted there, at most
100 times a run (:func:`_restarts`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from blocks import interrupt
from blocks.solve.settings import SolverSettings


@dataclass
class Outcome:
    status: int
    t: np.ndarray
    X: np.ndarray
    Y: np.ndarray
    x_min: np.ndarray
    x_end: np.ndarray | None
    t_reached: float
    bad_index: int
    stats: dict


def output_times(settings: SolverSettings) -> np.ndarray:
    n = int(round((settings.t_end - settings.t_start) / settings.dt_out))
    t = settings.t_start + settings.dt_out * np.arange(n + 1)
    if t[-1] < settings.t_end - 1e-12 * max(1.0, abs(settings.t_end)):
        t = np.append(t, settings.t_end)
    t[-1] = settings.t_end
    return t


def nominal_vector(circuit) -> np.ndarray:
    """Each state's nominal magnitude (1 bar for a pressure, 1 rad/s for a speed, a signal block's state
    its signal's: :mod:`blocks.compiler.signal_scale`), SI."""
    return np.concatenate([np.full(s.size, float(s.nominal)) for s in circuit.structure.states]) \
        if circuit.structure.states else np.zeros(0)


def atol_vector(circuit, settings: SolverSettings) -> np.ndarray:
    return settings.atol * nominal_vector(circuit)


def solve(circuit, vec, settings: SolverSettings, progress=None) -> Outcome:
    """``progress(fraction, seconds)``, if given, is called as the run advances (compiled solvers only)."""
    t_out = output_times(settings)
    atol = atol_vector(circuit, settings)
    stops = circuit.breakpoints(vec)
    stops = stops[(stops > t_out[0]) & (stops < t_out[-1])]
    if settings.solver in ("rodas", "fixed"):
        return _solve_compiled(circuit, vec, settings, t_out, stops, atol, progress)
    return _solve_scipy(circuit, vec, settings, t_out, _restarts(stops, t_out[0], t_out[-1]), atol)


SCIPY_RESTARTS = 100  # at most this many restarts of a scipy solver per run


def _restarts(stops: np.ndarray, t_start: float, t_end: float) -> np.ndarray:
    """The stops a scipy solver is restarted at: the first, then each at least (t_end - t_start)/
    SCIPY_RESTARTS after the one kept before it; none within 1e-9 of the run of its start or end. A
    multistep method restarts at order 1, so a restart at each of a recorded profile's 2000 points cost it
    40 times the time and 50 times the error, and two stops one rounding apart left it a span it could not
    step."""
    span = t_end - t_start
    spacing, edge = span / SCIPY_RESTARTS, 1e-9 * span
    kept = []
    for stop in stops:
        if stop - t_start > edge and t_end - stop > edge and (not kept or stop - kept[-1] >= spacing * (1 - 1e-9)):
            kept.append(stop)
    return np.array(kept, dtype=float)


PROGRESS_CHUNKS = 10
STAT_NAMES = ("steps", "rejected", "rhs_calls", "jacobians", "lu")


def _solve_compiled(circuit, vec, settings, t_out, stops, atol, progress) -> Outcome:
    """Consecutive calls of the compiled integrator over PROGRESS_CHUNKS slices of the output times, with
    ``progress`` called after each. Always sliced (with or without a callback) so that a result never
    depends on whether someone watched it; each slice restarts the step-size selection (a few steps)."""
    fixed = settings.fixed_step if settings.solver == "fixed" else 0.0
    n_obs = circuit.n_observed

    def run(x0, times):
        outcome = _integrate(circuit, vec, settings, x0, times, stops, atol, settings.max_steps)
        interrupt.check()  # a Ctrl-C the compiled call swallowed
        return outcome

    if len(t_out) < 2 * PROGRESS_CHUNKS:
        status, t_reached, x_end, X, Y, x_min, _x_max, stats, bad = run(vec.x0, t_out)
        return Outcome(int(status), t_out, X, Y, x_min, x_end, float(t_reached), int(bad),
                       dict(zip(STAT_NAMES, (int(s) for s in stats))))
    import time

    started = time.perf_counter()
    K, n = len(t_out), len(vec.x0)
    X, Y = np.full((K, n), np.nan), np.full((K, n_obs), np.nan)
    x_min, total = vec.x0.copy(), np.zeros(len(STAT_NAMES), dtype=np.int64)
    edges = np.linspace(0, K - 1, PROGRESS_CHUNKS + 1).astype(int)
    if fixed:
        edges = _on_grid(edges, t_out, fixed)
    x = vec.x0.copy()
    status, t_reached, bad = 0, float(t_out[0]), -1
    for a, b in zip(edges[:-1], edges[1:]):
        status, t_reached, x_end, Xc, Yc, xmin_c, _xmax, stats, bad = run(x, t_out[a:b + 1])
        X[a:b + 1], Y[a:b + 1] = Xc, Yc
        np.minimum(x_min, xmin_c, out=x_min)
        total += stats
        x = x_end
        if progress is not None:
            progress(b / (K - 1), time.perf_counter() - started)
        if status != 0:
            break
    return Outcome(int(status), t_out, X, Y, x_min, x, float(t_reached), int(bad),
                   dict(zip(STAT_NAMES, (int(s) for s in total))))


def _integrate(circuit, vec, settings, x0, times, stops, atol, max_steps):
    """One call of the circuit's compiled integrator (the one place its arguments are put together, so that
    :func:`warm_up` calls it with the very types a run does)."""
    fixed = settings.fixed_step if settings.solver == "fixed" else 0.0
    return circuit.module.integrate(x0, vec.theta, times, stops, settings.rtol, atol, 0.0, settings.max_step,
                                    max_steps, fixed, circuit.pattern, circuit.groups, circuit.n_groups,
                                    circuit.n_observed)


def _integrator_ready() -> bool:
    """Whether this process has the shared integrator compiled (or loaded from numba's cache) already."""
    from blocks.solve import rosenbrock

    return bool(rosenbrock.integrate.signatures)


def warm_up(circuit, vec, settings: SolverSettings) -> float:
    """Have numba compile (or load from its disk cache) the shared integrator before a run's clock starts;
    the seconds it took (0 when it was ready, or for the scipy solvers).

    The integrator (:mod:`blocks.solve.rosenbrock`) is compiled on its first call in a process. Inside the
    run, the first slice took those seconds: a progress line read "10 % simulated, 5.1 s elapsed, ~45.7 s
    left" for a run of 21 ms, and the run's time included them. One step from the initial state, with the
    run's own argument types (:func:`_integrate`), compiles it; its result is dropped."""
    if settings.solver not in ("rodas", "fixed") or _integrator_ready():
        return 0.0
    import time

    started = time.perf_counter()
    t0 = settings.t_start
    times = np.array([t0, t0 + min(settings.dt_out, settings.t_end - t0)], dtype=float)
    _integrate(circuit, vec, settings, vec.x0.copy(), times, np.zeros(0), atol_vector(circuit, settings), 1)
    interrupt.check()
    return time.perf_counter() - started


def _on_grid(edges: np.ndarray, t_out: np.ndarray, step: float) -> np.ndarray:
    """The slices' edges moved to the nearest output samples on the fixed step's grid t_out[0] + k*step
    (a slice restarts the grid at its first sample, so an edge off it would add a short step and shift the
    grid after it); none inside if no sample is on it."""
    steps = (t_out - t_out[0]) / step
    on_grid = np.flatnonzero(np.abs(steps - np.round(steps)) <= 1e-9 * np.maximum(1.0, steps))
    inner = [int(on_grid[np.argmin(np.abs(on_grid - e))]) for e in edges[1:-1]] if on_grid.size else []
    return np.unique(np.array([edges[0], *inner, edges[-1]], dtype=int))


class _Stop(Exception):
    def __init__(self, status: int, t: float, index: int):
        self.status, self.t, self.index = status, t, index


def _solve_scipy(circuit, vec, settings, t_out, stops, atol) -> Outcome:
    """scipy's solve_ivp on the compiled rhs, restarted at each stop. A non-finite state, or more rhs calls
    than ``max_steps`` (LSODA can loop for ever near a singularity), stops it with a located failure."""
    from scipy.integrate import solve_ivp

    rhs, observe = circuit.module.rhs, circuit.module.observe
    theta = vec.theta
    n = len(vec.x0)
    calls = [0]
    last_good = [float(t_out[0]), vec.x0.copy()]

    def fun(t, x):
        calls[0] += 1
        if not np.all(np.isfinite(x)):
            raise _Stop(3, last_good[0], int(np.argmax(~np.isfinite(x))))
        if calls[0] > settings.max_steps:
            raise _Stop(2, last_good[0], -1)
        dx = np.empty(n)
        rhs(t, x, theta, dx)
        last_good[0], last_good[1] = t, x
        return dx

    method = {"lsoda": "LSODA", "bdf": "BDF", "radau": "Radau"}[settings.solver]
    options = dict(rtol=settings.rtol, atol=atol, dense_output=True)
    if settings.max_step > 0:
        options["max_step"] = settings.max_step
    if method in ("BDF", "Radau") and n > 0:
        options["jac_sparsity"] = circuit.pattern
    status, t_reached, bad = 0, float(t_out[-1]), -1
    pieces = []  # the solutions between consecutive stops
    edges = np.concatenate([t_out[:1], stops, t_out[-1:]])
    x = vec.x0
    with np.errstate(all="ignore"):
        for start, end in zip(edges[:-1], edges[1:]):
            try:
                sol = solve_ivp(fun, (start, end), x, method=method, **options)
            except _Stop as stop:
                status, t_reached, bad = stop.status, stop.t, stop.index
                break
            except (RuntimeError, ValueError, ZeroDivisionError, np.linalg.LinAlgError):
                status, t_reached = 3, last_good[0]  # e.g. BDF: "Factor is exactly singular"
                break
            pieces.append(sol)
            if sol.status != 0:
                status, t_reached = 1, float(sol.t[-1])
                break
            x = sol.y[:, -1]
    K = len(t_out)
    X = np.full((K, n), np.nan)
    Y = np.full((K, circuit.n_observed), np.nan)
    if pieces:
        end = pieces[-1].t[-1]
        reached = t_out <= end + 1e-12 * max(1.0, abs(end))
        piece_of = np.minimum(np.searchsorted(edges[1:len(pieces) + 1], t_out, side="left"), len(pieces) - 1)
        for k in np.flatnonzero(reached):
            if pieces[piece_of[k]].sol is not None:
                X[k] = pieces[piece_of[k]].sol(t_out[k])
    else:
        X[0] = vec.x0
    m = int(np.sum(np.all(np.isfinite(X), axis=1)))
    for k in range(m):
        observe(t_out[k], X[k], theta, Y[k])
    x_min = np.nanmin(X[:m], axis=0) if m else vec.x0.copy()
    for piece in pieces:  # every step end point, not only the samples (cavitation between them)
        if piece.y.size:
            with np.errstate(all="ignore"):
                x_min = np.fmin(x_min, np.nanmin(piece.y, axis=1))
    x_end = X[m - 1] if m else vec.x0.copy()
    if status != 0:
        x_end = np.asarray(last_good[1], dtype=float)
        if bad < 0 and n:  # name the state that has grown most, relative to its tolerance
            with np.errstate(all="ignore"):
                bad = int(np.argmax(np.abs(np.nan_to_num(x_end, nan=np.inf)) / (atol + 1e-300)))
    stats = {"rhs_calls": calls[0]}
    if pieces:
        stats.update(jacobians=sum(int(p.njev) for p in pieces), lu=sum(int(p.nlu) for p in pieces))
    return Outcome(status, t_out, X, Y, x_min, x_end, t_reached, bad, stats)
