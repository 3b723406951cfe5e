"""The generic mechanical blocks, each alone against its closed form (raw Python functions called by name),
plus one numba compilation of every equation function compared with the pure-Python call."""

from __future__ import annotations

import math

import numba
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from blocks.block import PortKind, argument_names
from blocks.library.mechanical.angle_sensor import AngleSensor
from blocks.library.mechanical.force_source import ForceSource
from blocks.library.mechanical.gear import Gear
from blocks.library.mechanical.induction_motor import InductionMotor
from blocks.library.mechanical.inertia import Inertia
from blocks.library.mechanical.mass import Mass
from blocks.library.mechanical.position_sensor import PositionSensor
from blocks.library.mechanical.rack_pinion import RackPinion
from blocks.library.mechanical.rot_damper import RotDamper
from blocks.library.mechanical.rot_friction import RotFriction
from blocks.library.mechanical.speed_sensor import SpeedSensor
from blocks.library.mechanical.speed_source import SpeedSource
from blocks.library.mechanical.torque_source import TorqueSource
from blocks.library.mechanical.trans_damper import TransDamper
from blocks.library.mechanical.trans_friction import TransFriction
from blocks.library.mechanical.velocity_sensor import VelocitySensor
from blocks.library.mechanical.velocity_source import VelocitySource
from blocks.registry import get


def named(cls, values) -> dict[str, float]:
    names = cls.derivative_names()
    assert len(values) == len(names), (cls.__name__, names, values)
    return dict(zip(names, values))


ALL = {
    "inertia": Inertia, "mass": Mass, "rot_damper": RotDamper, "trans_damper": TransDamper,
    "rot_friction": RotFriction, "trans_friction": TransFriction, "gear": Gear, "rack_pinion": RackPinion,
    "torque_source": TorqueSource, "force_source": ForceSource, "speed_source": SpeedSource,
    "velocity_source": VelocitySource, "speed_sensor": SpeedSensor, "velocity_sensor": VelocitySensor,
    "angle_sensor": AngleSensor, "position_sensor": PositionSensor, "induction_motor": InductionMotor,
}


@pytest.mark.parametrize("type_name", list(ALL))
def test_mechanical_block_registered(type_name):
    assert get(type_name) is ALL[type_name]
    assert ALL[type_name].summary()


# ---------------------------------------------------------------- storage
def test_inertia_and_mass_store_and_apply_nothing():
    assert named(Inertia, Inertia.derivatives(J=0.085)) == {"tau_port": 0.0, "J_port": 0.085}
    assert named(Mass, Mass.derivatives(m=7500.0, g_x=0.0)) == {"f_port": 0.0, "m_port": 7500.0}
    assert Inertia.port("port").kind is PortKind.ROTATIONAL and Inertia.port("port").stores
    assert Mass.port("port").kind is PortKind.TRANSLATIONAL and Mass.port("port").stores


def test_a_mass_applies_its_weight_along_the_motion():
    """f = m*g_x: a 2 t load lifted by a motion with v > 0 up (g_x = -9.81 m/s^2) pulls down with 19.62 kN;
    the default g_x = 0 is a horizontal motion."""
    assert named(Mass, Mass.derivatives(m=2000.0, g_x=-9.81)) == {"f_port": pytest.approx(-19620.0), "m_port": 2000.0}
    assert Mass.param("g_x").default == 0.0


# ---------------------------------------------------------------- friction
def test_viscous_dampers():
    assert named(RotDamper, RotDamper.derivatives(port=20.0, b=0.01)) == {"tau_port": pytest.approx(-0.2)}
    assert named(TransDamper, TransDamper.derivatives(port=-0.5, b=300.0)) == {"f_port": pytest.approx(150.0)}


FRICTION = [
    (RotFriction, dict(Tc=10.0, b=0.01, w_w=0.1)),
    (TransFriction, dict(Fc=500.0, b=200.0, v_w=1e-3)),
]


@pytest.mark.parametrize("cls, p", FRICTION, ids=["rot", "trans"])
def test_friction_closed_form(cls, p):
    coulomb, b, width = list(p.values())
    for v in (-3.0, -0.05, 0.0, 1e-4, 2.0):
        assert cls.derivatives(port=v, **p)[0] == pytest.approx(-(coulomb * math.tanh(v / width) + b * v), rel=1e-12)
    # far beyond the smoothing width: plain Coulomb + viscous
    v = 1e3 * width
    assert cls.derivatives(port=v, **p)[0] == pytest.approx(-(coulomb + b * v), rel=1e-9)
    assert cls.derivatives(port=-v, **p)[0] == pytest.approx(coulomb + b * v, rel=1e-9)


