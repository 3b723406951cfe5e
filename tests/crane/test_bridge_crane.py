"""The bridge crane (issue 3, part F): netlists/bridge_crane/ (thesis section 2.10.1).

Three drive lines (drive_line.yaml: 4WRLE 16 servo valve, VAA VF250 motion-control valve, Parker motors,
axis inertia, feed-forward + PI position controller) on one 207 bar supply, and the tool point.

What is checked, and where each bound comes from:
- the netlist's numbers are the thesis's tables (compared with the blocks' own presets, so the values
  written into the YAML cannot drift from them);
- the default motion runs to its end with no cavitation warning;
- every pressure stays between tank (0 bar) and supply (207 bar), except the motor-side lines, which the
  MCV may hold above supply while it brakes a load: those stay below the axis's crack setting (table 2.4:
  230 / 260 / 270 bar), the pressure at which the unpiloted relief opens. 0.01 bar below tank is allowed
  for the solver (rtol 1e-6 of ~200 bar is 2e-4 bar);
- Newton's law on each motor shaft, with the inertia and displacement computed here from the thesis's
  numbers (table 2.14, appendix I): J*dw/dt = D*dp - (1 - eta_hm)*|D*dp|*tanh(w/w_w);
- each axis follows its reference: max error over the run no worse than the thesis's own regular
  controller (table 4.2, 50 % load: 10.1 mm) on the travel axes; slewing (no thesis figure) 0.5 deg
  (18 mm at the tool-point radius): an acceptance bound chosen here; in cruise 5 mm / 0.2 deg; the final
  error within the band x_db/Kp in which a P controller leaves the servo valve in its 2 % dead band;
- the run starts quietly (nothing moves before the first reference starts);
- the tool point is eqs. 2.66-2.67 of the axis positions, and the axis positions are theta*r_p/n_g and
  theta/n_G of the motor angles;
- the feed-forward gains Kv are what the netlist says they are: alone (Kp = Ki = 0) they drive each axis
  at its reference cruise speed;
- the axes are independent on the ideal supply (section 2.1's assumption): the bridge axis of the crane
  runs exactly as the bridge-travel drive line alone (bridge_travel.yaml).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit
from blocks.registry import get
from blocks.expressions import parse_expression
from blocks.units import UnitError, quantity

ROOT = Path(__file__).resolve().parents[2]
CRANE = ROOT / "netlists" / "bridge_crane" / "bridge_crane.yaml"
TRAVEL = ROOT / "netlists" / "bridge_crane" / "bridge_travel.yaml"

BAR = 1e5
AXES = ("bridge", "trolley", "slew")
P_SUPPLY = 207 * BAR                                               # section 2.1
P_CRACK = {"bridge": 230 * BAR, "trolley": 260 * BAR, "slew": 270 * BAR}   # table 2.4
N_G_SLEW = 44.6 * 1200 / 132                                       # table 2.14
# axis position per motor radian: travel r_p/n_g [m/rad], slewing 1/n_G [rad/rad] (table 2.14)
K_POS = {"bridge": 0.075 / 39.0, "trolley": 0.055 / 38.4, "slew": 1.0 / N_G_SLEW}
X_DB = 0.02            # the 4WRLE's dead band (section 2.2)
SOLVER_SLACK = 0.01 * BAR


@pytest.fixture(scope="module")
def crane() -> Circuit:
    return Circuit.from_file(CRANE)


@pytest.fixture(scope="module")
def values(crane) -> dict:
    return crane.vectors().values


@pytest.fixture(scope="module")
def result(crane):
    return crane.simulate()


def preset(type_name: str, name: str) -> dict[str, float]:
    """A block's preset in SI; plain expressions (the slewing n_G "44.6*1200/132") evaluated."""
    cls = get(type_name)
    out = {}
    for key, raw in cls.presets[name].items():
        try:
            out[key] = quantity(raw, cls.param(key).unit)
        except UnitError:
            out[key] = parse_expression(raw).evaluate({})
    return out


def error(result, axis: str) -> np.ndarray:
    """Reference minus position, SI (m or rad)."""
    return result[f"{axis}_ref"] - result[axis]


def phases(values, axis: str) -> dict[str, tuple[float, float]]:
    t0, ta = values[f"{axis}.t_start"], values[f"{axis}.t_acc"]
    t_dec = t0 + values[f"{axis}.stroke"] / values[f"{axis}.v_max"]
    return {"before": (-1.0, t0), "cruise": (t0 + ta + 0.3, t_dec), "after": (t_dec + ta, math.inf)}


def window(t, span):
    return (t >= span[0]) & (t < span[1])


