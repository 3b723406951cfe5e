"""The generic hydraulic blocks, each alone against its closed form (raw Python functions called by name),
plus one numba compilation of every equation function compared with the pure-Python call."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from blocks.block import argument_names
from blocks.library.hydraulic.accumulator import Accumulator
from blocks.library.hydraulic.check_valve import CheckValve
from blocks.library.hydraulic.counterbalance_valve import CounterbalanceValve
from blocks.library.hydraulic.cylinder import Cylinder
from blocks.library.hydraulic.flow import turbulent_flow
from blocks.library.hydraulic.flow_control_valve import FlowControlValve
from blocks.library.hydraulic.flow_sensor import FlowSensor
from blocks.library.hydraulic.flow_source import FlowSource
from blocks.library.hydraulic.flow_source_signal import FlowSourceSignal
from blocks.library.hydraulic.hydraulic_motor import HydraulicMotor
from blocks.library.hydraulic.laminar_orifice import LaminarOrifice
from blocks.library.hydraulic.orifice import Orifice
from blocks.library.hydraulic.pressure_reducing_valve import PressureReducingValve
from blocks.library.hydraulic.pressure_sensor import PressureSensor
from blocks.library.hydraulic.pressure_source import PressureSource
from blocks.library.hydraulic.pump import Pump
from blocks.library.hydraulic.relief_valve import ReliefValve
from blocks.library.hydraulic.shuttle_valve import ShuttleValve
from blocks.library.hydraulic.tank import Tank
from blocks.library.hydraulic.valve_4_3 import Valve43
from blocks.library.hydraulic.variable_orifice import VariableOrifice
from blocks.library.hydraulic.variable_pump import VariablePump
from blocks.library.hydraulic.volume import Volume
from blocks.registry import get

RHO = 850.0
BAR = 1e5
P_VAP = -0.9 * BAR  # the fluid's vapour pressure (gauge), for the displacement machines


def named(cls, values) -> dict[str, float]:
    """Map a derivatives() result onto the block's derivative names (checks the tuple length too)."""
    names = cls.derivative_names()
    assert len(values) == len(names), (cls.__name__, names, values)
    return dict(zip(names, values))


def sqrt_law(dp, area, cd=0.7, rho=RHO):
    return math.copysign(cd * area * math.sqrt(2.0 * abs(dp) / rho), dp)


# ---------------------------------------------------------------- registration
@pytest.mark.parametrize(
    "type_name, cls",
    [
        ("orifice", Orifice), ("pressure_source", PressureSource), ("tank", Tank), ("flow_source", FlowSource),
        ("flow_source_signal", FlowSourceSignal), ("volume", Volume), ("variable_orifice", VariableOrifice),
        ("laminar_orifice", LaminarOrifice), ("check_valve", CheckValve), ("relief_valve", ReliefValve),
        ("pressure_sensor", PressureSensor), ("flow_sensor", FlowSensor), ("hydraulic_motor", HydraulicMotor),
        ("valve_4_3", Valve43), ("cylinder", Cylinder), ("accumulator", Accumulator), ("pump", Pump),
        ("variable_pump", VariablePump),
        ("pressure_reducing_valve", PressureReducingValve), ("flow_control_valve", FlowControlValve),
        ("counterbalance_valve", CounterbalanceValve), ("shuttle_valve", ShuttleValve),
    ],
)
def test_hydraulic_block_registered(type_name, cls):
    assert get(type_name) is cls
    assert cls.summary()


# ---------------------------------------------------------------- orifices
def test_orifice_sqrt_law_at_large_dp():
    A, dp_t = 1e-5, 1e3
    for dp in (50 * BAR, 200 * BAR):
        q_a, q_b = Orifice.derivatives(a=dp, b=0.0, A=A, Cd=0.7, dp_t=dp_t, rho=RHO)
        assert q_b == pytest.approx(sqrt_law(dp, A), rel=1e-6)
        assert q_a == -q_b


@settings(max_examples=200, deadline=None)
@given(pa=st.floats(-1e7, 3e7), pb=st.floats(-1e7, 3e7))
@example(pa=5e-324, pb=0.0)  # found by CI: a subnormal pressure drop
def test_orifice_sign_symmetry(pa, pb):
    kw = dict(A=2e-5, Cd=0.65, dp_t=1e5, rho=RHO)
    q_ab = Orifice.derivatives(a=pa, b=pb, **kw)
    q_ba = Orifice.derivatives(a=pb, b=pa, **kw)
    assert q_ab[1] == pytest.approx(-q_ba[1], rel=1e-12, abs=1e-300)
    assert q_ab[0] + q_ab[1] == 0.0
    assert q_ab[1] * (pa - pb) >= 0.0  # never against the pressure drop
    if abs(pa - pb) > 1e-200:  # below, the laminar flow K*dp underflows to 0 in floating point (dp = 5e-324 Pa)
        assert q_ab[1] != 0.0


def test_orifice_linear_near_zero():
    A, dp_t = 1e-5, 1e5
    dp = 1.0
    q = Orifice.derivatives(a=dp, b=0.0, A=A, Cd=0.7, dp_t=dp_t, rho=RHO)[1]
    assert q == pytest.approx(0.7 * A * math.sqrt(2 / RHO) * dp / math.sqrt(dp_t), rel=1e-9)


def test_variable_orifice_matches_orifice_and_clips_at_zero():
    kw = dict(Cd=0.7, dp_t=1e5, rho=RHO)
    assert VariableOrifice.derivatives(a=3e6, b=1e6, A=1e-5, **kw) == Orifice.derivatives(a=3e6, b=1e6, A=1e-5, **kw)
    assert VariableOrifice.derivatives(a=3e6, b=1e6, A=-1e-5, **kw) == (0.0, 0.0)


def test_laminar_orifice():
    q = named(LaminarOrifice, LaminarOrifice.derivatives(a=5e6, b=1e6, G=2e-12))
    assert q["q_b"] == pytest.approx(8e-6)
    assert q["q_a"] == -q["q_b"]


# ---------------------------------------------------------------- sources, volume, sensors
def test_tank_and_sources():
    assert Tank.prescribes == ("port",)
    assert Tank.param("p").default == 0.0
    assert Tank.outputs(p=0.0) == (0.0,)
    assert named(FlowSource, FlowSource.derivatives(q=1e-4)) == {"q_a": -1e-4, "q_b": 1e-4}
    assert named(FlowSourceSignal, FlowSourceSignal.derivatives(q=-2e-4)) == {"q_a": 2e-4, "q_b": -2e-4}


def test_volume_stores_and_passes_no_flow():
    assert named(Volume, Volume.derivatives(V=2e-5)) == {"q_port": 0.0, "V_port": 2e-5}


def test_pressure_sensor():
    assert PressureSensor.outputs(port=1.5e7) == (1.5e7,)
    assert named(PressureSensor, PressureSensor.derivatives()) == {"q_port": 0.0}


def test_flow_sensor_outputs_the_flow_it_passes():
    R = 1e10
    (q_out,) = FlowSensor.outputs(a=2e6, b=1e6, R=R)
    q = named(FlowSensor, FlowSensor.derivatives(a=2e6, b=1e6, R=R))
    assert q_out == pytest.approx(1e-4)
    assert q["q_b"] == q_out and q["q_a"] == -q_out


# ---------------------------------------------------------------- check and relief valves
CV = dict(A_max=2e-5, p_crack=1 * BAR, p_open=3 * BAR, A_leak=1e-9, Cd=0.7, dp_t=1e4, rho=RHO)