@pytest.mark.parametrize("cls, p", FRICTION, ids=["rot", "trans"])
@settings(max_examples=200, deadline=None)
@given(v=st.floats(-1e3, 1e3, allow_subnormal=False))
def test_friction_opposes_motion(cls, p, v):
    (f,) = cls.derivatives(port=v, **p)
    if v > 0:
        assert f < 0
    elif v < 0:
        assert f > 0
    else:
        assert f == 0.0
    assert cls.derivatives(port=-v, **p)[0] == -f  # odd


@pytest.mark.parametrize("cls, p", FRICTION, ids=["rot", "trans"])
def test_friction_continuous_through_zero(cls, p):
    coulomb, b, width = list(p.values())
    slope = -(coulomb / width + b)  # d(f)/dv at v = 0: finite, set by the declared width
    for eps in (1e-6 * width, 1e-9 * width):
        f_plus = cls.derivatives(port=eps, **p)[0]
        f_minus = cls.derivatives(port=-eps, **p)[0]
        assert abs(f_plus - f_minus) < 1e-5 * coulomb
        assert f_plus / eps == pytest.approx(slope, rel=1e-6)


# ---------------------------------------------------------------- rigid links
def test_gear_is_a_rigid_link():
    assert Gear.rigid_link == ("a", "b")
    assert Gear.ratio(n=39.0) == pytest.approx(1 / 39.0)
    assert Gear.through_ports() == [] and Gear.derivative_names() == [] and Gear.output_names() == []
    assert Gear.derivatives is None and Gear.outputs is None


def test_rack_pinion_is_a_rigid_link():
    r = 0.075
    assert RackPinion.rigid_link == ("a", "b")
    assert RackPinion.port("a").kind is PortKind.ROTATIONAL and RackPinion.port("b").kind is PortKind.TRANSLATIONAL
    assert RackPinion.ratio(r=r) == r
    assert RackPinion.through_ports() == [] and RackPinion.derivative_names() == []
    # reflected through the link: a rack force f gives the shaft torque r*f, a rack mass m the inertia r^2*m
    rr = RackPinion.ratio(r=r)
    assert rr * 1000.0 == pytest.approx(75.0) and rr**2 * 7500.0 == pytest.approx(42.1875)


# ---------------------------------------------------------------- sources and sensors
def test_effort_sources():
    assert named(TorqueSource, TorqueSource.derivatives(tau=12.5)) == {"tau_port": 12.5}
    assert named(ForceSource, ForceSource.derivatives(f=-3e3)) == {"f_port": -3e3}


def test_flow_variable_sources_prescribe():
    assert SpeedSource.prescribes == ("port",) and SpeedSource.output_names() == ["port"]
    assert SpeedSource.outputs(w=3.0) == (3.0,) and SpeedSource.through_ports() == []
    assert VelocitySource.prescribes == ("port",) and VelocitySource.outputs(v=-0.2) == (-0.2,)
    assert SpeedSource.feedthrough() == ["w"]


def test_speed_and_velocity_sensors():
    assert SpeedSensor.outputs(port=7.0) == (7.0,)
    assert named(SpeedSensor, SpeedSensor.derivatives()) == {"tau_port": 0.0}
    assert VelocitySensor.outputs(port=-0.3) == (-0.3,)
    assert named(VelocitySensor, VelocitySensor.derivatives()) == {"f_port": 0.0}


def test_angle_and_position_sensors_integrate():
    assert named(AngleSensor, AngleSensor.derivatives(port=5.0)) == {"tau_port": 0.0, "der_theta": 5.0}
    assert AngleSensor.outputs(theta=1.25) == (1.25,)
    assert [s.name for s in AngleSensor.states] == ["theta"] and AngleSensor.states[0].start == 0.0
    assert named(PositionSensor, PositionSensor.derivatives(port=-0.4)) == {"f_port": 0.0, "der_x": -0.4}
    assert PositionSensor.outputs(x=0.9) == (0.9,)
    # the output reads the state only: no direct feedthrough from the port
    assert AngleSensor.feedthrough() == [] and PositionSensor.feedthrough() == []
    # forward Euler of the state equation reproduces the integral of a constant speed
    theta, w, h = 0.3, 2.0, 1e-3
    for _ in range(1000):
        theta += h * named(AngleSensor, AngleSensor.derivatives(port=w))["der_theta"]
    assert theta == pytest.approx(0.3 + 2.0, rel=1e-12)


# ---------------------------------------------------------------- prime mover
KLOSS = dict(w_sync=2 * math.pi * 1500 / 60, T_b=300.0, s_b=0.12, J_r=0.08)  # a 4-pole 50 Hz motor


