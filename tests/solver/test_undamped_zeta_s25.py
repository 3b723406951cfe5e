"""An undamped pair's damping ratio is 0, not -0 (the modes table printed 'zeta -0' for an eigenvalue 0 + 5j,
which reads as a growing mode)."""

import math

from blocks.linear_report import modes_csv, modes_table
from blocks.linearise import Mode


def test_an_undamped_pair_has_zeta_plus_zero():
    mode = Mode(complex(0.0, 5.0), [("x", 1.0)])
    assert mode.damping == 0.0 and math.copysign(1.0, mode.damping) == 1.0
    assert " -0 " not in modes_table([mode]) and ",-0," not in modes_csv([mode])


def test_a_growing_pair_keeps_its_negative_zeta():
    assert Mode(complex(0.5, 5.0), [("x", 1.0)]).damping < 0.0


def test_a_repeated_real_eigenvalue_split_by_rounding_is_two_real_modes():
    """A critically damped spool filter (zeta = 1, wn = 75.4 rad/s) has -wn twice; in a circuit's scaled A
    eig found it as a pair about 2e-8 of its size apart (a user review saw '-75.4 +- 1.6e-06j, zeta 1,
    12 Hz' for one axis and two real rows for the others). The same split, made here by a coupling of
    (2e-8*wn)^2: two real modes; a pair 1e-3 of its size apart stays a pair."""
    import numpy as np
    import pytest

    from blocks.linearise import _eig

    wn = 2 * math.pi * 12.0
    for apart, real in ((2e-8, True), (1e-3, False)):
        A = np.array([[-wn, 1.0], [-(apart * wn) ** 2, -wn]])
        assert np.abs(np.linalg.eigvals(A).imag) == pytest.approx([apart * wn] * 2, rel=1e-3)  # eig's own
        values = _eig(A)[0]
        assert np.all(values.imag == 0.0) == real, values
        assert values.real == pytest.approx([-wn, -wn], rel=1e-6)
