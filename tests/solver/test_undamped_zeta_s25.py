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