def cv_flow(dp, **over):
    kw = {**CV, **over}
    return named(CheckValve, CheckValve.derivatives(a=dp + 2e6, b=2e6, **kw))


def test_check_valve_closed_below_crack_only_leakage():
    for dp in (-50 * BAR, -1 * BAR, 0.0, 0.5 * BAR, 1 * BAR):
        q = cv_flow(dp)
        assert q["q_b"] == pytest.approx(turbulent_flow(dp, CV["A_leak"], 0.7, RHO, CV["dp_t"]), rel=1e-12, abs=1e-300)
        assert q["q_a"] == -q["q_b"]
    assert cv_flow(0.5 * BAR, A_leak=0.0)["q_b"] == 0.0
    assert cv_flow(-50 * BAR, A_leak=0.0)["q_b"] == 0.0


def test_check_valve_partly_and_fully_open():
    dp_mid = 2 * BAR  # half way from crack to full open: smooth_step = 1/2
    area_mid = CV["A_leak"] + 0.5 * (CV["A_max"] - CV["A_leak"])
    assert cv_flow(dp_mid)["q_b"] == pytest.approx(turbulent_flow(dp_mid, area_mid, 0.7, RHO, CV["dp_t"]), rel=1e-12)
    q_lo = cv_flow(1.2 * BAR)["q_b"]
    assert turbulent_flow(1.2 * BAR, CV["A_leak"], 0.7, RHO, CV["dp_t"]) < q_lo
    assert q_lo < turbulent_flow(1.2 * BAR, CV["A_max"], 0.7, RHO, CV["dp_t"])
    for dp in (3 * BAR, 10 * BAR, 100 * BAR):
        assert cv_flow(dp)["q_b"] == pytest.approx(turbulent_flow(dp, CV["A_max"], 0.7, RHO, CV["dp_t"]), rel=1e-12)
    assert cv_flow(100 * BAR)["q_b"] == pytest.approx(sqrt_law(100 * BAR, CV["A_max"]), rel=1e-6)


def test_check_valve_flow_continuous_and_monotone():
    dps = [CV["p_crack"] + i * 1.0 for i in range(-50000, 250000, 500)]  # through crack and full open
    qs = [cv_flow(dp)["q_b"] for dp in dps]
    assert all(q2 > q1 for q1, q2 in zip(qs, qs[1:]))
    for edge in (CV["p_crack"], CV["p_open"]):
        eps = 1e-3
        assert cv_flow(edge + eps)["q_b"] == pytest.approx(cv_flow(edge - eps)["q_b"], rel=1e-6)


RV = dict(p_set=200 * BAR, p_open=210 * BAR, A_max=5e-5, A_leak=1e-9, Cd=0.7, dp_t=1e5, rho=RHO)


def rv_flow(p_in, p_out=0.0):
    return named(ReliefValve, ReliefValve.derivatives(a=p_in, b=p_out, **RV))


def test_relief_valve_closed_partly_open_full():
    for p in (0.0, 100 * BAR, 199.9 * BAR, 200 * BAR):
        assert rv_flow(p)["q_b"] == pytest.approx(turbulent_flow(p, RV["A_leak"], 0.7, RHO, RV["dp_t"]), rel=1e-12)
    area_mid = RV["A_leak"] + 0.5 * (RV["A_max"] - RV["A_leak"])
    assert rv_flow(205 * BAR)["q_b"] == pytest.approx(turbulent_flow(205 * BAR, area_mid, 0.7, RHO, 1e5), rel=1e-12)
    for p in (210 * BAR, 250 * BAR):
        q = rv_flow(p)
        assert q["q_b"] == pytest.approx(turbulent_flow(p, RV["A_max"], 0.7, RHO, 1e5), rel=1e-12)
        assert q["q_a"] == -q["q_b"]
    # it opens on the difference p_in - p_out, not on p_in alone
    assert rv_flow(250 * BAR, 100 * BAR)["q_b"] == pytest.approx(
        turbulent_flow(150 * BAR, RV["A_leak"], 0.7, RHO, 1e5), rel=1e-12
    )



def test_a_full_open_pressure_at_or_below_the_setting_is_refused():
    """p_open <= p_set would make the opening a jump of the whole area (a solver that then crawls for
    seconds before it gives up); the values are refused with both numbers, as vphs validate shows them."""
    areas = {"A_max": 1e-5, "A_leak": 1e-9}  # check_values sees every value; the areas are checked too
    assert ReliefValve.check_values({"p_set": 200 * BAR, "p_open": 210 * BAR, **areas}) is None
    assert CheckValve.check_values({"p_crack": 0.2 * BAR, "p_open": 0.7 * BAR, **areas}) is None
    for p_open in (200 * BAR, 190 * BAR):
        said = ReliefValve.check_values({"p_set": 200 * BAR, "p_open": p_open, **areas})
        assert said == f"p_open = {p_open / BAR:g} bar must be above p_set = 200 bar (the valve opens over p_set ... p_open)"
    assert "must be above p_crack = 0.5 bar" in CheckValve.check_values({"p_crack": 0.5 * BAR, "p_open": 0.2 * BAR,
                                                                        **areas})


def test_a_cylinder_whose_annulus_is_larger_than_its_piston_is_refused():
    # A_B = pi*(30 mm)^2 on a 50 mm bore ran without a word; a double-rod cylinder (A_B = A_A) is fine
    bore = math.pi * 0.025**2
    values = {"A_A": bore, "stroke": 1.0}
    assert Cylinder.check_values({**values, "A_B": bore}) is None
    assert Cylinder.check_values({**values, "A_B": bore - math.pi * 0.014**2}) is None
    said = Cylinder.check_values({**values, "A_B": math.pi * 0.03**2})
    assert said.startswith("the rod-side area A_B = 2827.4 mm^2 is larger than the piston-side A_A = 1963.5 mm^2")


# ---------------------------------------------------------------- motor
MOTOR = dict(D=2 * 30e-6 / (2 * math.pi), J_m=0.0068, eta_hm=1.0, w_w=0.1, p_vap=P_VAP)


def test_motor_flows_and_torque():
    pa, pb, w, G = 150 * BAR, 20 * BAR, 12.0, 1e-12
    d = named(HydraulicMotor, HydraulicMotor.derivatives(a=pa, b=pb, shaft=w, G_leak=G, **MOTOR))
    q_m = MOTOR["D"] * w + G * (pa - pb)
    assert d["q_a"] == pytest.approx(-q_m) and d["q_b"] == pytest.approx(q_m)
    assert d["tau_shaft"] == pytest.approx(MOTOR["D"] * (pa - pb))
    assert d["J_shaft"] == MOTOR["J_m"]
    assert d["q_a"] + d["q_b"] == 0.0


@settings(max_examples=200, deadline=None)
@given(pa=st.floats(0, 4e7), pb=st.floats(0, 4e7), w=st.floats(-300, 300), G=st.floats(0, 1e-10))
def test_motor_power_balance(pa, pb, w, G):
    d = named(HydraulicMotor, HydraulicMotor.derivatives(a=pa, b=pb, shaft=w, G_leak=G, **MOTOR))
    hydraulic_in = -(d["q_a"] * pa + d["q_b"] * pb)  # power the motor takes from the nets
    shaft_out = d["tau_shaft"] * w
    leak_loss = G * (pa - pb) ** 2
    # the balance is a difference of products of large pressures: its rounding error scales with the
    # magnitudes of the terms summed, |q_a*p_a| + |q_b*p_b|, not only with the (possibly tiny) pressure drop
    scale = abs(pa - pb) * (MOTOR["D"] * abs(w) + G * abs(pa - pb)) + abs(d["q_a"] * pa) + abs(d["q_b"] * pb) + 1e-30
    assert abs(hydraulic_in - shaft_out - leak_loss) <= 1e-9 * scale
    if G == 0.0:
        assert (pa - pb) * MOTOR["D"] * w == pytest.approx(shaft_out, rel=1e-12, abs=1e-300)


