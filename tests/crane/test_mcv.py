"""The motion-control valves VAA-B-SICN-ST and VBSO-DE-CC (issue 3, part B).

Tier 1: each block alone, its raw equation functions called by keyword, against the thesis's equations
written out here independently: the spool equilibria eqs. 2.4, 2.7, 2.11, 2.12, 2.13 (VAA) and 2.19, 2.21,
2.22, 2.23 (VBSO) in both contact branches, the saturation at 0 and 1, the crack relation eq. 3.2 on the
measured crack pressures of table 3.2, the flow force eq. 3.13 (and eq. 3.14 on the measured multistep
data), the check valves' closed / partly open / fully open areas, and the conservation of oil.
Tier 2: the data-sheet flow curves (fig. 2.18's test model, netlists/components/mcv_*_flow.yaml) against
data/datasheets/, and the demonstration of section 2.4.1 with and without the valve.

Tolerances: the equilibria are exact algebra away from the declared regularisation bands (the contact
switch, |N| < dN/2 = 0.5 bar, and the saturation corners, u < u_w or u > 1 - u_w with u_w = 0.01), which
the tier-1 points avoid: rel 1e-9. The orifice law with dp_t = 0.1 bar differs from the plain square root
by (1 + (dp_t/dp)^2)^(-1/4) - 1 < 2e-4 for dp >= 5 bar. Data-sheet points read from the text (VBSO) are
given to 2 digits: 5 %. Points reconstructed from table 2.8 (VAA) are closed forms of the table's values
written to 4 digits: 1 %.
"""

from __future__ import annotations

import csv
import math
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from blocks.circuit import Circuit
from blocks.library.hydraulic.displacement import FILL_BAND
from blocks.registry import get
from blocks.units import quantity
from vphs_blocks.mcv_vaa import MotionControlValveVAA as VAA
from vphs_blocks.mcv_vaa import flow_force_pressure, smooth_unit, vaa_contact_force
from vphs_blocks.mcv_vbso import OverCentreValveVBSO as VBSO

ROOT = Path(__file__).resolve().parents[2]
COMPONENTS = ROOT / "netlists" / "components"
DATASHEETS = ROOT / "data" / "datasheets"
SHARED = ROOT.parent / "shared" / "data"

RHO, CD = 850.0, 0.7
BAR = 1e5
LPM = 1e-3 / 60.0  # 1 l/min in m^3/s
EXACT = 1e-9


def preset(cls, name: str) -> dict[str, float]:
    """A preset's values in SI over the block's defaults (fluid rho = 850 kg/m^3, beta = 8e8 Pa)."""
    values = {p.name: p.default for p in cls.params if p.default is not None}
    values.update(rho=RHO, beta=8e8)
    for key, raw in cls.presets[name].items():
        values[key] = quantity(raw, cls.param(key).unit)
    return values


def named(cls, values) -> dict[str, float]:
    names = cls.derivative_names()
    assert len(values) == len(names), (cls.__name__, names, values)
    return dict(zip(names, values))


def vaa(V1, V2, C1, C2, pt=0.0, u1=0.0, u2=0.0, du1=0.0, du2=0.0, **params):
    """The VAA's derivatives by name, VF250 preset, alpha 2.8, crack 230 bar unless overridden."""
    values = preset(VAA, "VF250") | {"alpha": 2.8, "p_crack": 230 * BAR} | params
    return named(VAA, VAA.derivatives(V1=V1, V2=V2, C1=C1, C2=C2, pt=pt, u1=u1, du1=du1, u2=u2, du2=du2,
                                      **{p.name: values[p.name] for p in VAA.params})), values


def vbso(V1, V2, C1, C2, u1=0.0, u2=0.0, du1=0.0, du2=0.0, **params):
    values = preset(VBSO, "05.42.05-10-04-35") | {"alpha": 3.2, "p_crack1": 100 * BAR,
                                                   "p_crack2": 230 * BAR} | params
    return named(VBSO, VBSO.derivatives(V1=V1, V2=V2, C1=C1, C2=C2, u1=u1, du1=du1, u2=u2, du2=du2,
                                        **{p.name: values[p.name] for p in VBSO.params})), values


def equilibria(der, values, u1=0.0, u2=0.0):
    """u_eq of both lines from the spool accelerations at rest: u'' = wn^2*(u_eq - u) at u' = 0."""
    wn2 = values["wn"] ** 2
    return der["der_du1"] / wn2 + u1, der["der_du2"] / wn2 + u2


