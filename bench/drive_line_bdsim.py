"""The drive-line benchmark circuit as a bdsim 1.4 block diagram.

Same equations, parameters and sign conventions as
`drive_line_reference.py` (see its docstring).  The diagram is built from
bdsim's own blocks:

    TIME -> FUNCTION(ref profile) -> v_ref, x_ref
    GAIN(r) theta -> x_b ; SUM(+-) x_ref - x_b ; GAIN(Kp), GAIN(Kff) ; SUM(++) ; CLIP(-1, 1) -> u
    spool:   SUM(+--) (wn^2 u, wn^2 x, 2 zeta wn v) -> INTEGRATOR v -> INTEGRATOR x
    valve:   FUNCTION(x, pA, pB) -> q_PA, q_AT, q_PB, q_BT
    motor:   FUNCTION(omega, pA, pB) -> q_m ;  FUNCTION(pA, pB, omega) -> net torque
    lines:   SUM(+--) q_PA - q_AT - q_m -> GAIN(beta/V) -> INTEGRATOR pA
             SUM(++-) q_m + q_PB - q_BT -> GAIN(beta/V) -> INTEGRATOR pB
    load:    GAIN(1/J) -> INTEGRATOR omega -> INTEGRATOR theta

Solver: bdsim always uses scipy.integrate.solve_ivp; its default method is
RK45 with max_step = T/100 (both kept).  rtol = 1e-6 and the same per-state
atol vector as the hand-written variants (reordered to bdsim's state order)
are passed through ``solver_args``.  The output grid is requested with
``dt = 1 ms`` (bdsim builds t_eval from it), so no interpolation is needed.
Console output (banner, compile report, progress bar, run report) and
graphics are switched off.
"""

from __future__ import annotations

import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import drive_line_reference as ref  # noqa: E402


def build(V: float):
    """Return (sim, bd, state names in order) for line volume V."""
    import bdsim

    p = ref.make_params(V)
    pS, pT = p[ref.I_PS], p[ref.I_PT]
    dpt2 = p[ref.I_DPT] ** 2
    kA = p[ref.I_CD] * p[ref.I_A0] * math.sqrt(2.0 / p[ref.I_RHO]) / (1.0 - p[ref.I_XDB])
    xdb = p[ref.I_XDB]
    D, leak = p[ref.I_D], p[ref.I_LEAK]
    wn, zeta = p[ref.I_WN], p[ref.I_ZETA]
    fc, wc, b = p[ref.I_FC], p[ref.I_WC], p[ref.I_B]
    vmax, t1, t2, t3 = p[ref.I_VMAX], p[ref.I_T1], p[ref.I_T2], p[ref.I_T3]

    def profile(t):
        a1 = vmax / t1
        a3 = vmax / (t3 - t2)
        x1 = 0.5 * vmax * t1
        x2 = x1 + vmax * (t2 - t1)
        if t <= 0.0:
            return [0.0, 0.0]
        if t <= t1:
            return [a1 * t, 0.5 * a1 * t * t]
        if t <= t2:
            return [vmax, x1 + vmax * (t - t1)]
        if t <= t3:
            tau = t - t2
            return [vmax - a3 * tau, x2 + vmax * tau - 0.5 * a3 * tau * tau]
        return [0.0, x2 + 0.5 * vmax * (t3 - t2)]

    def orifice(k, dp):
        return k * dp / (dp * dp + dpt2) ** 0.25

    def valve(x, pA, pB):
        op = x - xdb
        on = -x - xdb
        kpos = kA * op if op > 0.0 else 0.0
        kneg = kA * on if on > 0.0 else 0.0
        return [orifice(kpos, pS - pA),   # q_PA  P -> A
                orifice(kneg, pA - pT),   # q_AT  A -> T
                orifice(kneg, pS - pB),   # q_PB  P -> B
                orifice(kpos, pB - pT)]   # q_BT  B -> T

    def motor_flow(w, pA, pB):          # A -> motor -> B
        return D * w + leak * (pA - pB)

    def torque(pA, pB, w):
        tau_h = D * (pA - pB)
        return tau_h - b * w - fc * abs(tau_h) * math.tanh(w / wc)

    sim = bdsim.BDSim(banner=False, sysargs=False, toolboxes=False, graphics=False,
                      animation=False, progress=False, quiet=True, hold=False)
    bd = sim.blockdiagram()

    # states, created in the order of the hand-written state vector
    int_x = bd.INTEGRATOR(x0=0.0, name="x_spool", snames=["x_spool"])
    int_v = bd.INTEGRATOR(x0=0.0, name="v_spool", snames=["v_spool"])
    int_pA = bd.INTEGRATOR(x0=ref.P0, name="pA", snames=["pA"])
    int_pB = bd.INTEGRATOR(x0=ref.P0, name="pB", snames=["pB"])
    int_w = bd.INTEGRATOR(x0=0.0, name="omega", snames=["omega"])
    int_th = bd.INTEGRATOR(x0=0.0, name="theta", snames=["theta"])

    # controller: u = clip(Kff v_ref + Kp (x_ref - r theta), -1, 1)
    clock = bd.TIME(name="time")
    refgen = bd.FUNCTION(profile, nin=1, nout=2, name="refgen")
    xb = bd.GAIN(p[ref.I_R], name="x_bridge")
    err = bd.SUM("+-", name="err")
    kff = bd.GAIN(p[ref.I_KFF], name="kff")
    kp = bd.GAIN(p[ref.I_KP], name="kp")
    usum = bd.SUM("++", name="usum")
    usat = bd.CLIP(min=-1.0, max=1.0, name="u")

    # spool: dv/dt = wn^2 u - wn^2 x - 2 zeta wn v
    gu = bd.GAIN(wn * wn, name="wn2_u")
    gx = bd.GAIN(wn * wn, name="wn2_x")
    gv = bd.GAIN(2.0 * zeta * wn, name="2zwn_v")
    acc = bd.SUM("+--", name="spool_acc")

    # valve, motor, lines, load
    valv = bd.FUNCTION(valve, nin=3, nout=4, name="valve")
    qm = bd.FUNCTION(motor_flow, nin=3, nout=1, name="motor_flow")
    tq = bd.FUNCTION(torque, nin=3, nout=1, name="torque")
    sA = bd.SUM("+--", name="sumA")          # q_PA - q_AT - q_m
    sB = bd.SUM("++-", name="sumB")          # q_m + q_PB - q_BT
    cA = bd.GAIN(p[ref.I_BETA] / V, name="cA")
    cB = bd.GAIN(p[ref.I_BETA] / V, name="cB")
    invJ = bd.GAIN(1.0 / p[ref.I_J], name="invJ")

    c = bd.connect
    c(clock, refgen)
    c(int_th, xb)
    c(refgen[1], err[0])
    c(xb, err[1])
    c(refgen[0], kff)
    c(err, kp)
    c(kff, usum[0])
    c(kp, usum[1])
    c(usum, usat)

    c(usat, gu)
    c(int_x, gx, valv[0])
    c(int_v, gv, int_x)
    c(gu, acc[0])
    c(gx, acc[1])
    c(gv, acc[2])
    c(acc, int_v)

    c(int_pA, valv[1], qm[1], tq[0])
    c(int_pB, valv[2], qm[2], tq[1])
    c(int_w, qm[0], tq[2], int_th)

    c(valv[0], sA[0])   # q_PA
    c(valv[1], sA[1])   # q_AT
    c(qm, sA[2], sB[0])
    c(valv[2], sB[1])   # q_PB
    c(valv[3], sB[2])   # q_BT
    c(sA, cA)
    c(sB, cB)
    c(cA, int_pA)
    c(cB, int_pB)
    c(tq, invJ)
    c(invJ, int_w)

    bd.compile(report=False, verbose=False)
    return sim, bd, xb