def test_motor_friction_is_the_lost_fraction_of_hydraulic_torque_opposing_motion():
    """tau = tau_h - (1 - eta_hm)*|tau_h|*tanh(w/w_w): far from standstill the loss is (1 - eta_hm)|tau_h|."""
    lossy = {**MOTOR, "eta_hm": 0.9}
    tau_h = MOTOR["D"] * 130 * BAR
    for w, sign in ((50.0, 1.0), (-50.0, -1.0)):
        d = named(HydraulicMotor, HydraulicMotor.derivatives(a=150 * BAR, b=20 * BAR, shaft=w, G_leak=0.0, **lossy))
        assert d["tau_shaft"] == pytest.approx(tau_h - sign * 0.1 * tau_h, rel=1e-9)
    # braking (torque against motion): the loss still opposes the motion, so it adds to the braking torque
    d = named(HydraulicMotor, HydraulicMotor.derivatives(a=20 * BAR, b=150 * BAR, shaft=50.0, G_leak=0.0, **lossy))
    assert d["tau_shaft"] == pytest.approx(-tau_h - 0.1 * tau_h, rel=1e-9)
    # continuous through standstill
    d0 = named(HydraulicMotor, HydraulicMotor.derivatives(a=150 * BAR, b=20 * BAR, shaft=0.0, G_leak=0.0, **lossy))
    assert d0["tau_shaft"] == pytest.approx(tau_h)


# ---------------------------------------------------------------- pumps
PUMP = dict(D=28e-6 / (2 * math.pi), J_p=0.002, eta_hm=1.0, w_w=0.1, p_vap=P_VAP)  # 28 cm^3/rev


def pump(ps, pp, w, G=0.0, **over):
    return named(Pump, Pump.derivatives(s=ps, p=pp, shaft=w, G_leak=G, **{**PUMP, **over}))


def test_pump_flows_and_torque():
    """q = D*w - G_leak*(p_p - p_s) from s to p; the oil brakes the shaft with D*(p_p - p_s)."""
    ps, pp, w, G = 0.5 * BAR, 180 * BAR, 150.0, 2e-12
    d = pump(ps, pp, w, G)
    q = PUMP["D"] * w - G * (pp - ps)
    assert q == pytest.approx(28e-6 * 150.0 / (2 * math.pi) - 2e-12 * 179.5e5, rel=1e-12)  # 37.4 l/min
    assert d["q_p"] == pytest.approx(q, rel=1e-12) and d["q_s"] == pytest.approx(-q, rel=1e-12)
    assert d["q_s"] + d["q_p"] == 0.0
    assert d["tau_shaft"] == pytest.approx(-PUMP["D"] * (pp - ps), rel=1e-12)
    assert d["tau_shaft"] < 0.0  # pumping against pressure brakes the shaft
    assert d["J_shaft"] == PUMP["J_p"]
    # no pressure rise: the displaced flow and no torque; standing still: only the leakage, backwards
    assert pump(0.0, 0.0, w) == {"q_s": pytest.approx(-PUMP["D"] * w), "q_p": pytest.approx(PUMP["D"] * w),
                                 "tau_shaft": 0.0, "J_shaft": PUMP["J_p"]}
    assert pump(ps, pp, 0.0, G)["q_p"] == pytest.approx(-G * (pp - ps), rel=1e-12)


@settings(max_examples=200, deadline=None)
@given(dp=st.floats(1e3, 4e7), w=st.floats(5.0, 300.0), G=st.floats(0, 1e-10), eta=st.floats(0.5, 1.0),
       backwards=st.booleans())
def test_pump_shaft_power_is_hydraulic_power_over_eta_hm(dp, w, G, eta, backwards):
    """Pumping (dp*w > 0, |w| >= 50 w_w so tanh = 1): shaft power in -tau*w = D*dp*w/eta_hm, and the oil gets
    q_p*p_p + q_s*p_s = D*dp*w - G_leak*dp^2. Run backwards with the pressure on s, it pumps s <- p alike."""
    ps, pp = (dp, 0.0) if backwards else (0.0, dp)
    w = -w if backwards else w
    d = pump(ps, pp, w, G, eta_hm=eta)
    shaft_in = -d["tau_shaft"] * w
    hydraulic_out = d["q_p"] * pp + d["q_s"] * ps
    ideal = PUMP["D"] * dp * abs(w)
    assert shaft_in == pytest.approx(ideal / eta, rel=1e-12)
    assert hydraulic_out == pytest.approx(ideal - G * dp * dp, rel=1e-9, abs=1e-12 * ideal)
    assert shaft_in >= hydraulic_out * (1 - 1e-12)  # up to round-off when lossless


def test_pump_motoring_when_the_outlet_pressure_drives_it_backwards():
    """dp > 0, w < 0: oil flows p -> s and the shaft is driven (tau*w > 0); the friction (1/eta_hm - 1)|tau_h|
    still opposes w, so the shaft gets (2 - 1/eta_hm) of the hydraulic power D*dp*|w|."""
    dp, w, eta = 150 * BAR, -80.0, 0.9
    d = pump(0.0, dp, w, eta_hm=eta)
    assert d["q_p"] == pytest.approx(PUMP["D"] * w) and d["q_p"] < 0.0
    assert d["tau_shaft"] * w == pytest.approx((2.0 - 1.0 / eta) * PUMP["D"] * dp * abs(w), rel=1e-12)
    assert d["tau_shaft"] * w < PUMP["D"] * dp * abs(w)
    # at eta_hm = 0.5 (the lower bound) the friction takes all of it
    assert pump(0.0, dp, w, eta_hm=0.5)["tau_shaft"] == pytest.approx(0.0, abs=1e-12 * PUMP["D"] * dp)
    assert Pump.param("eta_hm").check(0.49) is not None


def test_pump_friction_smooth_through_standstill():
    dp, eta = 100 * BAR, 0.8
    tau_h = -PUMP["D"] * dp
    for w in (-1e-3, 0.0, 1e-3, 0.05):
        expected = tau_h - (1 / eta - 1) * abs(tau_h) * math.tanh(w / PUMP["w_w"])
        assert pump(0.0, dp, w, eta_hm=eta)["tau_shaft"] == pytest.approx(expected, rel=1e-12)
    assert pump(0.0, dp, 0.0, eta_hm=eta)["tau_shaft"] == pytest.approx(tau_h, rel=1e-12)


VPUMP = dict(D_max=45e-6 / (2 * math.pi), p_c=200 * BAR, dp_c=4 * BAR, tau_c=0.02, eps_max=1.0, J_p=0.004,
             eta_hm=1.0, w_w=0.1, p_vap=P_VAP)


def vpump(ps, pp, w, eps, G=0.0, **over):
    return named(VariablePump, VariablePump.derivatives(s=ps, p=pp, shaft=w, eps=eps, G_leak=G, **{**VPUMP, **over}))


