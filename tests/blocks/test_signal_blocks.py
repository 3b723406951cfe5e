"""The generic signal blocks, each alone against its closed form (or scipy.signal), and compiled by numba.

The equation functions are called as the compiler calls them: by argument name, with float scalars, float64
arrays for array parameters and states, and a ``der_x`` view filled in place. Dynamic blocks are integrated
here with scipy's solve_ivp on their own ``derivatives``.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy import signal
from scipy.integrate import solve_ivp
from scipy.interpolate import RegularGridInterpolator

from blocks.block import argument_names
from blocks.library.signal.clock import Clock
from blocks.library.signal.constant import Constant
from blocks.library.signal.dead_band import DeadBand
from blocks.library.signal.gain import Gain
from blocks.library.signal.highpass2 import Highpass2
from blocks.library.signal.integrator import Integrator
from blocks.library.signal.lookup_1d import Lookup1D
from blocks.library.signal.lookup_2d import Lookup2D
from blocks.library.signal.lowpass2 import Lowpass2
from blocks.library.signal.pid import PID
from blocks.library.signal.product import Product
from blocks.library.signal.profile import Profile
from blocks.library.signal.ramp import Ramp
from blocks.library.signal.saturation import Saturation
from blocks.library.signal.second_order import SecondOrder
from blocks.library.signal.step import Step
from blocks.library.signal.sum import Sum
from blocks.library.signal.switch import Switch
from blocks.library.signal.transfer_function import TransferFunction
from blocks.library.signal.transfer_function_strict import TransferFunctionStrict
from blocks.registry import all_types

A = np.asarray
finite = st.floats(-1e6, 1e6, allow_nan=False)


# ---------------------------------------------------------------- helpers
def call(fn, values: dict):
    """Call an equation function as the compiler does: by argument name."""
    return fn(**{name: values[name] for name in argument_names(fn)})


def params_of(cls, **given) -> dict:
    """Defaults of ``cls`` overridden by ``given``; arrays as float64 arrays."""
    values = {p.name: p.default for p in cls.params if p.default is not None}
    values.update(given)
    return {k: (A(v, dtype=float) if cls.param(k).array else float(v)) for k, v in values.items()}


def simulate(cls, params: dict, inputs, t_eval, method="DOP853", rtol=1e-10, atol=1e-12, start=None, **kw):
    """Integrate the block's own ``derivatives`` with solve_ivp; return (states at t_eval, outputs at t_eval).

    ``inputs(t)`` gives the dict of signal-input values. States are laid out in declaration order, array
    states as slices; ``start`` overrides the initial state vector.
    """
    lengths = {p.name: len(params[p.name]) for p in cls.params if p.array}
    layout, n = [], 0
    for s in cls.states:
        size = 1 if s.size is None else s.size(lengths)
        layout.append((s, slice(n, n + size)))
        n += size
    z0 = np.zeros(n) if start is None else A(start, dtype=float)
    for s, sl in layout:
        if start is None:
            z0[sl] = s.start

    def values_at(t, z, der=None):
        v = dict(params, t=t, **inputs(t))
        for s, sl in layout:
            v[s.name] = z[sl] if s.size is not None else z[sl.start]
            if s.size is not None and der is not None:
                v["der_" + s.name] = der[sl]
        return v

    def rhs(t, z):
        der = np.zeros(n)
        result = call(cls.derivatives, values_at(t, z, der))
        scalar = [sl for s, sl in layout if s.size is None]
        assert len(result) == len(scalar) == len(cls.derivative_names())
        for sl, d in zip(scalar, result):
            der[sl.start] = d
        return der

    sol = solve_ivp(rhs, (t_eval[0], t_eval[-1]), z0, t_eval=t_eval, method=method, rtol=rtol, atol=atol, **kw)
    assert sol.success, sol.message
    y = np.array([call(cls.outputs, values_at(t, sol.y[:, i]))[0] for i, t in enumerate(sol.t)])
    return sol.y, y


def step_input(t):
    return {"u": 1.0}


# ---------------------------------------------------------------- registry and declarations
SIGNAL_TYPES = {
    "clock": Clock, "constant": Constant, "step": Step, "ramp": Ramp, "profile": Profile, "gain": Gain,
    "sum": Sum, "product": Product, "saturation": Saturation, "dead_band": DeadBand, "lookup_1d": Lookup1D,
    "lookup_2d": Lookup2D, "transfer_function": TransferFunction,
    "transfer_function_strict": TransferFunctionStrict, "second_order": SecondOrder, "integrator": Integrator,
    "pid": PID, "lowpass2": Lowpass2, "highpass2": Highpass2, "switch": Switch,
}


def test_every_signal_block_is_registered_under_its_type_name():
    registry = all_types()
    for name, cls in SIGNAL_TYPES.items():
        assert registry[name] is cls and cls.type_name == name


@pytest.mark.parametrize("cls", SIGNAL_TYPES.values(), ids=SIGNAL_TYPES.keys())
def test_declarations_are_documented(cls):
    assert cls.summary() and "\n" not in cls.summary()
    for p in cls.params:
        assert p.unit and p.description and "\n" not in p.description


def test_feedthrough_is_what_the_outputs_read():
    strictly_proper = [Integrator, SecondOrder, Lowpass2, TransferFunctionStrict]
    for cls in strictly_proper:
        assert cls.feedthrough() == [], cls
    assert TransferFunction.feedthrough() == ["u"]
    assert Highpass2.feedthrough() == ["u"]
    assert PID.feedthrough() == ["e"]
    assert Sum.feedthrough() == ["u1", "u2", "u3"]
    assert [p.name for p in Sum.ports if p.optional] == ["u2", "u3"]


# ---------------------------------------------------------------- sources
def test_clock_and_constant():
    assert Clock.outputs(t=2.5) == (2.5,)
    assert Constant.outputs(value=-3.0) == (-3.0,)


def test_step():
    p = dict(t_step=1.0, y0=2.0, y1=-5.0)
    assert Step.outputs(t=0.999, **p) == (2.0,)
    assert Step.outputs(t=1.0, **p) == (-5.0,)
    assert Step.outputs(t=7.0, **p) == (-5.0,)


def test_ramp_with_slope_is_unbounded():
    p = dict(t_start=1.0, y0=2.0, slope=3.0, duration=0.0, y1=99.0)
    assert Ramp.outputs(t=0.0, **p) == (2.0,)
    assert Ramp.outputs(t=1.0, **p) == (2.0,)
    assert Ramp.outputs(t=11.0, **p)[0] == pytest.approx(32.0)


def test_ramp_with_duration_holds_the_final_value():
    p = dict(t_start=1.0, y0=2.0, slope=123.0, duration=4.0, y1=10.0)
    assert Ramp.outputs(t=0.5, **p) == (2.0,)
    assert Ramp.outputs(t=2.0, **p)[0] == pytest.approx(4.0)
    assert Ramp.outputs(t=5.0, **p) == (10.0,)
    assert Ramp.outputs(t=50.0, **p) == (10.0,)


def test_profile_interpolates_and_holds_outside():
    times, values = A([0.0, 1.0, 3.0, 3.5]), A([1.0, 3.0, -1.0, 0.0])
    ts = np.linspace(-1.0, 5.0, 301)
    got = [Profile.outputs(t=t, times=times, values=values)[0] for t in ts]
    assert_allclose(got, np.interp(ts, times, values), rtol=0, atol=1e-14)
    assert Profile.outputs(t=0.3, times=A([2.0]), values=A([7.0])) == (7.0,)


def test_profile_check_values():
    assert Profile.check_values({"times": [0, 1, 2], "values": [0, 1, 0]}) is None
    assert "strictly increasing" in Profile.check_values({"times": [0, 1, 1], "values": [0, 1, 0]})
    assert "entries" in Profile.check_values({"times": [0, 1, 2], "values": [0, 1]})


def test_breakpoints_are_where_the_time_signals_jump_or_kink():
    assert Step.breakpoints({"t_step": 1.5, "y0": 0.0, "y1": 1.0}) == (1.5,)
    assert Ramp.breakpoints({"t_start": 1.0, "y0": 0.0, "slope": 2.0, "duration": 4.0, "y1": 3.0}) == (1.0, 5.0)
    assert Ramp.breakpoints({"t_start": 1.0, "y0": 0.0, "slope": 2.0, "duration": 0.0, "y1": 3.0}) == (1.0,)
    # a profile: where its slope changes, held constant outside; a point in a straight run is none
    assert Profile.breakpoints({"times": A([0.0, 1.0, 2.0]), "values": A([0.0, 1.0, 2.0])}) == (0.0, 2.0)
    assert Profile.breakpoints({"times": A([0, 1, 2, 3, 4.0]), "values": A([5, 5, 6, 6, 6.0])}) == (1.0, 2.0)
    assert Profile.breakpoints({"times": A([0.0, 1.0]), "values": A([3.0, 3.0])}) == ()


# ---------------------------------------------------------------- static maps
@given(finite, finite)
def test_gain(u, k):
    assert Gain.outputs(u=u, k=k) == (k * u,)


def test_sum_signs_and_optional_inputs():
    assert Sum.outputs(u1=5.0, u2=3.0, u3=0.0, k1=1.0, k2=-1.0, k3=1.0) == (2.0,)
    assert Sum.outputs(u1=1.0, u2=2.0, u3=4.0, k1=2.0, k2=0.5, k3=-0.25) == (2.0,)


@given(finite, finite)
def test_product(u1, u2):
    assert Product.outputs(u1=u1, u2=u2) == (u1 * u2,)


@settings(deadline=None)  # the first example may compile the numba kernel
@given(finite, finite, finite)
def test_saturation(u, a, b):
    lower, upper = min(a, b), max(a, b)
    (y,) = Saturation.outputs(u=u, lower=lower, upper=upper)
    assert y == float(np.clip(u, lower, upper))


def test_dead_band():
    p = dict(lower=-1.0, upper=2.0)
    assert DeadBand.outputs(u=0.5, **p) == (0.0,)
    assert DeadBand.outputs(u=2.0, **p) == (0.0,)
    assert DeadBand.outputs(u=-1.0, **p) == (0.0,)
    assert DeadBand.outputs(u=5.0, **p) == (3.0,)
    assert DeadBand.outputs(u=-4.0, **p) == (-3.0,)
    assert "above" in DeadBand.check_values({"lower": 1.0, "upper": 0.0})
    assert Saturation.check_values({"lower": -1.0, "upper": 1.0}) is None


def test_switch():
    assert Switch.outputs(u1=1.0, control=0.5, u2=2.0, threshold=0.5) == (1.0,)
    assert Switch.outputs(u1=1.0, control=0.49, u2=2.0, threshold=0.5) == (2.0,)


X_TAB = A([-1.0, 0.0, 0.5, 2.0, 4.0])
Y_TAB = A([3.0, 1.0, 1.5, -2.0, 0.0])


@settings(deadline=None)  # the first example may compile the numba kernel
@given(st.floats(-10.0, 10.0))
def test_lookup_1d_clamped_is_numpy_interp(u):
    (y,) = Lookup1D.outputs(u=u, x_table=X_TAB, y_table=Y_TAB, extrapolate=0.0)
    assert y == pytest.approx(float(np.interp(u, X_TAB, Y_TAB)), abs=1e-12)


def test_lookup_1d_linear_extrapolation():
    p = dict(x_table=X_TAB, y_table=Y_TAB, extrapolate=1.0)
    assert Lookup1D.outputs(u=-3.0, **p)[0] == pytest.approx(3.0 + (-2.0) * (-2.0))  # slope -2 left
    assert Lookup1D.outputs(u=6.0, **p)[0] == pytest.approx(0.0 + 1.0 * 2.0)  # slope +1 right
    assert Lookup1D.outputs(u=1.0, **p)[0] == pytest.approx(float(np.interp(1.0, X_TAB, Y_TAB)))
    assert Lookup1D.check_values({"x_table": [0.0, 1.0], "y_table": [0.0, 1.0], "extrapolate": 0.0}) is None
    assert "strictly increasing" in Lookup1D.check_values({"x_table": [1.0, 0.0], "y_table": [0.0, 1.0]})


def test_lookup_2d_is_bilinear_and_clamped():
    xs, ys = A([0.0, 1.0, 3.0]), A([-2.0, 0.0, 1.0, 4.0])
    z = np.sin(xs[:, None]) + xs[:, None] * ys[None, :] ** 2  # (nx, ny)
    ref = RegularGridInterpolator((xs, ys), z, method="linear")
    rng = np.random.default_rng(1)
    for u1, u2 in rng.uniform([-1.0, -3.0], [4.0, 5.0], size=(200, 2)):
        (y,) = Lookup2D.outputs(u1=u1, u2=u2, x_table=xs, y_table=ys, z_table=z.ravel())
        expected = ref([[np.clip(u1, xs[0], xs[-1]), np.clip(u2, ys[0], ys[-1])]])[0]
        assert y == pytest.approx(expected, abs=1e-12)
    # at the grid points it returns the table exactly (row-major layout)
    assert Lookup2D.outputs(u1=1.0, u2=1.0, x_table=xs, y_table=ys, z_table=z.ravel())[0] == z[1, 2]
    assert Lookup2D.check_values({"x_table": xs, "y_table": ys, "z_table": z.ravel()}) is None
    assert "3 x 4" in Lookup2D.check_values({"x_table": xs, "y_table": ys, "z_table": z.ravel()[:-1]})


# ---------------------------------------------------------------- transfer functions
def test_transfer_function_realisation_is_tf2ss():
    """derivatives and outputs are exactly A x + B u and C x + D u of scipy.signal.tf2ss."""
    rng = np.random.default_rng(0)
    for num, den in [([1.0, 2.0, 3.0, 4.0], [2.0, 3.0, 4.0, 5.0]), ([0.5, 3.0], [4.0, 1.0, 2.0, 3.0, 1.0])]:
        a, b, c, d = signal.tf2ss(num, den)
        num, den = A(num), A(den)
        for _ in range(5):
            x, u = rng.normal(size=len(den) - 1), rng.normal()
            der_x = np.zeros_like(x)
            assert TransferFunction.derivatives(u=u, x=x, den=den, der_x=der_x) == ()
            assert_allclose(der_x, a @ x + b[:, 0] * u, rtol=1e-13, atol=1e-13)
            (y,) = TransferFunction.outputs(u=u, x=x, num=num, den=den)
            assert y == pytest.approx((c @ x + d[:, 0] * u)[0], abs=1e-13)
            if len(num) < len(den):
                (ys,) = TransferFunctionStrict.outputs(x=x, num=num, den=den)
                assert ys == pytest.approx(y, abs=1e-13)


@pytest.mark.parametrize("cls", [TransferFunction, TransferFunctionStrict])
def test_first_order_lag_step(cls):
    t = np.linspace(0.0, 6.0, 61)
    params = params_of(cls, num=[1.0], den=[1.0, 1.0])
    _, y = simulate(cls, params, step_input, t)
    assert_allclose(y, 1.0 - np.exp(-t), atol=1e-8)


@pytest.mark.parametrize(
    "cls, num, den",
    [
        (TransferFunctionStrict, [1.0, 0.5, 3.0], [1.0, 2.0, 3.0, 1.0]),
        (TransferFunction, [1.0, 2.0, 3.0, 4.0], [2.0, 3.0, 4.0, 5.0]),  # biproper, den[0] != 1
    ],
)
def test_third_order_vs_scipy_lsim(cls, num, den):
    t = np.linspace(0.0, 15.0, 3001)

    def u_of(t):
        return 1.0 + np.sin(2.0 * t) + 0.3 * np.cos(0.7 * t)

    params = params_of(cls, num=num, den=den)
    _, y = simulate(cls, params, lambda t: {"u": u_of(t)}, t)
    _, y_ref, _ = signal.lsim((num, den), u_of(t), t)
    assert_allclose(y, y_ref, atol=2e-5)
    # and the step response against scipy.signal.step
    _, y = simulate(cls, params, step_input, t)
    _, y_ref = signal.step((num, den), T=t)
    assert_allclose(y[1:], y_ref[1:], atol=1e-6)


def test_transfer_function_check_values():
    assert TransferFunction.check_values({"num": [1.0, 2.0], "den": [1.0, 3.0]}) is None
    assert TransferFunction.check_values({"num": [1.0], "den": [1.0, 3.0]}) is None
    assert "improper" in TransferFunction.check_values({"num": [1.0, 0.0, 0.0], "den": [1.0, 3.0]})
    assert "den[0]" in TransferFunction.check_values({"num": [1.0], "den": [0.0, 3.0]})
    assert "strictly" in TransferFunctionStrict.check_values({"num": [1.0, 2.0], "den": [1.0, 3.0]})
    assert TransferFunctionStrict.check_values({"num": [0.0, 2.0], "den": [1.0, 3.0]}) is None


# ---------------------------------------------------------------- second-order blocks
def second_order_step(t, wn, zeta):
    """Unit step response of wn^2/(s^2 + 2 zeta wn s + wn^2), closed form."""
    if zeta < 1.0:
        wd = wn * math.sqrt(1.0 - zeta**2)
        return 1.0 - np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta / math.sqrt(1.0 - zeta**2) * np.sin(wd * t))
    if zeta == 1.0:
        return 1.0 - np.exp(-wn * t) * (1.0 + wn * t)
    r = math.sqrt(zeta**2 - 1.0)
    s1, s2 = -wn * (zeta - r), -wn * (zeta + r)
    return 1.0 + (s2 * np.exp(s1 * t) - s1 * np.exp(s2 * t)) / (s1 - s2)


def second_order_impulse(t, wn, zeta):
    """Impulse response (the time derivative of the unit step response), closed form."""
    if zeta < 1.0:
        wd = wn * math.sqrt(1.0 - zeta**2)
        return wn / math.sqrt(1.0 - zeta**2) * np.exp(-zeta * wn * t) * np.sin(wd * t)
    if zeta == 1.0:
        return wn**2 * t * np.exp(-wn * t)
    r = math.sqrt(zeta**2 - 1.0)
    s1, s2 = -wn * (zeta - r), -wn * (zeta + r)
    return s1 * s2 * (np.exp(s1 * t) - np.exp(s2 * t)) / (s1 - s2)


@pytest.mark.parametrize("zeta", [0.1, 0.5, 1.0, 2.5])
def test_second_order_step_response(zeta):
    wn, k = 3.0, 2.0
    t = np.linspace(0.0, 10.0, 201)
    z, y = simulate(SecondOrder, params_of(SecondOrder, wn=wn, zeta=zeta, k=k), step_input, t)
    expected = k * second_order_step(t, wn, zeta)
    assert_allclose(y, expected, atol=1e-8)
    assert_allclose(z[0], y, rtol=0, atol=0)  # state x is the output
    assert_allclose(z[1], k * second_order_impulse(t, wn, zeta), atol=1e-6)  # state dx is dy/dt


@pytest.mark.parametrize("wn, zeta", [(5.0, 0.2), (2.0 * math.pi * 1.5, 1 / math.sqrt(2)), (1.0, 1.7)])
def test_lowpass2_and_highpass2_vs_scipy(wn, zeta):
    t = np.linspace(0.0, 8.0, 4001)

    def u_of(t):
        return 0.5 + np.sin(1.3 * t) + 0.4 * np.sin(9.0 * t)

    den = [1.0, 2.0 * zeta * wn, wn**2]
    for cls, num in [(Lowpass2, [wn**2]), (Highpass2, [1.0, 0.0, 0.0])]:
        params = params_of(cls, wn=wn, zeta=zeta)
        _, y = simulate(cls, params, lambda t: {"u": u_of(t)}, t)
        _, y_ref, _ = signal.lsim((num, den), u_of(t), t)
        assert_allclose(y, y_ref, atol=5e-5, err_msg=cls.__name__)
    # step responses in closed form: low-pass as second_order; high-pass is its second derivative / wn^2
    ts = np.linspace(0.0, 8.0, 81)
    _, y = simulate(Lowpass2, params_of(Lowpass2, wn=wn, zeta=zeta), step_input, ts)
    assert_allclose(y, second_order_step(ts, wn, zeta), atol=1e-8)
    _, y = simulate(Highpass2, params_of(Highpass2, wn=wn, zeta=zeta), step_input, ts)
    _, y_ref = signal.step(([1.0, 0.0, 0.0], den), T=ts)
    assert y[0] == 1.0  # a step passes straight through
    assert_allclose(y[1:], y_ref[1:], atol=1e-7)


# ---------------------------------------------------------------- integrator
def test_integrator_unlimited():
    t = np.linspace(0.0, 3.0, 31)
    params = params_of(Integrator, k=2.0)
    z, y = simulate(Integrator, params, lambda t: {"u": 1.5}, t, start=[0.25])
    assert_allclose(y, 0.25 + 3.0 * t, atol=1e-10)


def test_integrator_limits_stop_the_windup():
    """u = +1 until t = 2, then -1: the limited state stops at y_max = 0.5 and comes down at once."""
    t = np.linspace(0.0, 3.0, 301)

    def u_of(t):
        return {"u": 1.0 if t < 2.0 else -1.0}

    params = params_of(Integrator, k=1.0, y_min=-1.0, y_max=0.5)
    z, y = simulate(Integrator, params, u_of, t, method="RK45", rtol=1e-8, atol=1e-10, max_step=0.01)
    expected = np.where(t < 2.0, np.minimum(t, 0.5), 0.5 - (t - 2.0))
    assert_allclose(y, expected, atol=1e-6)
    assert z[0].max() < 0.5 + 1e-6  # no windup: without limits it would have reached 2.0
    assert Integrator.outputs(x=3.0, y_min=-1.0, y_max=0.5) == (0.5,)
    assert Integrator.derivatives(u=1.0, x=0.5, k=1.0, y_min=-1.0, y_max=0.5) == (0.0,)
    assert Integrator.derivatives(u=-1.0, x=0.5, k=1.0, y_min=-1.0, y_max=0.5) == (-1.0,)
    assert Integrator.derivatives(u=-1.0, x=-1.0, k=1.0, y_min=-1.0, y_max=0.5) == (0.0,)


# ---------------------------------------------------------------- PID
def test_pid_unsaturated_step_in_closed_form():
    """Constant e from rest: y = Kp e + Ki e t + (Kd e / Tf) exp(-t/Tf)."""
    Kp, Ki, Kd, Tf, e = 2.0, 3.0, 0.5, 0.05, 0.4
    t = np.linspace(0.0, 2.0, 201)
    params = params_of(PID, Kp=Kp, Ki=Ki, Kd=Kd, Tf=Tf, Kaw=5.0)
    _, y = simulate(PID, params, lambda t: {"e": e}, t, method="Radau")
    assert_allclose(y, Kp * e + Ki * e * t + Kd * e / Tf * np.exp(-t / Tf), atol=1e-7)


def test_pid_back_calculation_stops_the_windup():
    """Saturated from t = 0 (Kp e > u_max): with Kaw the integral settles at u_max - Kp e + Ki e / Kaw
    (closed form xi(t) = xi_inf (1 - exp(-Kaw t))); with Kaw = 0 it winds up as Ki e t. When e reverses,
    the anti-windup controller leaves saturation at once, the wound-up one stays saturated."""
    Kp, Ki, e, u_max, Kaw, t_rev = 2.0, 1.0, 1.0, 1.0, 4.0, 5.0
    t = np.linspace(0.0, t_rev, 101)
    xi_inf = u_max - Kp * e + Ki * e / Kaw
    common = dict(Kp=Kp, Ki=Ki, Kd=0.0, u_min=-u_max, u_max=u_max)
    z_aw, y_aw = simulate(PID, params_of(PID, Kaw=Kaw, **common), lambda t: {"e": e}, t, method="Radau")
    assert_allclose(z_aw[0], xi_inf * (1.0 - np.exp(-Kaw * t)), atol=1e-7)
    assert_allclose(y_aw, u_max)
    z_wu, y_wu = simulate(PID, params_of(PID, Kaw=0.0, **common), lambda t: {"e": e}, t, method="Radau")
    assert_allclose(z_wu[0], Ki * e * t, atol=1e-7)  # winds up
    assert z_aw[0, -1] == pytest.approx(xi_inf, abs=1e-6) and z_wu[0, -1] == pytest.approx(5.0)

    # reverse the error to e = -0.1 (it would take Kp*0.1 = 0.2 of headroom to leave saturation)
    t2 = np.linspace(t_rev, t_rev + 1.0, 51)
    e2 = -0.1
    for z0, Kaw_, leaves in [(z_aw[:, -1], Kaw, True), (z_wu[:, -1], 0.0, False)]:
        _, y2 = simulate(PID, params_of(PID, Kaw=Kaw_, **common), lambda t: {"e": e2}, t2,
                         method="Radau", start=z0)
        if leaves:
            assert y2[0] < u_max - 0.1  # out of saturation immediately
        else:
            assert_allclose(y2, u_max)  # still saturated a second later (wound-up integral to unwind)


def test_pid_with_ki_zero_keeps_an_offset_from_saturation_unless_kaw_is_zero():
    """Ki = 0 (a P controller): saturated from t = 0 (Kp e = 2 > u_max = 1), the back-calculation moves xi
    as xi(t) = (u_max - Kp e)(1 - exp(-Kaw t)); back inside the limits (e = 0.1) nothing moves it again, so
    the output keeps that offset, Kp e + xi, instead of Kp e. With Kaw = 0 xi stays 0 (the docstring's
    advice for a P controller)."""
    Kp, e, u_max, Kaw = 2.0, 1.0, 1.0, 4.0
    t = np.linspace(0.0, 2.0, 101)
    common = dict(Kp=Kp, Ki=0.0, Kd=0.0, u_min=-u_max, u_max=u_max)
    z, _ = simulate(PID, params_of(PID, Kaw=Kaw, **common), lambda t: {"e": e}, t, method="Radau")
    assert_allclose(z[0], (u_max - Kp * e) * (1.0 - np.exp(-Kaw * t)), atol=1e-7)
    t2 = np.linspace(2.0, 4.0, 51)
    z2, y2 = simulate(PID, params_of(PID, Kaw=Kaw, **common), lambda t: {"e": 0.1}, t2, method="Radau",
                      start=z[:, -1])
    assert z[0, -1] < -0.99
    assert_allclose(z2[0], z[0, -1], atol=1e-12)
    assert_allclose(y2, Kp * 0.1 + z[0, -1], atol=1e-7)
    z0, _ = simulate(PID, params_of(PID, Kaw=0.0, **common), lambda t: {"e": e}, t, method="Radau")
    assert_allclose(z0[0], 0.0, atol=1e-12)


# ---------------------------------------------------------------- numba: the compiler can use every function
def numba_cases():
    xs3 = A([0.1, -0.2, 0.3])
    return [
        (Clock, {"t": 1.25}),
        (Constant, {"value": 3.0}),
        (Step, {"t": 1.0, "t_step": 0.5, "y0": 1.0, "y1": 3.0}),
        (Step, {"t": 0.2, "t_step": 0.5, "y0": 1.0, "y1": 3.0}),
        (Ramp, {"t": 2.0, "t_start": 1.0, "y0": 1.0, "slope": 2.0, "duration": 0.0, "y1": 9.0}),
        (Ramp, {"t": 2.0, "t_start": 1.0, "y0": 1.0, "slope": 2.0, "duration": 4.0, "y1": 9.0}),
        (Profile, {"t": 1.7, "times": A([0.0, 1.0, 3.0]), "values": A([0.0, 2.0, -1.0])}),
        (Gain, {"u": 1.5, "k": -2.0}),
        (Sum, {"u1": 1.0, "u2": 2.0, "u3": 3.0, "k1": 1.0, "k2": -1.0, "k3": 0.5}),
        (Product, {"u1": 1.5, "u2": -3.0}),
        (Saturation, {"u": 4.0, "lower": -1.0, "upper": 2.0}),
        (DeadBand, {"u": -4.0, "lower": -1.0, "upper": 2.0}),
        (DeadBand, {"u": 0.0, "lower": -1.0, "upper": 2.0}),
        (Lookup1D, {"u": 5.0, "x_table": X_TAB, "y_table": Y_TAB, "extrapolate": 1.0}),
        (Lookup1D, {"u": 0.3, "x_table": X_TAB, "y_table": Y_TAB, "extrapolate": 0.0}),
        (Lookup2D, {"u1": 0.4, "u2": 2.5, "x_table": A([0.0, 1.0]), "y_table": A([0.0, 1.0, 3.0]),
                    "z_table": A([1.0, 2.0, 3.0, 4.0, 5.0, 7.0])}),
        (TransferFunction, {"u": 0.7, "x": xs3, "num": A([1.0, 2.0, 3.0, 4.0]), "den": A([2.0, 3.0, 4.0, 5.0])}),
        (TransferFunctionStrict, {"u": 0.7, "x": xs3, "num": A([1.0, 3.0]), "den": A([2.0, 3.0, 4.0, 5.0])}),
        (SecondOrder, {"u": 1.0, "x": 0.2, "dx": -0.5, "wn": 3.0, "zeta": 0.4, "k": 2.0}),
        (Lowpass2, {"u": 1.0, "x": 0.2, "dx": -0.5, "wn": 3.0, "zeta": 0.4}),
        (Highpass2, {"u": 1.0, "x": 0.2, "dx": -0.5, "wn": 3.0, "zeta": 0.4}),
        (Integrator, {"u": 1.0, "x": 0.5, "k": 2.0, "y_min": -1.0, "y_max": 0.5}),
        (Integrator, {"u": -1.0, "x": 0.5, "k": 2.0, "y_min": -1.0, "y_max": 0.5}),
        (PID, {"e": 0.3, "xi": 0.1, "xd": 0.05, "Kp": 2.0, "Ki": 1.0, "Kd": 0.1, "Tf": 0.01,
               "u_min": -0.5, "u_max": 0.5, "Kaw": 3.0}),
        (Switch, {"u1": 1.0, "control": 0.2, "u2": 2.0, "threshold": 0.5}),
    ]


_JITTED: dict = {}


def jitted(fn):
    if fn not in _JITTED:
        _JITTED[fn] = numba.njit(fn)
    return _JITTED[fn]


def _with_der(cls, values):
    """Copies of the array values, plus zeroed der_<array state> views, for one call."""
    v = {k: (x.copy() if isinstance(x, np.ndarray) else float(x)) for k, x in values.items()}
    v.setdefault("t", 0.0)
    for s in cls.states:
        if s.size is not None:
            v["der_" + s.name] = np.zeros_like(v[s.name])
    return v


def test_numba_cases_cover_every_signal_block():
    assert {cls for cls, _ in numba_cases()} == set(SIGNAL_TYPES.values())


@pytest.mark.parametrize("cls, values", numba_cases(), ids=[c.__name__ for c, _ in numba_cases()])
def test_numba_compiles_and_agrees(cls, values):
    for fn in (cls.outputs, cls.derivatives):
        if fn is None:
            continue
        py_values, nb_values = _with_der(cls, values), _with_der(cls, values)
        expected = call(fn, py_values)
        got = call(jitted(fn), nb_values)
        assert isinstance(got, tuple) and len(got) == len(expected)
        assert_allclose(np.array(got, dtype=float), np.array(expected, dtype=float), rtol=1e-14, atol=0)
        for s in cls.states:
            if s.size is not None and fn is cls.derivatives:
                assert_allclose(nb_values["der_" + s.name], py_values["der_" + s.name], rtol=1e-14, atol=0)
                assert np.any(nb_values["der_" + s.name] != 0.0)  # really written in place
    # the expected number of returned values
    if cls.outputs is not None:
        assert len(call(cls.outputs, _with_der(cls, values))) == len(cls.output_names())
    if cls.derivatives is not None:
        assert len(call(cls.derivatives, _with_der(cls, values))) == len(cls.derivative_names())


@settings(deadline=None, max_examples=50)
@given(st.floats(-3.0, 6.0), st.floats(-3.0, 6.0))
def test_numba_lookup_2d_agrees_everywhere(u1, u2):
    xs, ys, zs = A([0.0, 1.0, 3.0]), A([-1.0, 2.0]), A([1.0, -2.0, 0.5, 3.0, 4.0, 4.5])
    v = dict(u1=u1, u2=u2, x_table=xs, y_table=ys, z_table=zs)
    assert call(jitted(Lookup2D.outputs), v) == call(Lookup2D.outputs, v)