def run_bdsim(V: float, method: str | None = None, rtol: float = ref.RTOL):
    """Simulate with bdsim; returns (t, x_bridge [m], pA [Pa], info).

    method=None keeps bdsim's default solver (RK45).  info is a dict with
    'build_s' (diagram construction + compile), 'run_s' (sim.run: solve_ivp
    plus bdsim's replay of the 3001 output points) and 'ydot_calls'."""
    tb = time.perf_counter()
    sim, bd, xb = build(V)
    tb = time.perf_counter() - tb
    names = list(bd.statenames)
    order = [ref.STATE_NAMES.index(n.split(".")[-1]) for n in names]
    solver_args = dict(rtol=rtol, atol=ref.ATOL[order])
    if method is not None:
        solver_args["method"] = method
    tr = time.perf_counter()
    out = sim.run(bd, T=ref.T_END, dt=1e-3, solver_args=solver_args)
    tr = time.perf_counter() - tr
    x = np.asarray(out.x)
    t = np.asarray(out.t)
    col = {ref.STATE_NAMES[o]: i for i, o in enumerate(order)}
    x_b = x[:, col["theta"]] * ref.R_BRIDGE
    pA = x[:, col["pA"]]
    if len(t) != len(ref.T_EVAL) or np.max(np.abs(t - ref.T_EVAL)) > 1e-9:
        x_b = np.interp(ref.T_EVAL, t, x_b)
        pA = np.interp(ref.T_EVAL, t, pA)
        t = ref.T_EVAL.copy()
    stats = out[".stats"]
    info = dict(build_s=tb, run_s=tr, ydot_calls=int(stats["ydot_calls"]),
                integrator_s=float(stats["integrator_wall_time"]))
    return t, x_b, pA, info


if __name__ == "__main__":
    for V in (1e-3, 2e-5):
        t0 = time.perf_counter()
        t, x_b, pA, info = run_bdsim(V)
        print(f"V={V:g}: {time.perf_counter()-t0:.2f} s  x_b(3)={x_b[-1]:.5f}  "
              f"pA max {pA.max()/1e5:.1f} bar  {info}")