# ---- the thesis's equations, written out (p1 = pV1, p2 = pV2, p3 = pC1, p4 = pC2; pcr1, pcr2 the springs) ----
def eq_2_4(p_pilot, pt, alpha, pcr2, kp2, u):
    return p_pilot * alpha - pt * alpha + pcr2 - kp2 * u


def eq_2_7(p4, pt, pcr1, kp1):  # eq. 2.12 with p4 -> p3
    return (p4 - pt - pcr1) / kp1


def eq_2_11(p1, p4, pt, alpha, pcr1, pcr2, kp1, kp2):  # eq. 2.13 with p1 -> p2, p4 -> p3
    return (p1 * alpha + pcr2 - pt * (alpha + 1) + p4 - pcr1) / (kp1 + kp2)


def springs(values):
    """The thesis's spring preloads from the block's parameters: pcr1 = p_crack + p_s2, pcr2 = p_s2."""
    return values["p_crack"] + values["p_s2"], values["p_s2"]


# ---------------------------------------------------------------- registration
def test_registered():
    assert get("mcv_vaa") is VAA and get("mcv_vbso") is VBSO
    assert set(VAA.presets) == {"VF050", "VF150", "VF250"}


# ---------------------------------------------------------------- VAA: the spool equilibrium
def test_vaa_line2_contact_branch_eq_2_11():
    p1, p4, pt = 100 * BAR, 150 * BAR, 12 * BAR
    der, v = vaa(V1=p1, V2=10 * BAR, C1=0.0, C2=p4, pt=pt)
    pcr1, pcr2 = springs(v)
    expected = eq_2_11(p1, p4, pt, v["alpha"], pcr1, pcr2, v["kp1"], v["kp2"])
    assert 0.05 < expected < 0.95
    assert eq_2_4(p1, pt, v["alpha"], pcr2, v["kp2"], expected) > 0  # the pieces are in contact
    _, u2 = equilibria(der, v)
    assert u2 == pytest.approx(expected, rel=EXACT)
    wrong = eq_2_7(p4, pt, pcr1, v["kp1"])  # the other branch is far away: the test can tell them apart
    assert abs(wrong - expected) > 0.1


def test_vaa_line2_no_contact_branch_eq_2_7():
    # pilot below pt and no preload on spring 2: N = alpha*(p1 - pt) - kp2*u < 0
    p1, p4, pt = 0.0, 400 * BAR, 5 * BAR
    der, v = vaa(V1=p1, V2=0.0, C1=0.0, C2=p4, pt=pt, p_s2=0.0)
    pcr1, pcr2 = springs(v)
    expected = eq_2_7(p4, pt, pcr1, v["kp1"])
    assert 0.05 < expected < 0.95
    assert eq_2_4(p1, pt, v["alpha"], pcr2, v["kp2"], expected) < 0
    _, u2 = equilibria(der, v)
    assert u2 == pytest.approx(expected, rel=EXACT)
    assert abs(eq_2_11(p1, p4, pt, v["alpha"], pcr1, pcr2, v["kp1"], v["kp2"]) - expected) > 0.1


def test_vaa_line1_both_branches_eq_2_12_2_13():
    # contact (eq. 2.13): line 1 piloted by p2 = V2, loaded by p3 = C1
    p2, p3, pt = 90 * BAR, 180 * BAR, 10 * BAR
    der, v = vaa(V1=3 * BAR, V2=p2, C1=p3, C2=0.0, pt=pt, p_s2=50 * BAR)
    pcr1, pcr2 = springs(v)
    expected = eq_2_11(p2, p3, pt, v["alpha"], pcr1, pcr2, v["kp1"], v["kp2"])
    assert 0.05 < expected < 0.95 and eq_2_4(p2, pt, v["alpha"], pcr2, v["kp2"], expected) > 0
    u1, u2 = equilibria(der, v)
    assert u1 == pytest.approx(expected, rel=EXACT)
    assert u2 == 0.0  # line 2 sees no load (C2 = 0): closed
    # no contact (eq. 2.12): pilot far below pt
    p2, p3, pt = 0.0, 420 * BAR, 20 * BAR
    der, v = vaa(V1=0.0, V2=p2, C1=p3, C2=0.0, pt=pt, p_s2=50 * BAR)
    pcr1, pcr2 = springs(v)
    expected = eq_2_7(p3, pt, pcr1, v["kp1"])
    assert 0.05 < expected < 0.95 and eq_2_4(p2, pt, v["alpha"], pcr2, v["kp2"], expected) < 0
    u1, _ = equilibria(der, v)
    assert u1 == pytest.approx(expected, rel=EXACT)


