"""The MCV test rig of thesis chapter 3 against its measurements (issue 3, part D).

Tier 1: the rig's flow meter (vphs_blocks/flow_meter.py, eq. 3.4) alone, its raw functions called by
keyword, against its closed form; the reading of eq. 3.4's slope as 3000e5 Pa*s/m^3 against the thesis's own
simulated p1 - p3 (table 3.4); eq. 3.2 on table 3.2's measured pressures; the step metrics on a closed-form
second-order response.
Tier 2: the rig netlists (netlists/rig/):
- multistep: the 21 measured points with measured Q and p2 imposed; each steady state against an
  independent closed-form solution of the thesis's equations (eqs. 2.11/3.13, 2.14/2.15, the table-2.8 check
  valves, eq. 3.4); the steady state independent of the line volumes; the RMSE of p1 and p3 against the
  measurements no worse than the thesis's Simulink model's (computed from the two CSVs); the RMSE without
  the flow force is printed, not asserted;
- crack: eq. 3.2 on the simulated pressures gives table 3.2's crack pressure within 1 bar;
- step: rise time, first peak and settling of p3 for the PVG stepped 0 -> 100 % and 0 -> 50 % are physical,
  and the settled state is the closed-form steady state at the settled flow and return pressure.

Tolerances are stated where they are used, with where they come from.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from blocks.circuit import Circuit
from blocks.registry import get
from blocks.units import quantity
from vphs_blocks import rig
from vphs_blocks.flow_meter import FlowMeter

BAR = 1e5
LPM = 1e-3 / 60.0
RHO, CD = 850.0, 0.7

pytestmark = pytest.mark.skipif(not rig.MEASURED_MULTISTEP.exists(), reason="shared data not present")


# ---- the thesis's equations, written out independently of the blocks ---------------------------------------
VF250 = {"A_prv": 72.1e-6, "A_cv": 151.5e-6, "cv1": (0.5 * BAR, 2.0 * BAR), "cv2": (0.1 * BAR, 2.5 * BAR),
         "kp": 895 * BAR}  # tables 2.8, 2.9
METER = {"R": 3000e5, "dp0": 1 * BAR}  # eq. 3.4, slope read as 3000e5 Pa*s/m^3


def check_valve_drop(q, A, crack, full, law="cubic"):
    """dp of a check valve passing q: q = Cd*A*s*sqrt(2*dp/rho), s rising from 0 at crack to 1 at full,
    linearly (the thesis's Simscape valve) or as the C1 cubic the blocks use (same end points)."""
    def residual(dp):
        s = min(max((dp - crack) / (full - crack), 0.0), 1.0)
        if law == "cubic":
            s = s * s * (3.0 - 2.0 * s)
        return CD * A * s * math.sqrt(2.0 * dp / RHO) - q
    return brentq(residual, crack + 1e-9, 1e9, xtol=1e-10)


def p_F(q, dp, p_crack, q_max=100 * LPM):
    """Eq. 3.13: pF = P(Q_lpm)*z1*Q/sqrt(dp), the fit chosen by the crack setting, its argument held at q_max."""
    if p_crack > 180 * BAR:
        c = (1.66e-5, -3.0e-3, 0.071, 13.2)
    elif p_crack >= 120 * BAR:
        c = (-1.9e-5, 5.2e-3, -0.55, 28.9)
    else:
        c = (-4.4e-5, 0.011, -1.0, 40.5)
    x = min(q, q_max) / LPM
    return (c[0] * x**4 + c[1] * x**3 + c[2] * x**2 + c[3] * x) * 4.0847e5 * 1e5 * q / math.sqrt(dp)


def steady_state(Q, p2, p_crack, alpha=2.8, flow_force=1.0):
    """(p1, pv1, pc, pt) of the rig at flow Q with V2 at p2: check valve 2 (pt -> V2) and check valve 1
    (V1 -> C1) pass Q; the relief C2 -> pt passes Q = Cd*A_prv*u*sqrt(2*(pc - pt)/rho) at the spool
    equilibrium of eq. 2.11 with the flow force of eq. 3.13 (pieces in contact, pcr = pcr1 - pcr2):
        u = (alpha*pv1 + pc - pt*(alpha + 1) - pcr + pF)/(kp1 + kp2)
    and the flow meter loses dp0 + R*Q (eq. 3.4). Solved for pc by bisection."""
    pt = p2 + check_valve_drop(Q, VF250["A_cv"], *VF250["cv2"])
    d1 = check_valve_drop(Q, VF250["A_cv"], *VF250["cv1"])

    def residual(pc):
        dp = pc - pt
        u = (alpha * (pc + d1) + pc - pt * (alpha + 1) - p_crack + flow_force * p_F(Q, dp, p_crack)) / VF250["kp"]
        return u - Q / (CD * VF250["A_prv"] * math.sqrt(2.0 * dp / RHO))

    pc = brentq(residual, pt + 1.0, 1e9, xtol=1e-6)
    return pc + d1 + METER["dp0"] + METER["R"] * Q, pc + d1, pc, pt


def meter_q(dp, **params):
    values = {p.name: p.default for p in FlowMeter.params if p.default is not None} | params
    (q,) = FlowMeter.outputs(a=dp, b=0.0, **{p.name: values[p.name] for p in FlowMeter.params})
    q_a, q_b = FlowMeter.derivatives(a=dp, b=0.0, **{p.name: values[p.name] for p in FlowMeter.params})
    assert q_a == -q and q_b == q  # what leaves a enters b, and the output is that flow
    return q


# ---------------------------------------------------------------- tier 1: the flow meter
def test_flow_meter_registered_with_eq_3_4_preset():
    assert get("flow_meter") is FlowMeter
    preset = {k: quantity(v, FlowMeter.param(k).unit) for k, v in FlowMeter.presets["eq_3_4"].items()}
    assert preset == {"R": METER["R"], "dp0": METER["dp0"]}


@pytest.mark.parametrize("q_lpm", [0.5, 12.5, 47.7, 89.6])
def test_flow_meter_loss_is_offset_plus_laminar(q_lpm):
    """Beyond the rounded band, dp = dp0 + R*q exactly (eq. 3.4), both directions (odd in dp)."""
    q = q_lpm * LPM
    dp = METER["dp0"] + METER["R"] * q
    assert meter_q(dp, **METER) == pytest.approx(q, rel=1e-12)
    assert meter_q(-dp, **METER) == pytest.approx(-q, rel=1e-12)


def test_flow_meter_dead_band_and_rounding():
    w = 1e3
    for dp in (0.0, 0.3 * BAR, METER["dp0"] - w / 2):
        assert meter_q(dp, dp_w=w, **METER) == 0.0 and meter_q(-dp, dp_w=w, **METER) == 0.0
    # at the offset the rounded branch gives (w/2)^2/(2w)/R = w/(8R); continuous and C1 at both band edges
    assert meter_q(METER["dp0"], dp_w=w, **METER) == pytest.approx(w / 8 / METER["R"], rel=1e-12)
    h = 1e-3
    for edge in (METER["dp0"] - w / 2, METER["dp0"] + w / 2):
        left = (meter_q(edge, dp_w=w, **METER) - meter_q(edge - h, dp_w=w, **METER)) / h
        right = (meter_q(edge + h, dp_w=w, **METER) - meter_q(edge, dp_w=w, **METER)) / h
        assert abs(left - right) * METER["R"] < 1e-5


@given(st.floats(-1e6, 1e6))
@settings(max_examples=200, deadline=None)
def test_flow_meter_without_offset_is_the_plain_laminar_sensor(dp):
    """dp0 = 0: the two rounded bands cancel, q = dp/R everywhere (the library flow_sensor's law)."""
    assert meter_q(dp, R=3e8, dp0=0.0, dp_w=1e3) == pytest.approx(dp / 3e8, rel=1e-9, abs=1e-18)


def test_flow_meter_rejects_a_rounding_wider_than_the_offset():
    assert FlowMeter.check_values({"R": 3e8, "dp0": 1e5, "dp_w": 2e5})
    assert FlowMeter.check_values({"R": 3e8, "dp0": 1e5, "dp_w": 1e3}) is None
    assert FlowMeter.check_values({"R": 3e8, "dp0": 0.0, "dp_w": 1e3}) is None


def test_eq_3_4_slope_read_as_3000e5_reproduces_the_thesiss_p1_minus_p3():
    """The thesis's simulated p1 - p3 (table 3.4, 'Sim.') is the meter's loss plus check valve 1's drop
    (Simscape: linear opening between table 2.8's 0.5 and 2 bar). With the printed 30000e5 Pa*s/m^3 that sum
    misses by 5...40 bar; read as 3000e5 it matches at all 21 points within the rounding of the table
    (p1 and p3 to 0.1 bar each: 0.1 bar on their difference). The meter's drop is found on the block."""
    sim = rig.measured_points(rig.THESIS_MULTISTEP)
    for slope, ok in ((3000e5, True), (30000e5, False)):
        worst = 0.0
        for k in range(len(sim.labels)):
            q = sim.columns["Q"][k]
            dp_meter = brentq(lambda dp: meter_q(dp, R=slope, dp0=METER["dp0"]) - q, METER["dp0"], 1e8, xtol=1e-6)
            predicted = dp_meter + check_valve_drop(q, VF250["A_cv"], *VF250["cv1"], law="linear")
            worst = max(worst, abs(predicted - (sim.columns["p1"][k] - sim.columns["p3"][k])))
        assert bool(worst <= 0.1 * BAR) is ok, (slope, worst / BAR)


# ---------------------------------------------------------------- tier 1: eq. 3.2 and the thesis's figures
def test_eq_3_2_on_the_measured_crack_pressures():
    """Table 3.2's pcr is eq. 3.2 of its pv1, pv2, pc (to the table's 0.1 bar: 0.05 bar)."""
    import csv

    with open(rig.MEASURED_CRACK, newline="") as handle:
        rows = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    settings_ = rig.crack_settings()
    for row in rows:
        pv1, pv2, pc = (float(row[k]) * BAR for k in ("pv1 [bar]", "pv2 [bar]", "pc [bar]"))
        pcr = rig.crack_pressure_eq_3_2(pv1, pv2, pc, float(row["pilot_ratio"]))
        assert pcr == pytest.approx(settings_[row["setting"]], abs=0.05 * BAR)


def test_the_thesiss_rmse_figures_from_its_csvs():
    """The brief's 3.31 bar (p1) and 1.13 bar (p3): the thesis's Simulink columns against the measured ones."""
    measured, thesis = rig.measured_points(), rig.measured_points(rig.THESIS_MULTISTEP)
    assert list(measured.labels) == list(thesis.labels)
    assert np.allclose(measured.columns["Q"], thesis.columns["Q"], atol=0.25 * LPM)  # the same 21 points
    assert round(rig.rmse((thesis.columns["p1"] - measured.columns["p1"]) / BAR), 2) == 3.31
    assert round(rig.rmse((thesis.columns["p3"] - measured.columns["p3"]) / BAR), 2) == 1.13


def test_step_metrics_on_a_second_order_response():
    """p = 1 - exp(-z*w*t)*(cos(wd*t) + z/sqrt(1 - z^2)*sin(wd*t)): first peak 1 + exp(-pi*z/sqrt(1 - z^2))
    at pi/wd; the 2 % band is left for good before the envelope exp(-z*w*t)/sqrt(1 - z^2) falls below 0.02;
    rise time 10-90 % of the underdamped response between its two crossings (found here by bisection)."""
    z, w = 0.3, 2 * math.pi * 20.0
    wd = w * math.sqrt(1 - z * z)
    t = np.linspace(0.0, 1.0, 200001)
    p = 1 - np.exp(-z * w * t) * (np.cos(wd * t) + z / math.sqrt(1 - z * z) * np.sin(wd * t))
    p_of = lambda x: 1 - math.exp(-z * w * x) * (math.cos(wd * x) + z / math.sqrt(1 - z * z) * math.sin(wd * x))
    m = rig.step_metrics(t, 3.0 + 2.0 * p, t_step=0.0)  # offset and scale: p0 = 3, p_end = 5
    assert m["p0"] == pytest.approx(3.0) and m["p_end"] == pytest.approx(5.0, abs=1e-9)
    assert m["t_peak"] == pytest.approx(math.pi / wd, abs=2e-5)
    # a sampled maximum lies below the true one by at most |p''|/2*(dt/2)^2, |p''| = 2*w^2*overshoot at the peak
    overshoot = math.exp(-math.pi * z / math.sqrt(1 - z * z))
    sampling = 2.0 * w * w * overshoot / 2 * (t[1] / 2) ** 2
    assert 0.0 <= 3.0 + 2.0 * (1 + overshoot) - m["p_peak"] <= sampling * (1 + 1e-6)
    t10 = brentq(lambda x: p_of(x) - 0.1, 0.0, math.pi / wd)
    t90 = brentq(lambda x: p_of(x) - 0.9, 0.0, math.pi / wd)
    assert m["rise"] == pytest.approx(t90 - t10, abs=2e-5)
    assert 0.0 < m["settle"] <= math.log(1 / (0.02 * math.sqrt(1 - z * z))) / (z * w)


# ---------------------------------------------------------------- tier 2: the multistep rig
@pytest.fixture(scope="module")
def multistep():
    return {ff: rig.run_multistep(ff) for ff in (1.0, 0.0)}


def test_multistep_imposes_the_measured_q_and_p2(multistep):
    """The gray block's area is the orifice law inverted at the point's Q and p2, so in the steady state
    p2 and the meter's Q are the measured ones (to the settling tolerance, 1e-3 bar, and the leakage of the
    closed check valves, 1e-9 m^2 each: < 1e-4 l/min)."""
    errors = rig.point_errors(multistep[1.0])
    assert np.max(np.abs(errors["p2"])) < 2e-3
    assert np.max(np.abs(errors["Q"])) < 1e-3


@pytest.mark.parametrize("flow_force", [1.0, 0.0])
def test_multistep_steady_states_are_the_closed_form(multistep, flow_force):
    """Each simulated point against steady_state() above. Budget 0.02 bar: the settling tolerance (1e-3 bar),
    the laminar transition dp_t = 0.1 bar of the blocks' orifices (on check-valve drops of 0.6...1.7 bar it
    shifts them by < 0.7 %, < 0.012 bar), the leakage of the closed check valves (< 0.05 % of Q)."""
    pcr = rig.crack_settings()
    for p in multistep[flow_force]:
        p1, _, pc, _ = steady_state(p.Q, p.p2, pcr[p.setting], flow_force=flow_force)
        assert p.p1 == pytest.approx(p1, abs=0.02 * BAR), (p.setting, p.Q / LPM)
        assert p.p3 == pytest.approx(pc, abs=0.02 * BAR), (p.setting, p.Q / LPM)


def test_multistep_steady_state_does_not_depend_on_the_line_volumes():
    circuit = Circuit.from_file(rig.MULTISTEP_NETLIST)
    base = {"Q": 47.4 * LPM, "p2": 5.6 * BAR, "p_crack": 152.0 * BAR}
    a = rig.steady_point(circuit, base)
    b = rig.steady_point(circuit, base | {"V_p1": 3e-4, "V_v1": 3e-4, "V_v2": 3e-4, "V_pc": 3e-4})
    assert b.p1 == pytest.approx(a.p1, abs=2e-3 * BAR) and b.p3 == pytest.approx(a.p3, abs=2e-3 * BAR)


def test_multistep_rmse_no_worse_than_the_thesiss_model(multistep, capsys):
    """With the flow force of eq. 3.13 on, as the thesis's chapter-3 model: RMSE of p1 and p3 over the 21
    points against the measurements no worse than the thesis's Simulink results against the same points.
    Without the flow force (chapter-2 model) the RMSE is printed only."""
    measured, thesis = rig.measured_points(), rig.measured_points(rig.THESIS_MULTISTEP)
    limit = {n: rig.rmse((thesis.columns[n] - measured.columns[n]) / BAR) for n in ("p1", "p3")}
    on, off = rig.point_errors(multistep[1.0]), rig.point_errors(multistep[0.0])
    with capsys.disabled():
        print(f"\n  multistep RMSE [bar], flow_force 1: p1 {rig.rmse(on['p1']):.2f}, p3 {rig.rmse(on['p3']):.2f}; "
              f"flow_force 0: p1 {rig.rmse(off['p1']):.2f}, p3 {rig.rmse(off['p3']):.2f}; "
              f"thesis: p1 {limit['p1']:.2f}, p3 {limit['p3']:.2f}")
    assert rig.rmse(on["p1"]) <= limit["p1"]
    assert rig.rmse(on["p3"]) <= limit["p3"]


def test_multistep_csv_has_the_measured_files_format(multistep, tmp_path):
    out = tmp_path / "rig_multistep.csv"
    rig.write_multistep_csv(multistep[1.0], out)
    table = rig.measured_points(out)
    measured = rig.measured_points()
    assert table.group == measured.group == "setting" and table.labels == measured.labels
    assert {n: table.units[n] for n in table.units} == {n: measured.units[n] for n in measured.units}
    assert np.allclose(table.columns["p3"], [p.p3 for p in multistep[1.0]], rtol=0, atol=1e-6 * BAR)


def test_steady_point_refuses_a_run_that_does_not_settle():
    """With the line volumes at 0.01 l the equilibrium of setting 3 at 12.8 l/min is unstable in this model
    (a limit cycle): the driver must say so rather than report a value."""
    circuit = Circuit.from_file(rig.MULTISTEP_NETLIST)
    small = {"Q": 12.8 * LPM, "p2": 1.7 * BAR, "p_crack": 211.5 * BAR, "V_p1": 1e-5, "V_v1": 1e-5, "V_v2": 1e-5}
    with pytest.raises(rig.NotSettled, match="still vary"):
        rig.steady_point(circuit, small, t_end=1.0, t_max=2.0)


# ---------------------------------------------------------------- tier 2: the crack-pressure rig
def test_crack_pressure_within_1_bar_of_table_3_2():
    """Eq. 3.2 on the simulated pv1, pv2, pc averaged over 0.05...0.5 l/min through the valve, as table 3.2
    was read: the crack pressure of each setting within 1 bar of the table (the block's p_crack is the
    table's value; what is tested is that the rig, read as the thesis read it, gives it back: eq. 3.2 assumes
    u = 0 and equal drops over the two check valves, neither of which holds exactly)."""
    readings = rig.run_crack()
    assert set(readings) == {"1", "2", "3"}
    for setting, r in readings.items():
        assert not r["warnings"]
        assert abs(r["pcr"] - r["p_crack"]) <= 1.0 * BAR, (setting, r["pcr"] / BAR, r["p_crack"] / BAR)


# ---------------------------------------------------------------- tier 2: the step responses
@pytest.fixture(scope="module")
def steps():
    circuit = Circuit.from_file(rig.STEP_NETLIST)
    out = {}
    for setting, pcr in rig.crack_settings().items():
        for u in (1.0, 0.5):
            values = {"p_crack": pcr, "u_step": u}
            result = circuit.simulate(values)
            out[(setting, u)] = (result, rig.step_metrics(result.t, result["p3"], circuit.vectors(values).values["t_step"]))
    return out


def test_step_responses_are_physical(steps):
    """p3 after the PVG step: rises (positive rise time), its first peak lies above the settled value (the
    oil is compressed before the relief opens), and it settles within the 2 % band before the last 10 % of
    the run over which the settled value is averaged; no cavitation. The one warning allowed: at full
    stroke the relief flow overshoots the range the flow force was fitted on (100 l/min) for a few ms, by
    under 1 l/min (100.1 l/min at setting 1), which the run says (blocks/valid_ranges.py)."""
    fit = re.compile(r"mcv: C[12]\.flow left its valid range \(at least -100 l/min\) .* reaching (-[\d.]+) l/min")
    for (setting, u), (result, m) in steps.items():
        beyond = [fit.match(w) for w in result.warnings]
        assert all(beyond), (setting, u, result.warnings)
        assert all(-float(b.group(1)) < 101.0 for b in beyond) and (u == 1.0 or not beyond), (setting, u, beyond)
        assert m["rise"] > 0.0
        assert m["p_peak"] > m["p_end"], (setting, u, m)
        assert m["settle"] < 0.9 * m["t_run"], (setting, u, m)


def test_step_responses_settle_at_the_closed_form_steady_state(steps):
    """The settled p1 and p3 are the closed-form steady state at the settled flow and return pressure
    (the PVG's compensated flow and its B -> T drop; budget as in the multistep test plus the end of the
    run's residual motion: 0.05 bar)."""
    pcr = rig.crack_settings()
    for (setting, u), (result, m) in steps.items():
        Q, p2 = result["Q"][-1], result["p2"][-1]
        p1, _, pc, _ = steady_state(Q, p2, pcr[setting])
        assert result["p3"][-1] == pytest.approx(pc, abs=0.05 * BAR), (setting, u)
        assert result["p1"][-1] == pytest.approx(p1, abs=0.05 * BAR), (setting, u)
    # the 50 % step settles at a lower flow than the 100 % one (PVG: 7 bar across 43 % vs 100 % of its area)
    for setting in pcr:
        assert steps[(setting, 0.5)][0]["Q"][-1] < steps[(setting, 1.0)][0]["Q"][-1]