def kloss_torque(w, w_sync=KLOSS["w_sync"], T_b=KLOSS["T_b"], s_b=KLOSS["s_b"]):
    """Kloss's formula as the data books write it, tau = 2*T_b/(s/s_b + s_b/s) (s != 0)."""
    s = (w_sync - w) / w_sync
    return 2 * T_b / (s / s_b + s_b / s)


def motor_torque(w, **over):
    return named(InductionMotor, InductionMotor.derivatives(shaft=w, **{**KLOSS, **over}))["tau_shaft"]


def test_induction_motor_kloss_points():
    w_sync, T_b, s_b = KLOSS["w_sync"], KLOSS["T_b"], KLOSS["s_b"]
    assert w_sync == pytest.approx(157.08, abs=5e-3)
    assert motor_torque((1 - s_b) * w_sync) == pytest.approx(T_b, rel=1e-12)  # breakdown
    assert motor_torque(w_sync) == 0.0  # synchronous: no torque
    assert motor_torque(0.0) == pytest.approx(2 * T_b * s_b / (1 + s_b**2), rel=1e-12)  # starting torque
    assert named(InductionMotor, InductionMotor.derivatives(shaft=10.0, **KLOSS))["J_shaft"] == KLOSS["J_r"]
    for w in (-50.0, 0.0, 60.0, 130.0, 150.0, 156.0, 157.0, 158.0, 170.0, 400.0):
        assert motor_torque(w) == pytest.approx(kloss_torque(w), rel=1e-12)


def test_induction_motor_generates_above_synchronous_speed():
    """s < 0: negative torque, the mirror image of the motoring curve: -T_b at s = -s_b."""
    w_sync, s_b = KLOSS["w_sync"], KLOSS["s_b"]
    assert motor_torque((1 + s_b) * w_sync) == pytest.approx(-KLOSS["T_b"], rel=1e-12)
    for s in (1e-6, 0.01, 0.05, 0.12, 0.5, 1.0):
        above, below = motor_torque((1 + s) * w_sync), motor_torque((1 - s) * w_sync)
        assert above < 0.0 < below and above == pytest.approx(-below, rel=1e-12)


def test_induction_motor_breakdown_is_the_largest_torque_and_smooth_at_synchronous_speed():
    w_sync, T_b, s_b = KLOSS["w_sync"], KLOSS["T_b"], KLOSS["s_b"]
    slips = [k / 1000 for k in range(-1500, 1501)]
    torques = [motor_torque((1 - s) * w_sync) for s in slips]
    assert max(torques) == pytest.approx(T_b, rel=1e-12) and min(torques) == pytest.approx(-T_b, rel=1e-12)
    assert slips[torques.index(max(torques))] == pytest.approx(s_b)
    # through s = 0: the slope 2*T_b/s_b per unit slip, i.e. -2*T_b/(s_b*w_sync) per rad/s, no jump
    h = 1e-6
    slope = (motor_torque(w_sync + h) - motor_torque(w_sync - h)) / (2 * h)
    assert slope == pytest.approx(-2 * T_b / (s_b * w_sync), rel=1e-6)


# ---------------------------------------------------------------- numba: compiled == pure Python
NUMBA_CASES = {
    Inertia: dict(J=0.1), Mass: dict(m=100.0, g_x=-9.81),
    RotDamper: dict(port=3.0, b=0.01), TransDamper: dict(port=-0.2, b=50.0),
    RotFriction: dict(port=0.03, Tc=10.0, b=0.01, w_w=0.1), TransFriction: dict(port=-1e-4, Fc=50.0, b=5.0, v_w=1e-3),
    Gear: dict(n=39.0), RackPinion: dict(r=0.075),
    TorqueSource: dict(tau=4.0), ForceSource: dict(f=-10.0),
    SpeedSource: dict(w=2.0), VelocitySource: dict(v=0.1),
    SpeedSensor: dict(port=8.0), VelocitySensor: dict(port=-0.5),
    AngleSensor: dict(port=4.0, theta=0.5), PositionSensor: dict(port=0.2, x=1.5),
    InductionMotor: dict(shaft=150.0, **KLOSS),
}


@pytest.mark.parametrize("cls", list(NUMBA_CASES), ids=lambda c: c.type_name)
def test_numba_compiled_matches_python(cls):
    values = NUMBA_CASES[cls]
    for fn_name in ("outputs", "derivatives", "ratio"):
        fn = getattr(cls, fn_name)
        if fn is None:
            continue
        args = [float(values[name]) for name in argument_names(fn)]
        expected = fn(*args)
        got = numba.njit(fn)(*args)
        if fn_name == "ratio":
            got, expected = (got,), (expected,)
        assert len(got) == len(expected)
        for g, e in zip(got, expected):
            assert g == pytest.approx(e, rel=1e-12, abs=1e-300)