def cubic_step(x, x0, width):
    """The C1 ramp the valves open by, written out: 0 below x0, 1 above x0 + width, 3s^2 - 2s^3 between."""
    s = min(max((x - x0) / width, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


FILL_BAND = 500.0  # Pa: below p_vap the chambers' fill falls from 1 to 0 over this band (0.005 bar)


@pytest.mark.parametrize("below, fill", [(-1e5, 1.0), (0.0, 1.0), (FILL_BAND / 4, 1 - 0.15625), (FILL_BAND / 2, 0.5),
                                         (FILL_BAND, 0.0), (0.3 * BAR, 0.0)])
@pytest.mark.parametrize("backwards", [False, True])
def test_pump_chambers_fill_only_from_liquid(below, fill, backwards):
    """The side the chambers fill from (s turning forwards, p backwards) at p_vap - below: the displaced
    flow scales with the fill f = 1 - cubic_step(below, 0, 0.005 bar); the leakage does not, nor does the
    oil's torque (vapour-filled chambers are flooded from the outlet and work against its full pressure)."""
    G, w, high = 2e-12, 150.0, 120 * BAR
    p_in = P_VAP - below
    ps, pp, w = (high, p_in, -w) if backwards else (p_in, high, w)
    assert fill == pytest.approx(1 - cubic_step(below, 0.0, FILL_BAND), abs=1e-12)
    d = pump(ps, pp, w, G)
    assert d["q_p"] == pytest.approx(fill * PUMP["D"] * w - G * (pp - ps), rel=1e-12, abs=1e-18)
    assert d["q_s"] == -d["q_p"]
    assert d["tau_shaft"] == pytest.approx(-PUMP["D"] * (pp - ps), rel=1e-12)
    v = vpump(ps, pp, w, 0.4, G)
    assert v["q_p"] == pytest.approx(fill * 0.4 * VPUMP["D_max"] * w - G * (pp - ps), rel=1e-12, abs=1e-18)


@pytest.mark.parametrize("below, fill", [(0.0, 1.0), (FILL_BAND / 2, 0.5), (FILL_BAND, 0.0)])
@pytest.mark.parametrize("backwards", [False, True])
def test_an_overrunning_motor_brakes_only_on_the_oil_its_inlet_holds(below, fill, backwards):
    """A load overrunning the motor (w > 0 with p_b > p_a: braking) draws its inlet a down; below the vapour
    pressure the chambers take in vapour, and the flow through it scales with the fill, as for the pumps
    (backwards: the inlet is b). The leakage does not, nor does the braking torque D*(p_a - p_b), which is
    continuous through w = 0 where the side the chambers fill from changes."""
    G, w, high = 1e-12, 80.0, 150 * BAR
    p_in = P_VAP - below
    pa, pb, w = (high, p_in, -w) if backwards else (p_in, high, w)
    d = named(HydraulicMotor, HydraulicMotor.derivatives(a=pa, b=pb, shaft=w, G_leak=G, **MOTOR))
    assert d["q_b"] == pytest.approx(fill * MOTOR["D"] * w + G * (pa - pb), rel=1e-12, abs=1e-18)
    assert d["tau_shaft"] == pytest.approx(MOTOR["D"] * (pa - pb), rel=1e-12)
    assert d["tau_shaft"] * w < 0.0  # braking
    still = [named(HydraulicMotor, HydraulicMotor.derivatives(a=pa, b=pb, shaft=s, G_leak=G, **MOTOR))["tau_shaft"]
             for s in (-1e-9, 0.0, 1e-9)]
    assert still == pytest.approx([MOTOR["D"] * (pa - pb)] * 3, rel=1e-12)


@pytest.mark.parametrize("eps_max", [1.0, 0.6])
def test_variable_pump_compensator_target(eps_max):
    """d(eps)/dt = (eps_target - eps)/tau_c: full stroke (eps_max) below p_c, eps_max/2 mid-band,
    eps_max*(1 - 0.15625) a quarter into the band, zero from p_c + dp_c up."""
    p_c, dp_c, tau_c, eps = VPUMP["p_c"], VPUMP["dp_c"], VPUMP["tau_c"], 0.3
    cases = [(0.0, eps_max), (100 * BAR, eps_max), (p_c, eps_max), (p_c + dp_c / 4, eps_max * (1 - 0.15625)),
             (p_c + dp_c / 2, eps_max / 2), (p_c + dp_c, 0.0), (300 * BAR, 0.0)]
    for dp, target in cases:
        assert target == pytest.approx(eps_max * (1 - cubic_step(dp, p_c, dp_c)), rel=1e-12)
        d = vpump(2 * BAR, 2 * BAR + dp, 150.0, eps, eps_max=eps_max)  # the setting is on p_p - p_s
        assert d["der_eps"] == pytest.approx((target - eps) / tau_c, rel=1e-12, abs=1e-12)


def test_variable_pump_flow_and_torque_scale_with_the_displacement():
    ps, pp, w, eps, G = 0.0, 150 * BAR, 150.0, 0.4, 1e-12
    d = vpump(ps, pp, w, eps, G)
    D = eps * VPUMP["D_max"]
    assert d["q_p"] == pytest.approx(D * w - G * pp, rel=1e-12) and d["q_s"] == -d["q_p"]
    assert d["tau_shaft"] == pytest.approx(-D * pp, rel=1e-12)
    assert d["J_shaft"] == VPUMP["J_p"]
    (out,) = VariablePump.outputs(eps=eps, eps_max=1.0)
    assert out == eps
    # lossy and pumping: shaft power = hydraulic power / eta_hm
    lossy = vpump(ps, pp, w, eps, eta_hm=0.85)
    assert -lossy["tau_shaft"] * w == pytest.approx(D * pp * w / 0.85, rel=1e-12)


def test_variable_pump_displacement_clipped_to_its_range():
    """The state beyond [0, eps_max] (a start above eps_max, a solver's overshoot) displaces eps_max or 0."""
    w, pp = 150.0, 100 * BAR
    assert VariablePump.outputs(eps=1.0, eps_max=0.6) == (0.6,)
    assert VariablePump.outputs(eps=-0.01, eps_max=0.6) == (0.0,)
    high = vpump(0.0, pp, w, 1.0, eps_max=0.6)
    assert high["q_p"] == pytest.approx(0.6 * VPUMP["D_max"] * w, rel=1e-12)
    assert high["der_eps"] == pytest.approx((0.6 - 1.0) / VPUMP["tau_c"], rel=1e-12)  # the state still lags back
    low = vpump(0.0, pp, w, -0.01, G=1e-12)
    assert low["q_p"] == pytest.approx(-1e-12 * pp, rel=1e-12) and low["tau_shaft"] == 0.0
    assert VariablePump.check_values({"initial.eps": 0.5}) is None
    for start in (-0.1, 1.2):
        assert "outside [0, 1]" in VariablePump.check_values({"initial.eps": start})


@settings(max_examples=200, deadline=None)
@given(dp=st.floats(-1e6, 4e7), eps_max=st.floats(0.0, 1.0))
def test_variable_pump_lag_points_into_its_range(dp, eps_max):
    """At eps = 0 the state cannot fall, at eps = eps_max it cannot rise: started in range, it stays."""
    assert vpump(0.0, dp, 100.0, 0.0, eps_max=eps_max)["der_eps"] >= 0.0
    assert vpump(0.0, dp, 100.0, eps_max, eps_max=eps_max)["der_eps"] <= 0.0


# ---------------------------------------------------------------- 4/3 valve
VALVE = dict(A_max=125e-6, x_db=0.02, A_leak=0.0, A_float=0.0, A_bypass=0.0, x_c=0.05, Cd=0.7, dp_t=1e5, rho=RHO)
PS, PT, PA, PB = 207 * BAR, 0.0, 90 * BAR, 40 * BAR


def valve(x, P=PS, T=PT, A=PA, B=PB, **over):
    return named(Valve43, Valve43.derivatives(P=P, T=T, A=A, B=B, x=x, **{**VALVE, **over}))


def edge(dp, area):
    return turbulent_flow(dp, area, VALVE["Cd"], RHO, VALVE["dp_t"])


def test_valve_positive_spool_opens_PA_and_BT():
    x = 0.5
    area = VALVE["A_max"] * (x - 0.02) / 0.98
    q_PA, q_BT = edge(PS - PA, area), edge(PB - PT, area)
    d = valve(x)
    assert q_PA > 0 and q_BT > 0
    assert d["q_P"] == pytest.approx(-q_PA) and d["q_A"] == pytest.approx(q_PA)
    assert d["q_B"] == pytest.approx(-q_BT) and d["q_T"] == pytest.approx(q_BT)


def test_valve_negative_spool_opens_PB_and_AT():
    x = -0.7
    area = VALVE["A_max"] * (0.7 - 0.02) / 0.98
    q_PB, q_AT = edge(PS - PB, area), edge(PA - PT, area)
    d = valve(x)
    assert q_PB > 0 and q_AT > 0
    assert d["q_P"] == pytest.approx(-q_PB) and d["q_B"] == pytest.approx(q_PB)
    assert d["q_A"] == pytest.approx(-q_AT) and d["q_T"] == pytest.approx(q_AT)


def test_valve_full_stroke_gives_full_area():
    assert valve(1.0)["q_A"] == pytest.approx(edge(PS - PA, VALVE["A_max"]), rel=1e-12)
    assert valve(-1.0)["q_B"] == pytest.approx(edge(PS - PB, VALVE["A_max"]), rel=1e-12)


def test_valve_dead_band_closed_and_leakage():
    for x in (0.0, 0.01, -0.02, 0.02):
        assert all(v == 0.0 for v in valve(x).values())
    leak = 1e-8
    d = valve(0.0, A_leak=leak)
    q_PA, q_BT, q_PB, q_AT = edge(PS - PA, leak), edge(PB - PT, leak), edge(PS - PB, leak), edge(PA - PT, leak)
    assert d["q_P"] == pytest.approx(-(q_PA + q_PB))
    assert d["q_T"] == pytest.approx(q_BT + q_AT)
    assert d["q_A"] == pytest.approx(q_PA - q_AT)
    assert d["q_B"] == pytest.approx(q_PB - q_BT)


def test_valve_reverse_flow_is_negative():
    # load pressure above supply: oil flows back A -> P through the open P-A edge
    d = valve(0.5, A=250 * BAR)
    assert d["q_A"] < 0 and d["q_P"] > 0


@pytest.mark.parametrize("x", [0.0, 0.01, -0.02])
def test_valve_centre_passages_float_tandem_open(x):
    """In the centre (|x| < x_c = 0.05) A and B drain to T through A_float*(1 - |x|/x_c) each, P to T
    through A_bypass*(1 - |x|/x_c); inside the dead band no metering edge is open."""
    open_ = 1.0 - abs(x) / 0.05
    float_ = valve(x, A_float=20e-6)
    assert float_["q_A"] == pytest.approx(-edge(PA - PT, 20e-6 * open_), rel=1e-12)
    assert float_["q_B"] == pytest.approx(-edge(PB - PT, 20e-6 * open_), rel=1e-12)
    assert float_["q_P"] == 0.0
    tandem = valve(x, A_bypass=30e-6)
    assert tandem["q_P"] == pytest.approx(-edge(PS - PT, 30e-6 * open_), rel=1e-12)
    assert tandem["q_A"] == tandem["q_B"] == 0.0  # the work ports held
    both = valve(x, A_float=20e-6, A_bypass=30e-6)
    assert both["q_T"] == pytest.approx(float_["q_T"] + tandem["q_T"], rel=1e-12)


def test_valve_centre_passages_shut_once_the_spool_leaves_the_centre():
    for x in (0.05, -0.3, 1.0):
        assert valve(x, A_float=20e-6, A_bypass=30e-6) == valve(x)


@settings(max_examples=300, deadline=None)
@given(
    P=st.floats(0, 4e7), T=st.floats(0, 4e7), A=st.floats(0, 4e7), B=st.floats(0, 4e7),
    x=st.floats(-1, 1), leak=st.sampled_from([0.0, 1e-9, 1e-6]), centre=st.sampled_from([0.0, 2e-5]),
)
def test_valve_conserves_flow(P, T, A, B, x, leak, centre):
    d = valve(x, P=P, T=T, A=A, B=B, A_leak=leak, A_float=centre, A_bypass=centre / 2)
    total = sum(d.values())
    scale = sum(abs(v) for v in d.values()) + 1e-300
    assert abs(total) <= 1e-12 * scale


# ---------------------------------------------------------------- cylinder
CYL = dict(A_A=3e-3, A_B=1.8e-3, stroke=0.5, V0_A=1e-4, V0_B=8e-5, k_stop=1e8, c_stop=1e5, dx_stop=1e-4)


def cyl(x, v, pA=100 * BAR, pB=20 * BAR, **over):
    return named(Cylinder, Cylinder.derivatives(A=pA, B=pB, rod=v, x=x, **{**CYL, **over}))


def test_cylinder_volumes_flows_force():
    x, v, pA, pB = 0.2, 0.05, 100 * BAR, 20 * BAR
    d = cyl(x, v, pA, pB)
    assert d["V_A"] == pytest.approx(CYL["V0_A"] + CYL["A_A"] * x)
    assert d["V_B"] == pytest.approx(CYL["V0_B"] + CYL["A_B"] * (CYL["stroke"] - x))
    assert d["q_A"] == pytest.approx(-CYL["A_A"] * v)
    assert d["q_B"] == pytest.approx(CYL["A_B"] * v)
    assert d["f_rod"] == pytest.approx(pA * CYL["A_A"] - pB * CYL["A_B"])
    assert d["der_x"] == v


def test_cylinder_volume_rates_match_flows():
    # dV_A/dt = A_A*v is exactly what the piston draws from net A (q_A = -dV_A/dt), likewise for B
    x, v, h = 0.3, 0.1, 1e-6
    d0, d1 = cyl(x, v), cyl(x + v * h, v)
    assert (d1["V_A"] - d0["V_A"]) / h == pytest.approx(-d0["q_A"], rel=1e-6)
    assert (d1["V_B"] - d0["V_B"]) / h == pytest.approx(-d0["q_B"], rel=1e-6)


def test_cylinder_end_stops():
    stroke, k = CYL["stroke"], CYL["k_stop"]
    f_free = cyl(0.25, 0.0)["f_rod"]
    # inside the stroke: no stop force
    assert cyl(0.0, 0.0)["f_rod"] == pytest.approx(f_free) and cyl(stroke, 0.0)["f_rod"] == pytest.approx(f_free)
    # beyond the ends the spring pushes back in, the damper opposes motion
    d = 1e-3
    assert cyl(stroke + d, 0.0)["f_rod"] == pytest.approx(f_free - k * d)
    assert cyl(-d, 0.0)["f_rod"] == pytest.approx(f_free + k * d)
    assert cyl(stroke + d, 0.1)["f_rod"] == pytest.approx(f_free - k * d - CYL["c_stop"] * 0.1)
    assert cyl(-d, -0.1)["f_rod"] == pytest.approx(f_free + k * d + CYL["c_stop"] * 0.1)
    # continuous at contact even while moving (damping fades in over dx_stop)
    for x_edge, v in ((stroke, 0.2), (0.0, -0.2)):
        assert cyl(x_edge + 1e-12, v)["f_rod"] == pytest.approx(cyl(x_edge - 1e-12, v)["f_rod"], abs=1e-2)
    # volumes stay at least the dead volumes when the stops are penetrated
    assert cyl(-d, 0.0)["V_A"] == CYL["V0_A"]
    assert cyl(stroke + d, 0.0)["V_B"] == CYL["V0_B"]


# ---------------------------------------------------------------- pressure-reducing, flow-control, counterbalance, shuttle
def ascending_pairs(values):
    """Neighbouring pairs (lo, hi) of the distinct values, ascending."""
    ordered = sorted(set(values))
    return list(zip(ordered, ordered[1:]))


def kpa(n):
    """Pressures drawn as whole kPa: neighbours differ by at least 1 kPa, a change the laws resolve (a
    drawn difference of 1e-300 Pa is lost in rounding and proves nothing)."""
    return st.lists(st.integers(0, n).map(lambda k: k * 1e3), min_size=2, max_size=6)


# With dp_t = 1 kPa the regularised law is the plain square-root law to (1 + (dp_t/dp)^2)^(-1/4) - 1 > -2.5e-5
# at the smallest drop compared here (1 bar); 1e-4 relative tells any area or pressure error apart.
SQRT_REL = 1e-4
PRV = dict(p_set=50 * BAR, dp_band=5 * BAR, dp_relief=2 * BAR, A_max=20e-6, A_relief=5e-6, A_leak=1e-9, Cd=0.7,
           dp_t=1e3, rho=RHO)


def prv(p_A, p_P=200 * BAR, p_T=0.0, **over):
    return named(PressureReducingValve, PressureReducingValve.derivatives(P=p_P, A=p_A, T=p_T, **{**PRV, **over}))


def prv_expected(p_A, p_P=200 * BAR, p_T=0.0):
    """(q_PA, q_AT) from the edges' areas: the reducing edge closes over 50 ... 55 bar of p_A - p_T, the
    relieving edge opens over 57 ... 62 bar."""
    x = p_A - p_T
    a_pa = 1e-9 + (20e-6 - 1e-9) * (1.0 - cubic_step(x, 50 * BAR, 5 * BAR))
    a_at = 1e-9 + (5e-6 - 1e-9) * cubic_step(x, 57 * BAR, 5 * BAR)
    return sqrt_law(p_P - p_A, a_pa), sqrt_law(p_A - p_T, a_at)


@pytest.mark.parametrize("p_A_bar, p_T_bar", [(5, 0), (30, 0), (49, 0), (52.5, 0), (54, 0), (56, 0), (59.5, 0),
                                              (61, 0), (80, 0), (65, 12), (40, 3)])
def test_pressure_reducing_valve_edges_against_the_square_root_law(p_A_bar, p_T_bar):
    p_A, p_T = p_A_bar * BAR, p_T_bar * BAR
    d = prv(p_A, p_T=p_T)
    q_PA, q_AT = prv_expected(p_A, p_T=p_T)
    assert d["q_P"] == pytest.approx(-q_PA, rel=SQRT_REL)
    assert d["q_T"] == pytest.approx(q_AT, rel=SQRT_REL)
    assert d["q_A"] == pytest.approx(q_PA - q_AT, rel=SQRT_REL)


def test_pressure_reducing_valve_regions():
    """Open below the setting, half shut in the middle of the band, both edges shut in the overlap, relieving above."""
    full = sqrt_law(170 * BAR, 20e-6)
    assert prv(30 * BAR)["q_A"] == pytest.approx(full - sqrt_law(30 * BAR, 1e-9), rel=SQRT_REL)
    assert prv(52.5 * BAR)["q_P"] == pytest.approx(-sqrt_law(147.5 * BAR, 10e-6 + 0.5e-9), rel=SQRT_REL)
    overlap = prv(56 * BAR)
    assert overlap["q_P"] == pytest.approx(-sqrt_law(144 * BAR, 1e-9), rel=SQRT_REL)  # leakage only
    assert overlap["q_T"] == pytest.approx(sqrt_law(56 * BAR, 1e-9), rel=SQRT_REL)
    assert prv(70 * BAR)["q_T"] == pytest.approx(sqrt_law(70 * BAR, 5e-6), rel=SQRT_REL)
    # the setting is on p_A - p_T (the spring chamber drains to T): the same drop closes the edge at any p_T
    assert prv(62.5 * BAR, p_T=10 * BAR)["q_P"] == pytest.approx(-sqrt_law(137.5 * BAR, 10e-6 + 0.5e-9), rel=SQRT_REL)
    # without the overlap the relieving edge starts where the reducing one has shut
    assert prv(56 * BAR, dp_relief=0.0)["q_T"] > 10 * overlap["q_T"]


@settings(max_examples=200, deadline=None)
@given(p_P=st.floats(10 * BAR, 350 * BAR), p_T=st.floats(0.0, 5 * BAR), levels=kpa(35000))
def test_pressure_reducing_valve_outlet_flow_falls_as_the_outlet_pressure_rises(p_P, p_T, levels):
    """Between the tank and the supply pressure, the flow delivered to A strictly falls as p_A rises (the
    reducing edge closes and its drop shrinks, the relieving edge opens and its drop grows): one regulated
    pressure for every load."""
    for lo, hi in ascending_pairs(p for p in levels if p_T <= p <= p_P):
        assert prv(hi, p_P=p_P, p_T=p_T)["q_A"] < prv(lo, p_P=p_P, p_T=p_T)["q_A"]


@settings(max_examples=200, deadline=None)
@given(P=st.floats(-1e6, 4e7), A=st.floats(-1e6, 4e7), T=st.floats(-1e6, 4e7))
def test_pressure_reducing_valve_conserves_flow(P, A, T):
    d = prv(A, p_P=P, p_T=T)
    assert abs(sum(d.values())) <= 1e-12 * (sum(abs(v) for v in d.values()) + 1e-300)


def test_pressure_reducing_valve_continuous_at_the_band_edges():
    for edge in (50, 55, 57, 62):
        lo, hi = prv(edge * BAR - 1e-3), prv(edge * BAR + 1e-3)
        for key in lo:
            assert hi[key] == pytest.approx(lo[key], rel=1e-6, abs=1e-12)


def test_pressure_reducing_valve_refuses_a_leak_above_an_open_area():
    assert PressureReducingValve.check_values(PRV) is None
    said = PressureReducingValve.check_values({**PRV, "A_leak": 1e-5})
    assert said == "A_leak = 1e-05 m^2 must not exceed A_relief = 5e-06 m^2 (the closed edge would pass more than the open one)"


FCV = dict(A_meter=10e-6, dp_c=10 * BAR, knee=0.1, Cd=0.7, dp_t=1e3, rho=RHO)


def fcv(dp, **over):
    return named(FlowControlValve, FlowControlValve.derivatives(a=dp + 30 * BAR, b=30 * BAR, **{**FCV, **over}))


def test_flow_control_valve_square_root_law_below_and_held_flow_above_the_setting():
    """Below dp_c - knee*dp_c/2 = 9.5 bar the whole drop is over the metering orifice; above 10.5 bar the
    compensator holds it at dp_c: q_set = Cd*A*sqrt(2*dp_c/rho) = 1.074 l/min... for any drop."""
    for dp in (1 * BAR, 5 * BAR, 9.4 * BAR):
        assert fcv(dp)["q_b"] == pytest.approx(sqrt_law(dp, 10e-6), rel=SQRT_REL)
    q_set = 0.7 * 10e-6 * math.sqrt(2 * 10 * BAR / RHO)
    for dp in (10.6 * BAR, 20 * BAR, 100 * BAR, 300 * BAR):
        assert fcv(dp)["q_b"] == pytest.approx(q_set, rel=SQRT_REL)
    # in the knee: dp_m = dp - (dp - dp_c + w/2)^2/(2w), w = 1 bar; at dp = dp_c that is dp_c - w/8
    assert fcv(10 * BAR)["q_b"] == pytest.approx(sqrt_law(10 * BAR - 1 * BAR / 8, 10e-6), rel=SQRT_REL)


def test_flow_control_valve_reverse_flow_is_not_compensated():
    for dp in (-5 * BAR, -50 * BAR):
        q = fcv(dp)
        assert q["q_b"] == pytest.approx(sqrt_law(dp, 10e-6), rel=SQRT_REL)
        assert q["q_a"] == -q["q_b"]


@settings(max_examples=200, deadline=None)
@given(levels=kpa(45000), knee=st.floats(0.0, 1.0))
def test_flow_control_valve_flow_never_falls_as_the_drop_rises(levels, knee):
    for lo, hi in ascending_pairs(p - 50 * BAR for p in levels):  # -50 ... 400 bar
        q_lo, q_hi = fcv(lo, knee=knee)["q_b"], fcv(hi, knee=knee)["q_b"]
        assert q_hi >= q_lo
        if hi < 10 * BAR * (1 - knee / 2):  # below the knee: strictly, the square-root law
            assert q_hi > q_lo
    assert fcv(0.0, knee=knee)["q_b"] == 0.0  # no flow without a drop, even with the widest knee


def test_flow_control_valve_is_c1_through_the_knee():
    h = 1.0
    for dp in (9.5 * BAR, 10 * BAR, 10.5 * BAR):
        left = (fcv(dp)["q_b"] - fcv(dp - h)["q_b"]) / h
        right = (fcv(dp + h)["q_b"] - fcv(dp)["q_b"]) / h
        assert right == pytest.approx(left, rel=1e-3, abs=1e-15)
    # and the slope does fall to zero across the knee (the compensator takes over)
    assert (fcv(10.5 * BAR + h)["q_b"] - fcv(10.5 * BAR)["q_b"]) == pytest.approx(0.0, abs=1e-18)


CBV = dict(p_set=200 * BAR, R_pilot=4.0, dp_open=40 * BAR, A_relief=20e-6, A_check=30e-6, p_check=0.5 * BAR,
           p_check_open=2 * BAR, A_leak=1e-9, dp_w=1 * BAR, Cd=0.7, dp_t=1e3, rho=RHO)


def cbv(V, C, pilot, **over):
    return named(CounterbalanceValve, CounterbalanceValve.derivatives(V=V, C=C, pilot=pilot, **{**CBV, **over}))


def relief_area(p_ctl):
    return 1e-9 + (20e-6 - 1e-9) * cubic_step(p_ctl, 200 * BAR, 40 * BAR)


ROUNDED_AT_ZERO = 4.0 * 1 * BAR / 8  # R_pilot*dp_w/8: the rounded max(p_pilot - p_V, 0) at p_pilot = p_V


@pytest.mark.parametrize("V, C, pilot, p_ctl", [
    (0.0, 150 * BAR, 0.0, 150 * BAR + ROUNDED_AT_ZERO),  # holding the load, pilot at the tank: leakage only
    (0.0, 220 * BAR, 0.0, 220 * BAR + ROUNDED_AT_ZERO),  # overload: the relief cracks without pilot
    (0.0, 100 * BAR, 30 * BAR, 220 * BAR),  # lowering: piloted open half way
    (0.0, 100 * BAR, 60 * BAR, 340 * BAR),  # piloted fully open
    (10 * BAR, 100 * BAR, 40 * BAR, 90 * BAR + 4 * 30 * BAR),  # both referenced to p_V
    (50 * BAR, 260 * BAR, 0.0, 210 * BAR),  # pilot below p_V: the pilot piston does not pull
])
def test_counterbalance_relief_against_the_square_root_law(V, C, pilot, p_ctl):
    d = cbv(V, C, pilot)
    q_r = sqrt_law(C - V, relief_area(p_ctl))
    assert d["q_V"] == pytest.approx(q_r, rel=SQRT_REL)  # check valve shut: only the relief passes
    assert d["q_C"] == -d["q_V"] and d["q_pilot"] == 0.0


def test_counterbalance_check_valve_lifts_the_load():
    V, C = 150 * BAR, 140 * BAR  # 10 bar across the check valve, far above its full-open 2 bar
    d = cbv(V, C, 0.0)
    assert d["q_C"] == pytest.approx(sqrt_law(10 * BAR, 30e-6) - sqrt_law(-10 * BAR, 1e-9), rel=SQRT_REL)
    # half open at the middle of 0.5 ... 2 bar
    d = cbv(101.25 * BAR, 100 * BAR, 0.0)
    assert d["q_C"] == pytest.approx(sqrt_law(1.25 * BAR, 15e-6) + sqrt_law(1.25 * BAR, 1e-9), rel=SQRT_REL)
    assert cbv(100.4 * BAR, 100 * BAR, 0.0, A_leak=0.0)["q_C"] == 0.0  # below the crack pressure: tight


def test_counterbalance_opening_pressure_with_pilot():
    """Cracks at p_C + R*p_pilot = p_set (V at the tank): the pilot lowers the load pressure it needs by R."""
    for pilot in (0.0, 10 * BAR, 25 * BAR):
        p_crack = 200 * BAR - 4.0 * pilot
        shut, cracked = cbv(0.0, p_crack - 1 * BAR, pilot), cbv(0.0, p_crack + 8 * BAR, pilot)  # 0.5 bar rounding
        assert shut["q_V"] == pytest.approx(sqrt_law(p_crack - 1 * BAR, 1e-9), rel=SQRT_REL)
        assert cracked["q_V"] > 100 * shut["q_V"]


@settings(max_examples=200, deadline=None)
@given(V=st.floats(0.0, 50 * BAR), C=st.floats(60 * BAR, 350 * BAR),
       pilots=kpa(10000))
def test_counterbalance_lowering_flow_never_falls_as_the_pilot_rises(V, C, pilots):
    for lo, hi in ascending_pairs(pilots):
        assert cbv(V, C, hi)["q_V"] >= cbv(V, C, lo)["q_V"]


@settings(max_examples=200, deadline=None)
@given(V=st.floats(0.0, 50 * BAR), pilot=st.floats(0.0, 100 * BAR),
       loads=kpa(29000))
def test_counterbalance_lowering_flow_rises_with_the_load_pressure(V, pilot, loads):
    for lo, hi in ascending_pairs(60 * BAR + p for p in loads):  # 60 ... 350 bar
        assert cbv(V, hi, pilot)["q_V"] > cbv(V, lo, pilot)["q_V"]


@settings(max_examples=200, deadline=None)
@given(V=st.floats(-1e6, 4e7), C=st.floats(-1e6, 4e7), pilot=st.floats(-1e6, 4e7))
def test_counterbalance_conserves_flow(V, C, pilot):
    d = cbv(V, C, pilot)
    assert d["q_pilot"] == 0.0
    assert abs(d["q_V"] + d["q_C"]) <= 1e-12 * (abs(d["q_V"]) + 1e-300)


def test_counterbalance_refuses_inconsistent_values():
    assert CounterbalanceValve.check_values(CBV) is None
    said = CounterbalanceValve.check_values({**CBV, "p_check_open": 0.5 * BAR})
    assert said == "p_check_open = 0.5 bar must be above p_check = 0.5 bar (the check valve opens over p_check ... p_check_open)"
    assert "must not exceed A_relief" in CounterbalanceValve.check_values({**CBV, "A_leak": 1e-4})


SHUTTLE = dict(A_max=10e-6, dp_w=1 * BAR, A_leak=1e-9, Cd=0.7, dp_t=1e3, rho=RHO)


def shuttle(a, b, out, **over):
    return named(ShuttleValve, ShuttleValve.derivatives(a=a, b=b, out=out, **{**SHUTTLE, **over}))


def test_shuttle_passes_the_higher_inlet():
    d = shuttle(150 * BAR, 100 * BAR, 80 * BAR)
    q_a, q_b = sqrt_law(70 * BAR, 10e-6), sqrt_law(20 * BAR, 1e-9)  # a open, b shut (leakage)
    assert d["q_a"] == pytest.approx(-q_a, rel=SQRT_REL) and d["q_b"] == pytest.approx(-q_b, rel=SQRT_REL)
    assert d["q_out"] == pytest.approx(q_a + q_b, rel=SQRT_REL)
    swapped = shuttle(100 * BAR, 150 * BAR, 80 * BAR)
    assert (swapped["q_a"], swapped["q_b"], swapped["q_out"]) == (d["q_b"], d["q_a"], d["q_out"])
    # equal inlets: the ball in the middle, each passage half open
    even = shuttle(100 * BAR, 100 * BAR, 90 * BAR)
    assert even["q_out"] == pytest.approx(2 * sqrt_law(10 * BAR, 5e-6 + 0.5e-9), rel=SQRT_REL)


def test_shuttle_refuses_a_leak_above_the_open_area():
    assert ShuttleValve.check_values(SHUTTLE) is None
    said = ShuttleValve.check_values({**SHUTTLE, "A_leak": 2e-5})
    assert said == "A_leak = 2e-05 m^2 must not exceed A_max = 1e-05 m^2 (the closed passage would pass more than the open one)"


def dead_ended_outlet(a, b, **over):
    return brentq(lambda p: shuttle(a, b, p, **over)["q_out"], min(a, b) - 1.0, max(a, b) + 1.0, xtol=1e-6, rtol=1e-15)


@pytest.mark.parametrize("dp_t", [1e3, 1e6])
def test_shuttle_dead_ended_outlet_reads_the_higher_pressure(dp_t):
    """Load-sense line (no flow at out): outside the band p_out is max(p_a, p_b) lowered by the leak x into the
    other inlet. With r = A_leak/A_max, delta = |p_a - p_b| and g(x) = x/(x^2 + dp_t^2)^(1/4) <= sqrt(x),
    A_max*g(x) = A_leak*g(delta + x) gives x <= 2^(1/4)*r*sqrt(dp_t*(delta + x)) if x <= dp_t (there
    g(x) >= x/(2 dp_t^2)^(1/4)), else x <= sqrt(2)*r^2*(delta + x). Inside the band p_out stays between
    the two and within 0.044*dp_w (the docstring's bound, linear law) of the higher."""
    r = 1e-9 / 10e-6
    for a, b in ((150 * BAR, 100 * BAR), (20 * BAR, 180 * BAR), (100 * BAR, 100.6 * BAR)):
        p = dead_ended_outlet(a, b, dp_t=dp_t)
        x, delta = max(a, b) - p, abs(a - b)
        assert 0.0 < x <= max(2 ** 0.25 * r * math.sqrt(dp_t * (delta + x)), math.sqrt(2) * r * r * (delta + x))
    for dp in np.linspace(-0.5 * BAR, 0.5 * BAR, 41):
        a, b = 100 * BAR + dp, 100 * BAR
        p = dead_ended_outlet(a, b, dp_t=dp_t)
        assert min(a, b) - 1e-3 <= p <= max(a, b) + 1e-3
        assert max(a, b) - p <= 0.044 * BAR


@settings(max_examples=200, deadline=None)
@given(a=st.floats(0.0, 4e7), b=st.floats(0.0, 4e7), outs=kpa(40000))
def test_shuttle_outlet_flow_falls_as_the_outlet_pressure_rises(a, b, outs):
    for lo, hi in ascending_pairs(outs):
        assert shuttle(a, b, hi)["q_out"] < shuttle(a, b, lo)["q_out"]


@settings(max_examples=200, deadline=None)
@given(a=st.floats(-1e6, 4e7), b=st.floats(-1e6, 4e7), out=st.floats(-1e6, 4e7))
def test_shuttle_conserves_flow(a, b, out):
    d = shuttle(a, b, out)
    assert abs(sum(d.values())) <= 1e-12 * (sum(abs(v) for v in d.values()) + 1e-300)


def test_shuttle_continuous_through_the_band():
    for dp in (-0.5 * BAR, 0.0, 0.5 * BAR):
        lo, hi = shuttle(100 * BAR + dp - 1e-3, 100 * BAR, 60 * BAR), shuttle(100 * BAR + dp + 1e-3, 100 * BAR, 60 * BAR)
        for key in lo:
            assert hi[key] == pytest.approx(lo[key], rel=1e-6)


# ---------------------------------------------------------------- numba: compiled == pure Python
NUMBA_CASES = {
    Orifice: dict(a=3e6, b=1e6, A=1e-5, Cd=0.7, dp_t=1e5, rho=RHO),
    PressureSource: dict(p=2e7),
    Tank: dict(p=0.0),
    FlowSource: dict(q=1e-4),
    FlowSourceSignal: dict(q=2e-4),
    Volume: dict(V=1e-5),
    VariableOrifice: dict(a=3e6, b=1e6, A=1e-5, Cd=0.7, dp_t=1e5, rho=RHO),
    LaminarOrifice: dict(a=3e6, b=1e6, G=1e-12),
    CheckValve: dict(a=1.5e5, b=0.0, **{k: v for k, v in CV.items()}),
    ReliefValve: dict(a=2.05e7, b=1e5, **RV),
    PressureSensor: dict(port=1e7),
    FlowSensor: dict(a=2e6, b=1e6, R=1e10),
    HydraulicMotor: dict(a=1e7, b=1e6, shaft=10.0, G_leak=1e-12, **MOTOR),
    Valve43: dict(P=PS, T=PT, A=PA, B=PB, x=0.3, **{**VALVE, "A_leak": 1e-9}),
    Cylinder: dict(A=1e7, B=2e6, rod=0.1, x=0.5002, **CYL),
    Pump: dict(s=1e5, p=1.5e7, shaft=150.0, G_leak=1e-12, **PUMP),
    VariablePump: dict(s=1e5, p=2.02e7, shaft=150.0, eps=0.7, G_leak=1e-12, **VPUMP),
    PressureReducingValve: dict(P=200 * BAR, A=53 * BAR, T=1 * BAR, **PRV),
    FlowControlValve: dict(a=40 * BAR, b=30.2 * BAR, **FCV),
    CounterbalanceValve: dict(V=5 * BAR, C=150 * BAR, pilot=25 * BAR, **CBV),
    ShuttleValve: dict(a=100.2 * BAR, b=100 * BAR, out=90 * BAR, **SHUTTLE),
}


@pytest.mark.parametrize("cls", list(NUMBA_CASES), ids=lambda c: c.type_name)
def test_numba_compiled_matches_python(cls):
    values = NUMBA_CASES[cls]
    for fn_name in ("outputs", "derivatives"):
        fn = getattr(cls, fn_name)
        if fn is None:
            continue
        args = [float(values[name]) for name in argument_names(fn)]
        expected = fn(*args)
        got = numba.njit(fn)(*args)
        assert len(got) == len(expected)
        for g, e in zip(got, expected):
            assert g == pytest.approx(e, rel=1e-12, abs=1e-300)