def test_vaa_contact_force_eq_2_4():
    # N = alpha*(p_pilot - pt) + pcr2 - kp2*u, by hand: 2.8*(50 - 10) + 20 - 400*0.3 = 12 bar
    assert vaa_contact_force(50 * BAR, 10 * BAR, 2.8, 20 * BAR, 400 * BAR, 0.3) == pytest.approx(12 * BAR, rel=1e-12)
    assert vaa_contact_force(50 * BAR, 10 * BAR, 2.8, 20 * BAR, 400 * BAR, 0.4) < 0  # 2.8*40 + 20 - 160 = -28
    assert vaa_contact_force(0.0, 10 * BAR, 2.8, 0.0, 400 * BAR, 0.0) < 0  # pilot below pt, no preload


@settings(max_examples=300, deadline=None)
@given(p_pilot=st.floats(0, 350), p_load=st.floats(0, 400), pt=st.floats(0, 60), alpha=st.floats(1, 10),
       p_crack=st.floats(50, 300), p_s2=st.floats(0, 400))
def test_vaa_branch_follows_the_sign_of_N(p_pilot, p_load, pt, alpha, p_crack, p_s2):
    """Wherever the block's u2 lies in the exact range, eq. 2.4 at that u decides which equation it obeys:
    N > 0 -> eq. 2.11, N <= 0 -> eq. 2.7 (the thesis's branch rule), for any pressures and settings."""
    der, v = vaa(V1=p_pilot * BAR, V2=0.0, C1=0.0, C2=p_load * BAR, pt=pt * BAR, alpha=alpha,
                 p_crack=p_crack * BAR, p_s2=p_s2 * BAR)
    _, u2 = equilibria(der, v)
    assume(v["u_w"] < u2 < 1.0 - v["u_w"])
    pcr1, pcr2 = springs(v)
    n = eq_2_4(p_pilot * BAR, pt * BAR, alpha, pcr2, v["kp2"], u2)
    assume(abs(n) > v["dN"])  # outside the declared rounding of the switch
    if n > 0:
        expected = eq_2_11(p_pilot * BAR, p_load * BAR, pt * BAR, alpha, pcr1, pcr2, v["kp1"], v["kp2"])
    else:
        expected = eq_2_7(p_load * BAR, pt * BAR, pcr1, v["kp1"])
    assert u2 == pytest.approx(expected, rel=1e-9, abs=1e-12)


def test_vaa_saturation_at_0_and_1():
    # far below the crack: eq. 2.11 < 0 -> exactly 0 (no leak through the relief)
    der, v = vaa(V1=10 * BAR, V2=0.0, C1=0.0, C2=100 * BAR, pt=1 * BAR)
    pcr1, pcr2 = springs(v)
    assert eq_2_11(10 * BAR, 100 * BAR, 1 * BAR, 2.8, pcr1, pcr2, v["kp1"], v["kp2"]) < 0
    assert equilibria(der, v)[1] == 0.0
    # pilot beyond the full stroke: eq. 2.11 > 1 -> exactly 1
    der, v = vaa(V1=450 * BAR, V2=0.0, C1=0.0, C2=100 * BAR, pt=1 * BAR)
    assert eq_2_11(450 * BAR, 100 * BAR, 1 * BAR, 2.8, pcr1, pcr2, v["kp1"], v["kp2"]) > 1
    assert equilibria(der, v)[1] == pytest.approx(1.0, abs=1e-12)
    # the rounded corners: C1, monotonic, between the clip and 0 / 1, exact from u_w on
    w = v["u_w"]
    xs = np.linspace(-0.05, 1.05, 2201)
    ys = np.array([smooth_unit(x, w) for x in xs])
    assert np.all(np.diff(ys) >= 0)
    # the lower corner lies below the clip, the upper above it
    low, high = xs < 0.5, xs >= 0.5
    assert np.all(ys[low] <= np.clip(xs[low], 0, 1) + 1e-15) and np.all(ys[high] >= np.clip(xs[high], 0, 1) - 1e-15)
    inside = (xs >= w) & (xs <= 1 - w)
    assert np.array_equal(ys[inside], xs[inside])
    h = 1e-7  # C1: the slopes left and right of each junction agree (a kink would differ by 1)
    for x0 in (0.0, w, 1.0 - w, 1.0):
        left = (smooth_unit(x0, w) - smooth_unit(x0 - h, w)) / h
        right = (smooth_unit(x0 + h, w) - smooth_unit(x0, w)) / h
        assert abs(left - right) < 1e-3, (x0, left, right)


