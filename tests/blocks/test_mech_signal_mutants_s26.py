"""Generic signal and mechanical blocks against laws their existing tests did not pin down; written from a
mutation test of blocks/library/mechanical and blocks/library/signal (session 26), one law per test.

Each block alone, its raw equation functions called by argument name (as in test_signal_blocks.py).
Tolerances: the closed forms are written here from the docstrings and evaluated in the same floating-point
operations on numbers of order 1-100, so they agree to a few ulps: rel 1e-12.
"""

from __future__ import annotations

import numpy as np
import pytest

from blocks.block import argument_names
from blocks.library.signal.integrator import Integrator
from blocks.library.signal.pid import PID
from blocks.library.signal.profile import Profile
from blocks.library.signal.ramp import Ramp


def call(fn, values: dict):
    """Call an equation function as the compiler does: by argument name."""
    return fn(**{name: values[name] for name in argument_names(fn)})


# ---------------------------------------------------------------- PID
@pytest.mark.parametrize("e, xd, xi", [(0.8, 0.2, 0.3), (0.8, 1.5, 0.1), (-0.6, 0.4, -0.2), (-0.6, -1.9, -0.5)])
def test_pid_back_calculation_uses_the_whole_unsaturated_output(e, xd, xi):
    """While the output is limited, dxi/dt = Ki*e + Kaw*(y - v), v = Kp*e + xi + Kd*(e - xd)/Tf the
    unsaturated output with its derivative part (docstring; C(s) = Kp + Ki/s + Kd*s/(Tf*s + 1)). Checked at
    points where the output is saturated and the derivative part Kd*(e - xd)/Tf is of the order of the rest,
    so leaving it out, flipping it or mis-scaling it by Tf changes dxi/dt by more than 10 %."""
    p = dict(Kp=1.5, Ki=2.0, Kd=0.03, Tf=0.05, u_min=-0.5, u_max=0.5, Kaw=4.0)
    vals = p | dict(e=e, xi=xi, xd=xd)
    v = p["Kp"] * e + xi + p["Kd"] * (e - xd) / p["Tf"]
    y = min(max(v, p["u_min"]), p["u_max"])
    assert y != v  # saturated
    (y_block,) = call(PID.outputs, vals)
    assert y_block == y
    dxi, dxd = call(PID.derivatives, vals)
    assert dxi == pytest.approx(p["Ki"] * e + p["Kaw"] * (y - v), rel=1e-12)
    assert dxd == pytest.approx((e - xd) / p["Tf"], rel=1e-12)


# ---------------------------------------------------------------- time signals



@pytest.mark.parametrize("duration", [0.25, 0.5, 1.0, 4.0])
def test_ramp_with_duration_is_the_straight_line_from_y0_to_y1(duration):
    """duration > 0: y = y0 + (y1 - y0)*(t - t_start)/duration on [t_start, t_start + duration], y1 after
    (the docstring), for any duration, also under a second; checked at the quarter points, where a line
    through both ends is the only law that passes (an error in the interpolation moves at least one of
    them by > 10 %), and beyond the end, where the slope (ignored) would carry it on."""
    p = dict(t_start=1.0, y0=2.0, slope=123.0, duration=duration, y1=10.0)
    for frac in (0.25, 0.5, 0.75):
        (y,) = Ramp.outputs(t=1.0 + frac * duration, **p)
        assert y == pytest.approx(2.0 + 8.0 * frac, rel=1e-12)
    assert Ramp.outputs(t=1.0 + 2.0 * duration, **p) == (10.0,)
    assert Ramp.outputs(t=1.0 + duration, **p) == (10.0,)


@pytest.mark.parametrize("duration", [0.25, 0.5, 1.0, 4.0])
def test_ramp_breakpoints_are_both_kinks(duration):
    """A ramp with a duration kinks at t_start and at t_start + duration (where it stops): the solver is
    told of both, whatever the duration; an unbounded ramp (duration 0) only at t_start."""
    p = dict(t_start=1.0, y0=2.0, slope=3.0, duration=duration, y1=10.0)
    assert Ramp.breakpoints(p) == (1.0, 1.0 + duration)
    assert Ramp.breakpoints(p | {"duration": 0.0}) == (1.0,)


def test_profile_breakpoints_skip_points_inside_a_straight_run():
    """Breakpoints are where the profile's slope changes (docstring): a straight line split into segments of
    unequal length (slope 1 over [0, 1] and [1, 3]) has none at t = 1; the points where it starts and stops
    moving (0 and 3) are breakpoints, 4 and 5 (flat padding) are not. A second profile with equal slopes
    -2 over [0, 0.5] and [0.5, 2] likewise has none at 0.5. The slopes here are exact in binary floating
    point, so the comparison is exact."""
    v = {"times": np.array([0.0, 1.0, 3.0, 4.0, 5.0]), "values": np.array([0.0, 1.0, 3.0, 3.0, 3.0])}
    assert Profile.breakpoints(v) == (0.0, 3.0)
    v = {"times": np.array([0.0, 0.5, 2.0, 4.0]), "values": np.array([1.0, 0.0, -3.0, 1.0])}  # slopes -2, -2, 2
    assert Profile.breakpoints(v) == (0.0, 2.0, 4.0)


# ---------------------------------------------------------------- integrator


@pytest.mark.parametrize("rate", [1e-6, 0.3, 0.999, 5.0])
def test_integrator_leaves_a_limit_as_soon_as_the_input_reverses(rate):
    """Conditional integration (docstring): at a limit the state stops only while k*u pushes it further out;
    any rate back inside, however small, moves it at once: dx/dt = k*u at x = y_min with k*u > 0 and at
    x = y_max with k*u < 0; pushing outwards, dx/dt = 0."""
    p = dict(k=2.0, y_min=-1.0, y_max=0.5)
    u = rate / p["k"]
    assert Integrator.derivatives(u=u, x=p["y_min"], **p) == (pytest.approx(rate, rel=1e-15),)
    assert Integrator.derivatives(u=-u, x=p["y_max"], **p) == (pytest.approx(-rate, rel=1e-15),)
    assert Integrator.derivatives(u=-u, x=p["y_min"], **p) == (0.0,)
    assert Integrator.derivatives(u=u, x=p["y_max"], **p) == (0.0,)
