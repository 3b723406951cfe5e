"""Generic signal and mechanical blocks against laws their existing tests did not pin down; written from a
mutation test of blocks/library/mechanical and blocks/library/signal (session 26), one law per test.

Each block alone, its raw equation functions called by argument name (as in test_signal_blocks.py).
Tolerances: the closed forms are written here from the docstrings and evaluated in the same floating-point
operations on numbers of order 1-100, so they agree to a few ulps: rel 1e-12.
"""

from __future__ import annotations

import pytest

from blocks.block import argument_names
from blocks.library.signal.pid import PID


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
