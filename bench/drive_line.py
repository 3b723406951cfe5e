"""Drive-line speed benchmark: vphs vs hand-written numba/solve_ivp vs bdsim.

The circuit, equations, sign conventions and solver tolerances are described
in `drive_line_reference.py`.  For each line volume V in (1e-3, 2e-5) m^3:

* hand-written variants: numba rhs with solve_ivp LSODA and BDF, each with
  finite-difference and with the analytic numba Jacobian; rtol 1e-6 and the
  per-state atol vector `drive_line_reference.ATOL` (numba compiled before
  timing, best of up to 5 repeats);
* bdsim 1.4 block diagram with its default solver (RK45, max_step T/100),
  rtol 1e-6 and the same atol; the time is that of `sim.run` (diagram build
  and compile excluded, shown separately);
* vphs through `run_vphs(V)` (plugged in by the lead), printed LAST.

Errors are the maximum deviation from the Radau reference (rtol 1e-10) on the
common 1 ms grid: bridge position in mm, pA in bar.

Run: python bench/drive_line.py
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import drive_line_reference as ref  # noqa: E402

VOLUMES = (1e-3, 2e-5)
NETLIST = os.path.join(ROOT, "netlists", "examples", "drive_line.yaml")


def run_vphs(V: float):
    """Simulate the drive line with vphs.

    Must return (t, x_bridge [m], pA [Pa], seconds) where seconds is the wall
    time of the simulation itself (model build excluded or included: say so
    when plugging in).  t should be the 1 ms grid `ref.T_EVAL` (otherwise the
    result is interpolated onto it).
    """
    from blocks.circuit import Circuit

    global _CIRCUIT
    if _CIRCUIT is None:  # built (and compiled or loaded from cache) once, outside the timing
        _CIRCUIT = Circuit.from_file(os.path.join(ROOT, "netlists", "examples", "drive_line.yaml"))
        _CIRCUIT.simulate({"V_line": V})
    overrides = {"V_line": V}
    seconds, result = _best_time(lambda: _CIRCUIT.simulate(overrides))
    RHS_CALLS["vphs"] = result.stats["rhs_calls"]
    return result.t, result["x"], result["pA"], seconds


_CIRCUIT = None
RHS_CALLS: dict[str, int] = {}
RATIOS: dict[float, float] = {}

HANDWRITTEN_FOR_RODAS = """
from drive_line_reference import rhs as _hand_rhs, R_BRIDGE as _R


@njit(cache=True)
def rhs(t, x, th, dx):
    dx[:] = _hand_rhs(t, x, th)


@njit(cache=True)
def observe(t, x, th, y):
    y[0] = x[5] * _R
    y[1] = x[2]
"""


def run_handwritten_rodas(V: float):
    """The hand-written rhs (bench/drive_line_reference.py) under vphs's compiled Rodas4P2, with the
    hand-written variants' tolerances: the difference to `vphs` is the cost of the generated rhs."""
    from blocks.circuit import cache_dir
    from blocks.solve.generated import build_module

    module = build_module(HANDWRITTEN_FOR_RODAS, cache_dir(), "bench_handwritten_drive_line")
    p = ref.make_params(V)
    y0 = ref.y0() if hasattr(ref, "y0") else np.array([0.0, 0.0, 20e5, 20e5, 0.0, 0.0])
    n = len(y0)
    args = (y0, p, ref.T_EVAL, np.zeros(0), ref.RTOL, ref.ATOL, 0.0, 0.0, 10**7, 0.0, np.ones((n, n), dtype=np.bool_),
            np.arange(n, dtype=np.int64), n, 2)
    module.integrate(*args)  # compile or load from cache outside the timing
    seconds, out = _best_time(lambda: module.integrate(*args))
    status, _, _, X, Y, _, _, stats, _ = out
    assert status == 0, status
    RHS_CALLS["handwritten"] = int(stats[2])
    return ref.T_EVAL, Y[:, 0], Y[:, 1], seconds


def _best_time(fn, max_repeats=5, budget_s=2.0):
    """Run fn() up to max_repeats times (stop when budget is used); best time and last result."""
    best = np.inf
    res = None
    spent = 0.0
    for _ in range(max_repeats):
        t0 = time.perf_counter()
        res = fn()
        dt = time.perf_counter() - t0
        best = min(best, dt)
        spent += dt
        if spent > budget_s:
            break
    return best, res


def _on_grid(t, v):
    t = np.asarray(t, dtype=float)
    v = np.asarray(v, dtype=float)
    if len(t) == len(ref.T_EVAL) and np.max(np.abs(t - ref.T_EVAL)) < 1e-9:
        return v
    return np.interp(ref.T_EVAL, t, v)


def _errors(t, x_b, pA, xb_ref, pA_ref):
    e_x = np.max(np.abs(_on_grid(t, x_b) - xb_ref)) * 1e3
    e_p = np.max(np.abs(_on_grid(t, pA) - pA_ref)) / 1e5
    return e_x, e_p


def _line(name, seconds, e_x, e_p, extra=""):
    print(f"  {name:<28s} {seconds * 1e3:10.2f} ms   err x_b {e_x:9.2e} mm   "
          f"err pA {e_p:9.2e} bar{extra}")