# ---- the netlist's numbers are the thesis's tables -------------------------------------------------------
def test_motors_inertias_and_valves_are_the_thesis_tables(values):
    f12_030, f12_060 = preset("parker_motor", "F12-030"), preset("parker_motor", "F12-060")
    motors = {"bridge": (2, f12_030), "trolley": (1, f12_030), "slew": (1, f12_060)}
    for axis, (n, motor) in motors.items():
        for key in ("D", "A_lm", "A_ld", "J_m"):   # n identical motors on one shaft = n times one motor
            assert values[f"{axis}.motor.{key}"] == pytest.approx(n * motor[key], rel=1e-12), (axis, key)
        assert values[f"{axis}.motor.eta_hm"] == 0.9
    inertias = {"bridge": "bridge_travel", "trolley": "trolley_travel", "slew": "slewing"}
    for axis, name in inertias.items():
        table = preset("bc_axis_inertia", name)
        for key in ("J0", "r", "n_g"):
            assert values[f"{axis}.inertia.{key}"] == pytest.approx(table[key], rel=1e-12), (axis, key)
        assert values[f"{axis}.inertia.m_L"] == 7500.0
        assert values[f"{axis}.mcv.p_crack"] == P_CRACK[axis]
        assert values[f"{axis}.mcv.alpha"] == 2.8
        assert values[f"{axis}.mcv.A_prv"] == pytest.approx(72.1e-6)          # VF250, table 2.8
        assert values[f"{axis}.valve.A_max"] == pytest.approx(124.9e-6)       # 4WRLE 16, section 2.2
        assert values[f"{axis}.position.k"] == pytest.approx(K_POS[axis], rel=1e-12)
    assert values["supply.p"] == P_SUPPLY
    assert (values["fluid.rho"], values["fluid.nu"], values["fluid.beta"]) == pytest.approx((850.0, 1.8e-5, 8e8))  # table 2.1


# ---- the default run -----------------------------------------------------------------------------------
def test_default_motion_runs_to_the_end_without_cavitation(result, values):
    assert result.t[-1] == pytest.approx(4.0)
    assert result.warnings == []
    for axis in AXES:   # every reference has finished before the end
        assert values[f"{axis}.t_start"] + values[f"{axis}.stroke"] / values[f"{axis}.v_max"] \
            + values[f"{axis}.t_acc"] < result.t[-1]


def test_pressures_stay_between_tank_and_supply_or_the_mcv_setting(result):
    for axis in AXES:
        for name in ("VA.p", "VB.p", "mcv.pt"):   # valve side and the MCV's internal node
            p = result.state(f"{axis}.{name}")
            assert p.min() >= -SOLVER_SLACK, (axis, name, p.min() / BAR)
            assert p.max() <= P_SUPPLY, (axis, name, p.max() / BAR)
        for name in ("CA.p", "CB.p"):              # motor side: held by the MCV up to its crack setting
            p = result.state(f"{axis}.{name}")
            assert p.min() >= -SOLVER_SLACK, (axis, name, p.min() / BAR)
            assert p.max() <= P_CRACK[axis], (axis, name, p.max() / BAR)


def test_newton_on_each_motor_shaft_with_the_thesis_inertia(result):
    """J*dw/dt = tau(dp, w) with J and D computed here from table 2.14 and appendix I (not from the netlist):
    catches a wrong motor count, inertia or gear ratio. dw/dt by central differences of the 2 ms samples."""
    rev = 2 * math.pi
    shafts = {
        "bridge": (2 * 30e-6 / rev, 0.085 + 7500 * 0.075**2 / 39.0**2 + 2 * 1.7e-3),
        "trolley": (30e-6 / rev, 0.027 + 7500 * 0.055**2 / 38.4**2 + 1.7e-3),
        "slew": (59.8e-6 / rev, 0.011 + 7500 * 2.1**2 / N_G_SLEW**2 + 5.0e-3),
    }
    for axis, (D, J) in shafts.items():
        w = result.state(f"{axis}.shaft.w")
        tau_h = D * (result.state(f"{axis}.CA.p") - result.state(f"{axis}.CB.p"))
        tau = tau_h - 0.1 * np.abs(tau_h) * np.tanh(w / 0.1)
        residual = J * np.gradient(w, result.t) - tau
        assert np.sqrt(np.mean(residual**2)) < 0.01 * np.sqrt(np.mean(tau**2)), axis


def test_mcv_brakes_the_bridge(result, values):
    """While the bridge decelerates, the MCV holds the outlet line above the inlet: the braking torque comes
    from the return side, and the inlet side, refilled through the cross-line relief, does not cavitate."""
    t_dec = values["bridge.t_start"] + values["bridge.stroke"] / values["bridge.v_max"]
    span = window(result.t, (t_dec + 0.1, t_dec + values["bridge.t_acc"] - 0.1))
    w = result.state("bridge.shaft.w")[span]
    assert np.all(w > 0) and np.all(np.diff(w) < 0)     # still moving forward, slowing down
    dp = result.state("bridge.CB.p")[span] - result.state("bridge.CA.p")[span]
    assert dp.mean() > 0