@pytest.mark.skipif(not (SHARED / "mcv_vf250_crack.csv").exists(), reason="shared data not present")
@pytest.mark.parametrize("p_s2_bar", [0.0, 400.0])
def test_vaa_opens_where_eq_3_2_says(p_s2_bar):
    """Table 3.2's three settings: with pv1, pv2 as measured and pt = pv2 + (pv1 - pc) (the thesis's
    assumption), the block's relief starts to open (u2_eq leaves 0) at the measured pc, i.e. where
    eq. 3.2, pcr = pc*(alpha + 2) - pv1 - pv2*(alpha + 1), puts the crack. pc is found by bisection on the
    block; the table's pressures are rounded to 0.1 bar and its pcr reproduces them to 0.04 bar, i.e. pc to
    0.01 bar. The contact force eq. 2.4 at u = 0 is positive there (the thesis's check)."""
    with open(SHARED / "mcv_vf250_crack.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert len(rows) == 3
    for row in rows:
        alpha = float(row["pilot_ratio"])
        pv1, pv2, pc = (float(row[k]) * BAR for k in ("pv1 [bar]", "pv2 [bar]", "pc [bar]"))
        crack = float(row["crack [bar]"]) * BAR

        def u2_at(p_c):
            der, v = vaa(V1=pv1, V2=pv2, C1=0.0, C2=p_c, pt=pv2 + (pv1 - p_c), alpha=alpha, p_crack=crack,
                         p_s2=p_s2_bar * BAR)
            return equilibria(der, v)[1]

        lo, hi = pc - 5 * BAR, pc + 5 * BAR
        assert u2_at(lo) == 0.0 and u2_at(hi) > 0.0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if u2_at(mid) == 0.0 else (lo, mid)
        assert hi == pytest.approx(pc, abs=0.02 * BAR), row["setting"]
        pt = pv2 + (pv1 - pc)
        assert eq_2_4(pv1, pt, alpha, p_s2_bar * BAR, 400 * BAR, 0.0) > 0
        assert crack == pytest.approx(pc * (alpha + 2) - pv1 - pv2 * (alpha + 1), abs=0.05 * BAR)


# ---------------------------------------------------------------- VAA: the flow force of chapter 3
POLYNOMIALS = {  # eq. 3.13's three fits, coefficients of Q^4, Q^3, Q^2, Q (Q in l/min), by crack setting
    "above 180 bar": (1.66e-5, -3.0e-3, 0.071, 13.2),
    "120 to 180 bar": (-1.9e-5, 5.2e-3, -0.55, 28.9),
    "below 120 bar": (-4.4e-5, 0.011, -1.0, 40.5),
}


def p_F(q, dp, coefficients):
    """pF = P(Q_lpm)*Q*z1/sqrt(dp), z1 = 4.0847e5*1e5, Q in m^3/s, dp in Pa (the plain square root)."""
    x = q / LPM
    c4, c3, c2, c1 = coefficients
    return (c4 * x**4 + c3 * x**3 + c2 * x**2 + c1 * x) * q * 4.0847e5 * 1e5 / math.sqrt(dp)


@pytest.mark.parametrize("crack_bar, fit, p1_bar, p2_bar, p4_bar", [
    (95.4, "below 120 bar", 48.6, 6.0, 42.8),  # the pressures of table 3.4's 4th step of each setting,
    (152.0, "120 to 180 bar", 66.5, 7.3, 59.2),  # pt = p2 + (p1 - p4) as in chapter 3
    (211.5, "above 180 bar", 78.8, 5.8, 73.1)])
def test_vaa_flow_force_eq_3_13(crack_bar, fit, p1_bar, p2_bar, p4_bar):
    p1, p2, p4, u2 = p1_bar * BAR, p2_bar * BAR, p4_bar * BAR, 0.15
    pt = p2 + (p1 - p4)
    common = dict(V1=p1, V2=p2, C1=0.0, C2=p4, pt=pt, u2=u2, p_crack=crack_bar * BAR)
    der0, v = vaa(flow_force=0, **common)
    der1, _ = vaa(flow_force=1, **common)
    pcr1, pcr2 = springs(v)
    base = eq_2_11(p1, p4, pt, v["alpha"], pcr1, pcr2, v["kp1"], v["kp2"])
    q = CD * v["A_prv"] * u2 * math.sqrt(2 * (p4 - pt) / RHO)  # the relief's flow at u2 (plain law)
    assert 20 * LPM < q < 100 * LPM  # inside the fit's range
    expected = base + p_F(q, p4 - pt, POLYNOMIALS[fit]) / (v["kp1"] + v["kp2"])
    assert 0.02 < base < 0.9
    assert equilibria(der0, v, u2=u2)[1] == pytest.approx(base, rel=EXACT)
    assert equilibria(der1, v, u2=u2)[1] == pytest.approx(expected, rel=1e-5)
    # the other fits give clearly different openings: the choice by crack setting is tested
    for other, coefficients in POLYNOMIALS.items():
        if other != fit:
            wrong = base + p_F(q, p4 - pt, coefficients) / (v["kp1"] + v["kp2"])
            assert abs(wrong - expected) > 1e-3
    # pF(Q = 0) = 0: a closed relief feels no flow force, so the crack is unchanged (chapter 3's condition)
    der0, _ = vaa(flow_force=0, **(common | {"u2": 0.0}))
    der1, _ = vaa(flow_force=1, **(common | {"u2": 0.0}))
    assert der1["der_du2"] == der0["der_du2"]


@pytest.mark.skipif(not (SHARED / "mcv_vf250_multistep.csv").exists(), reason="shared data not present")
def test_flow_force_gives_the_constant_stiffness_of_eq_3_14():
    """Eq. 3.14 on the measured multistep data (table 3.4): with pF the spring stiffness settles near the
    thesis's 895 bar/unit; without it, it does not (eq. 3.12, "highly non-constant"). Reading used:
    pv1 = p1 - dpf with dpf = 1 bar + 3e8 Pa*s/m^3 * Q; eq. 3.4 prints 30000e5, which would put pv1
    below pc (flow against check valve 1) at 12.5 l/min, so a factor 10 is taken as a misprint.
    Rows with Q >= 20 l/min (the thesis: most accurate between 20 and 100 l/min)."""
    with open(SHARED / "mcv_vf250_multistep.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    crack = {"1": 95.4 * BAR, "2": 152.0 * BAR, "3": 211.5 * BAR}  # table 3.2
    alpha, a_max = 2.8, 72.1e-6
    with_pf, without = [], []
    for row in rows:
        Q = float(row["Q [l/min]"]) * LPM
        if Q < 20 * LPM:
            continue
        pv1 = float(row["p1 [bar]"]) * BAR - (1e5 + 3e8 * Q)
        pv2, pc = float(row["p2 [bar]"]) * BAR, float(row["p3 [bar]"]) * BAR
        pcr = crack[row["setting"]]
        pt = pv2 + (pv1 - pc)
        factor = a_max * CD * math.sqrt(2) * math.sqrt(2 * pc - pv2 - pv1) / (Q * math.sqrt(RHO))
        numerator = pc * (alpha + 2) - pcr - pv2 * (alpha + 1) - pv1
        pf = flow_force_pressure(Q, pc - pt, pcr, 100 * LPM, 1e4)
        with_pf.append(factor * (numerator + pf) / BAR)
        without.append(factor * numerator / BAR)
    with_pf, without = np.array(with_pf), np.array(without)
    assert len(with_pf) == 19
    assert np.all((with_pf > 800) & (with_pf < 950)), with_pf
    assert abs(np.mean(with_pf) - 895) < 0.05 * 895
    assert np.max(without) < 600  # without the flow force the "stiffness" is far off and spread


# ---------------------------------------------------------------- VAA: flows
def turbulent(dp, area, dp_t=1e4):
    return CD * area * math.sqrt(2 / RHO) * dp / (dp * dp + dp_t * dp_t) ** 0.25


@pytest.mark.parametrize("size", ["VF050", "VF150", "VF250"])
def test_vaa_check_valve_areas(size):
    v = preset(VAA, size)
    common = dict(preset(VAA, size), alpha=2.8, p_crack=230 * BAR)
    cr, op, a_max, leak = v["p_cv1_crack"], v["p_cv1_open"], v["A_cv1"], v["A_leak"]
    for dp, area in ((0.5 * cr, leak), (0.5 * (cr + op), leak + 0.5 * (a_max - leak)), (op, a_max),
                     (3 * op, a_max), (-5 * BAR, leak)):
        # check valve 1, line 1 (V1 -> C1); relief closed (u1 = 0), so C1 receives what the check valve passes
        der, _ = vaa(V1=20 * BAR + dp, V2=0.0, C1=20 * BAR, C2=0.0, pt=0.0, **common)
        assert der["q_C1"] == pytest.approx(turbulent(dp, area), rel=1e-12), (size, dp)
        # line 2 the same
        der, _ = vaa(V1=0.0, V2=20 * BAR + dp, C1=0.0, C2=20 * BAR, pt=0.0, **common)
        assert der["q_C2"] == pytest.approx(turbulent(dp, area), rel=1e-12), (size, dp)
    cr, op, a_max = v["p_cv2_crack"], v["p_cv2_open"], v["A_cv2"]
    for dp, area in ((0.5 * cr, leak), (0.5 * (cr + op), leak + 0.5 * (a_max - leak)), (op, a_max)):
        # check valve 2, pt -> V1 (V1 = C1: check valve 1 passes nothing; V2 high: pt -> V2 shut)
        der, _ = vaa(V1=20 * BAR, V2=100 * BAR, C1=20 * BAR, C2=100 * BAR, pt=20 * BAR + dp, **common)
        assert der["q_V1"] == pytest.approx(turbulent(dp, area), rel=1e-12), (size, dp)


def test_vaa_relief_area_and_cross_line_route():
    """Relief 2 open at u2 = 0.4: area 0.4*A_prv (eq. 2.15); its flow reaches pt, and leaves pt by the
    check valve 2 towards the lower V line only."""
    der, v = vaa(V1=30 * BAR, V2=5 * BAR, C1=0.0, C2=80 * BAR, pt=10 * BAR, u2=0.4)
    q_r2 = turbulent(70 * BAR, 0.4 * v["A_prv"])
    q_out = turbulent(5 * BAR, v["A_cv2"])  # pt -> V2, 5 bar: fully open (p_cv2_open = 2.5 bar)
    q_leak_v1 = turbulent(-20 * BAR, v["A_leak"])  # pt -> V1 against 20 bar: the leak only (negative)
    assert der["q_C2"] == pytest.approx(turbulent(-75 * BAR, v["A_leak"]) - q_r2, rel=1e-12)
    assert der["q_V2"] == pytest.approx(q_out - turbulent(-75 * BAR, v["A_leak"]), rel=1e-12)
    assert der["der_pt"] == pytest.approx(v["beta"] / v["V_t"] * (q_r2 - q_out - q_leak_v1), rel=1e-9)


@settings(max_examples=200, deadline=None)
@given(p=st.lists(st.floats(-1, 400), min_size=5, max_size=5), u=st.lists(st.floats(-0.1, 1.1), min_size=2, max_size=2),
       force=st.sampled_from([0, 1]))
def test_vaa_conserves_oil(p, u, force):
    der, v = vaa(V1=p[0] * BAR, V2=p[1] * BAR, C1=p[2] * BAR, C2=p[3] * BAR, pt=p[4] * BAR, u1=u[0], u2=u[1],
                 flow_force=force)
    ports = der["q_V1"] + der["q_V2"] + der["q_C1"] + der["q_C2"]
    stored = v["V_t"] / v["beta"] * der["der_pt"]
    scale = max(abs(der[k]) for k in ("q_V1", "q_V2", "q_C1", "q_C2")) + 1e-12
    assert abs(ports + stored) <= 1e-12 * scale


# ---------------------------------------------------------------- VBSO
def test_vbso_contact_on_relief_2_eqs_2_21_2_22():
    pv1, pv2, pc1, pc2 = 80 * BAR, 5 * BAR, 250 * BAR, 150 * BAR  # N = alpha*Ar*(pv1 - pv2) > 0
    der, v = vbso(V1=pv1, V2=pv2, C1=pc1, C2=pc2)
    a, pcr1, pcr2, kp1, kp2 = v["alpha"], v["p_crack1"], v["p_crack2"], v["kp1"], v["kp2"]
    u2 = (a * pv1 - pv2 * (a + 1) - pcr2 + pc2) / kp2  # eq. 2.21
    u1 = (-pv1 + pc1 - pcr1) / kp1  # eq. 2.22
    assert 0.05 < u1 < 0.95 and 0.05 < u2 < 0.95
    got = equilibria(der, v)
    assert got[0] == pytest.approx(u1, rel=EXACT) and got[1] == pytest.approx(u2, rel=EXACT)
    assert abs((-pv2 + pc2 - pcr2) / kp2 - u2) > 0.1  # eq. 2.19 would differ


def test_vbso_contact_on_relief_1_eqs_2_19_2_23():
    pv1, pv2, pc1, pc2 = 5 * BAR, 80 * BAR, 150 * BAR, 340 * BAR  # N < 0
    der, v = vbso(V1=pv1, V2=pv2, C1=pc1, C2=pc2)
    a, pcr1, pcr2, kp1, kp2 = v["alpha"], v["p_crack1"], v["p_crack2"], v["kp1"], v["kp2"]
    u1 = (a * pv2 - pv1 * (a + 1) - pcr1 + pc1) / kp1  # eq. 2.23
    u2 = (-pv2 + pc2 - pcr2) / kp2  # eq. 2.19
    assert 0.02 < u1 < 0.95 and 0.02 < u2 < 0.95
    got = equilibria(der, v)
    assert got[0] == pytest.approx(u1, rel=EXACT) and got[1] == pytest.approx(u2, rel=EXACT)
    assert abs((-pv1 + pc1 - pcr1) / kp1 - u1) > 0.1  # eq. 2.22 would differ


def test_vbso_branches_meet_and_saturate():
    # pv1 = pv2: eqs. 2.19 and 2.21 agree (no jump at the switch); the rounding only adds alpha*dN/8/kp2
    pv, pc2 = 40 * BAR, 500 * BAR
    der, v = vbso(V1=pv, V2=pv, C1=0.0, C2=pc2)
    u_switch = (-pv + pc2 - v["p_crack2"]) / v["kp2"]
    assert equilibria(der, v)[1] == pytest.approx(u_switch + v["alpha"] * v["dN"] / 8 / v["kp2"], rel=1e-9)
    der, v = vbso(V1=0.0, V2=0.0, C1=50 * BAR, C2=50 * BAR)  # below both cracks
    assert equilibria(der, v) == (0.0, 0.0)
    der, v = vbso(V1=0.0, V2=400 * BAR, C1=300 * BAR, C2=0.0)  # pilot on V2 beyond relief 1's full stroke
    assert equilibria(der, v)[0] == pytest.approx(1.0, abs=1e-12)


def test_vbso_check_and_relief_areas():
    v = preset(VBSO, "05.42.05-10-04-35")
    cr, op, a_max, leak = v["p_cv_crack"], v["p_cv_open"], v["A_cv"], v["A_leak"]
    for dp, area in ((0.5 * cr, leak), (0.5 * (cr + op), leak + 0.5 * (a_max - leak)), (op, a_max), (5 * op, a_max)):
        der, _ = vbso(V1=10 * BAR + dp, V2=0.0, C1=10 * BAR, C2=0.0)
        assert der["q_C1"] == pytest.approx(turbulent(dp, area), rel=1e-12)
    der, v = vbso(V1=0.0, V2=0.0, C1=20 * BAR, C2=0.0, u1=0.3)  # relief 1 at u1 = 0.3 (eq. 2.24)
    assert der["q_V1"] == pytest.approx(turbulent(20 * BAR, 0.3 * v["A_prv"]) - turbulent(-20 * BAR, leak), rel=1e-12)
    assert der["q_V1"] + der["q_C1"] == 0.0


# ---------------------------------------------------------------- data-sheet flow curves (tier 2)
def read_points(name: str) -> dict[str, list[tuple[float, float]]]:
    """data/datasheets/<name>: curve -> [(Q [m^3/s], dp [Pa])]."""
    with open(DATASHEETS / name) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    curves: dict[str, list[tuple[float, float]]] = {}
    for row in rows:
        curves.setdefault(row["curve"], []).append((float(row["Q [l/min]"]) * LPM, float(row["dp [bar]"]) * BAR))
    return curves


@lru_cache(maxsize=None)
def circuit(name: str) -> Circuit:
    return Circuit.from_file(COMPONENTS / f"{name}.yaml")


def compare_curve(r, column: str, points, rel: float, what: str, crack_band: float):
    """Each (Q, dp) point against the simulated dp at that Q on the ramp. A point at Q = 0 is the crack:
    at 0.5 l/min the simulated dp lies between it and crack_band above it (the valve just opening)."""
    q, dp = r["Q"], r[column]
    for q_point, dp_point in points:
        if q_point == 0.0:
            at = float(np.interp(0.5 * LPM, q, dp))
            assert dp_point <= at <= dp_point + crack_band, f"{what}: crack {dp_point / BAR} bar, sim {at / BAR} bar"
        else:
            at = float(np.interp(q_point, q, dp))
            assert at == pytest.approx(dp_point, rel=rel), f"{what} at {q_point / LPM:.4g} l/min"


@pytest.mark.parametrize("size, q_end", [("VF050", 50), ("VF150", 150), ("VF250", 200)])
def test_vaa_datasheet_curves(size, q_end):
    overrides = {"Q_end": q_end * LPM}
    for comp in ("check", "relief"):
        for key, raw in VAA.presets[size].items():
            overrides[f"{comp}.{key}"] = quantity(raw, VAA.param(key).unit)
    r = circuit("mcv_vaa_flow").simulate(overrides)
    assert r["u_relief"].min() > 0.999  # the relief is held fully open by the pilot
    v = preset(VAA, size)
    curves = read_points("mcv_vaa_flow.csv")
    compare_curve(r, "dp_check", curves[f"{size} check V->C"], 0.01, f"{size} check",
                  0.25 * (v["p_cv1_open"] - v["p_cv1_crack"]))
    compare_curve(r, "dp_relief", curves[f"{size} relief C->V"], 0.01, f"{size} relief",
                  0.25 * (v["p_cv2_open"] - v["p_cv2_crack"]))
    # the relieved oil crosses pt to V1 (the lower line), not to the piloted V2 = 500 bar
    assert np.all(r["pt_relief"] < 100 * BAR)


def test_vbso_datasheet_curves():
    r = circuit("mcv_vbso_flow").simulate()
    assert r["u_relief"].min() > 0.999
    v = preset(VBSO, "05.42.05-10-04-35")
    curves = read_points("mcv_vbso_flow.csv")
    compare_curve(r, "dp_check", curves["check V->C"], 0.05, "VBSO check", 0.25 * (v["p_cv_open"] - v["p_cv_crack"]))
    compare_curve(r, "dp_relief", curves["relief C->V"], 0.05, "VBSO relief", 0.0)


# ---------------------------------------------------------------- the demonstration of section 2.4.1
def test_demo_without_mcv_cavitates():
    """The inlet closes (1.5 to 2 s) while the inertia keeps the motor turning: it draws line A down to the
    vapour pressure, where its chambers fill with vapour (a cavity under a cm^3 in the line: the fill band of
    blocks/library/hydraulic/displacement.py), no braking pressure builds, and the motor outruns its inlet,
    stopped only by the load torque (the thesis's uneven deceleration, section 2.4.1)."""
    r = circuit("mcv_demo_without").simulate()
    (warning,) = r.warnings
    assert "net 'A' reached the vapour pressure -1 bar" in warning and "vapour cavity" in warning
    assert r["pA"].min() >= -1 * BAR - FILL_BAND
    w, t = r["speed"], r.t
    at_close = w[np.searchsorted(t, 2.0)]
    assert at_close > 0.5 * w.max()  # still over half speed when the inlet is shut
    # coasting against the load torque and the vacuum at the inlet: (J_load + J_m)*dw/dt = -T_load +
    # D*(p_a - p_b), p_a at the vapour pressure, p_b drained (the motor passes no oil). (Before the chambers'
    # fill, the motor pumped its line's vapour as oil and kept braking on it: T_load/J within 20 % only.)
    coast = (t > 2.2) & (t < 2.8)
    decel = -np.polyfit(t[coast], w[coast], 1)[0]
    vacuum = 30e-6 / (2 * np.pi) * np.mean(r["pB"][coast] - r["pA"][coast])
    assert 0.4 < vacuum < 0.5  # N*m: D times a little over 1 bar
    assert decel == pytest.approx((20.0 + vacuum) / (0.2 + 0.0018), rel=1e-5)


def test_demo_with_mcv_decelerates_evenly_without_cavitation():
    without = circuit("mcv_demo_without").simulate()
    r = circuit("mcv_demo_with").simulate()
    assert r.warnings == []
    for name in ("pV1", "pC1", "pC2", "pV2", "pt"):  # pt is the valve's own node, which the run does not check
        assert r[name].min() >= -1 * BAR, name
    w, w0, t = r["speed"], without["speed"], r.t
    assert w.max() > 100 and abs(w[-1]) < 0.01 * w.max() and w0.max() > 100  # both ran; with the valve, stopped
    # the valve holds the motor to its inlet: stopped as the inlet shuts, where without it the motor coasts on
    stopped = t[(t > 1.5) & (np.abs(w) < 0.01 * w.max())][0]
    assert stopped < 2.05 and np.all(np.abs(w0[(without.t > 1.5) & (without.t <= 2.5)]) > 0.01 * w0.max()), stopped
    assert -w[t > 1.5].min() < 0.05 * w.max()  # little backward motion after the stop
    # the relief in the return line closes as the inlet closes, and opened only under inlet pressure
    assert r["u2"].max() > 0.05 and r["u2"][-1] < 1e-3 and r["u1"].max() < 1e-6