def bench_volume(V: float) -> None:
    print(f"\nV = {V:g} m^3 ({V * 1e3:g} l) per line")
    t0 = time.perf_counter()
    t_r, y_r = ref.reference(V)
    t_ref = time.perf_counter() - t0
    xb_ref = ref.bridge_position(y_r)
    pA_ref = y_r[2]
    vref, xref = ref.reference_profile(t_r, V)
    print(f"  reference Radau rtol 1e-10: {t_ref:.2f} s; x_b(3 s) = {xb_ref[-1]:.4f} m, "
          f"max tracking error {np.max(np.abs(xref - xb_ref)) * 1e3:.2f} mm, "
          f"pA {pA_ref.min() / 1e5:.1f}..{pA_ref.max() / 1e5:.1f} bar, "
          f"pB {y_r[3].min() / 1e5:.1f}..{y_r[3].max() / 1e5:.1f} bar")

    fastest = np.inf
    for method in ("LSODA", "BDF"):
        for use_jac in (False, True):
            name = f"hand-written {method}" + (" +jac" if use_jac else "")
            ref.solve_handwritten(V, method, use_jac)  # warm-up (scipy paths)
            sec, (t, y) = _best_time(lambda: ref.solve_handwritten(V, method, use_jac))
            fastest = min(fastest, sec)
            _line(name, sec, *_errors(t, ref.bridge_position(y), y[2], xb_ref, pA_ref))

    try:
        import drive_line_bdsim as bds
    except Exception as exc:  # pragma: no cover
        print(f"  bdsim: not available ({type(exc).__name__}: {exc})")
    else:
        bds.build(V)  # warm-up: loads bdsim's block library once
        best, res = np.inf, None
        for _ in range(3):
            t, x_b, pA, info = bds.run_bdsim(V)
            if info["run_s"] < best:
                best, res = info["run_s"], (t, x_b, pA, info)
            if info["run_s"] > 1.0:
                break
        t, x_b, pA, info = res
        _line("bdsim (default RK45)", best, *_errors(t, x_b, pA, xb_ref, pA_ref),
              f"   [{info['ydot_calls']} rhs calls, solve_ivp {info['integrator_s'] * 1e3:.0f} ms,"
              f" build+compile {info['build_s'] * 1e3:.0f} ms]")

    try:
        t, x_b, pA, sec = run_handwritten_rodas(V)
    except Exception as exc:
        print(f"  hand-written rhs + vphs Rodas4P2: not available ({type(exc).__name__}: {exc})")
    else:
        calls = RHS_CALLS["handwritten"]
        _line("hand-written rhs + Rodas4P2", sec, *_errors(t, x_b, pA, xb_ref, pA_ref),
              f"   [{calls} rhs calls, {sec / calls * 1e6:.3f} us per call incl. solver work]")

    try:
        t, x_b, pA, sec = run_vphs(V)
    except NotImplementedError as exc:
        print(f"  vphs: not available ({exc})")
    except Exception as exc:
        print(f"  vphs: not available ({type(exc).__name__}: {exc})")
    else:
        calls = RHS_CALLS["vphs"]
        print(f"  vphs: {calls} rhs calls, {sec / calls * 1e6:.3f} us per call incl. solver work "
              f"(tighter pressure atol than the hand-written variants: 0.1 Pa vs 20 Pa)")
        _line("vphs", sec, *_errors(t, x_b, pA, xb_ref, pA_ref))
        RATIOS[V] = sec / fastest
        print(f"  ratio vphs / fastest hand-written (solve_ivp) = {sec / fastest:.2f}")


def bench_cli() -> None:
    rel = os.path.relpath(NETLIST, ROOT)
    if not os.path.exists(NETLIST):
        print(f"\nvphs CLI: {rel} is missing, not timed")
        return
    exe = shutil.which("vphs")
    cmd = [exe, "run", rel] if exe else [sys.executable, "-m", "vphs", "run", rel]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    sec = time.perf_counter() - t0
    shown = " ".join(["vphs" if exe else "python -m vphs", "run", rel])
    if proc.returncode != 0:
        tail = (proc.stderr or proc.stdout).strip().splitlines()[-1:] or [""]
        print(f"\nvphs CLI: `{shown}` failed (exit {proc.returncode}, {sec:.2f} s): {tail[0]}")
    else:
        print(f"\nvphs CLI: fresh process `{shown}`: {sec:.2f} s wall")


def main() -> None:
    import platform

    import numba
    import scipy

    print(f"drive-line benchmark  (python {platform.python_version()}, numpy {np.__version__}, "
          f"scipy {scipy.__version__}, numba {numba.__version__})")
    print(f"  rtol {ref.RTOL:g}, atol {ref.ATOL.tolist()} "
          f"[x_spool, v_spool, pA Pa, pB Pa, omega, theta]; output grid 1 ms")
    t0 = time.perf_counter()
    ref.warmup()
    print(f"  numba warm-up (compile or cache load): {time.perf_counter() - t0:.2f} s")
    for V in VOLUMES:
        bench_volume(V)
    bench_cli()
    print("\ntarget: vphs within 1.5x of the fastest hand-written variant, at equal or better accuracy")
    for V, ratio in RATIOS.items():
        print(f"ratio vphs / hand-written, V = {V * 1e3:g} l: {ratio:.2f}")


if __name__ == "__main__":
    main()