def test_axes_follow_their_references(result, values):
    limits = {  # (max over the run, in cruise) in m or rad
        "bridge": (10.1e-3, 5e-3), "trolley": (10.1e-3, 5e-3), "slew": (math.radians(0.5), math.radians(0.2))}
    for axis in AXES:
        e = error(result, axis)
        span = phases(values, axis)
        assert np.abs(e).max() < limits[axis][0], (axis, np.abs(e).max())
        assert np.abs(e[window(result.t, span["cruise"])]).max() < limits[axis][1], axis
        final_band = X_DB / values[f"{axis}.Kp"]
        assert abs(e[-1]) < final_band, (axis, e[-1], final_band)
        assert abs(result[f"{axis}_ref"][-1] - values[f"{axis}.stroke"]) < 1e-6 * abs(values[f"{axis}.stroke"])


def test_the_run_starts_quietly(result, values):
    """Before the first reference starts nothing moves, no valve opens, and the locked lines keep their
    pressure (they lose only the MCV check valves' and the motor drains' leakage: < 1 bar in 0.2 s)."""
    first = min(values[f"{axis}.t_start"] for axis in AXES)
    quiet = result.t < first - 0.01   # the solver's dense output may straddle the reference's first corner
    assert quiet.sum() > 50
    for axis in AXES:
        assert np.abs(result[axis][quiet]).max() < 1e-9
        assert np.abs(result.state(f"{axis}.valve.x")[quiet]).max() < 1e-9
        for u in ("u1", "u2"):
            assert np.abs(result.state(f"{axis}.mcv.{u}")[quiet]).max() < 1e-9
        for net, start in (("VA", 0.0), ("VB", 0.0), ("CA", 20 * BAR), ("CB", 20 * BAR)):
            p = result.state(f"{axis}.{net}.p")[quiet]
            assert np.abs(p - start).max() < 1 * BAR, (axis, net)


def test_tool_point_and_axis_positions(result):
    b, t, alpha = result["bridge"], result["trolley"], result["slew"]
    assert np.allclose(result["tool_x"], 2.1 * np.sin(alpha) + b, rtol=0, atol=1e-12)          # eq. 2.66
    assert np.allclose(result["tool_y"], 2.1 - 2.1 * np.cos(alpha) + t, rtol=0, atol=1e-12)    # eq. 2.67
    for axis in AXES:
        theta = result.state(f"{axis}.angle.theta")
        assert np.allclose(result[axis], K_POS[axis] * theta, rtol=1e-12, atol=1e-15), axis
    assert result["tool_x"][-1] == pytest.approx(1.0 + 2.1 * math.sin(math.radians(20)), abs=5e-3)
    assert result["tool_y"][-1] == pytest.approx(0.3 + 2.1 * (1 - math.cos(math.radians(20))), abs=5e-3)


def test_feed_forward_alone_gives_the_cruise_speed(crane, values):
    """Kv is the feed-forward that drives each axis at its reference speed: with Kp = Ki = 0 the cruise
    speed (slope of the position over the second half of the cruise) is within 3 % of v_max."""
    off = {f"{axis}.{k}": 0.0 for axis in AXES for k in ("Kp", "Ki")}
    r = crane.simulate(off)
    for axis in AXES:
        a, b = phases(values, axis)["cruise"]
        span = window(r.t, (0.5 * (a + b), b))
        speed = np.polyfit(r.t[span], r[axis][span], 1)[0]
        assert speed == pytest.approx(values[f"{axis}.v_max"], rel=0.03), axis


def test_axes_are_independent_on_the_ideal_supply(result, values):
    """The crane's bridge axis runs as the bridge-travel drive line alone: the supply is an ideal 207 bar
    source (section 2.1), so the other two axes do not disturb it."""
    same = {f"bridge.{k}": values[f"bridge.{k}"] for k in ("t_start", "t_acc", "stroke", "v_max", "Kv", "Kp", "Ki")}
    alone = Circuit.from_file(TRAVEL).simulate(same)
    t = result.t[result.t <= alone.t[-1]]
    assert np.allclose(np.interp(t, alone.t, alone["x"]), result["bridge"][: t.size], rtol=0, atol=2e-5)
    assert np.allclose(np.interp(t, alone.t, alone["pCB"]), result.state("bridge.CB.p")[: t.size],
                       rtol=0, atol=0.2 * BAR)
