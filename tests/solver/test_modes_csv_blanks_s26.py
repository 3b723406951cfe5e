"""The modes CSV leaves blank what the console writes as '-': a real mode has no natural frequency (the CSV
wrote f_n = 0, which reads as a mode at 0 Hz), an integrator has no damping ratio (it wrote nan)."""

import csv
import io
import math

import pytest

from blocks.linear_report import modes_csv
from blocks.linearise import Mode


def rows(found):
    return list(csv.DictReader(io.StringIO(modes_csv(found))))


def test_a_real_mode_has_no_natural_frequency_and_an_integrator_no_zeta():
    decaying, integrator, pair = rows([Mode(complex(-30.0, 0.0), [("x", 1.0)]),
                                      Mode(complex(0.0, 0.0), [("y", 1.0)]),
                                      Mode(complex(-3.0, 4.0), [("z", 1.0)])])
    assert decaying["f_n [Hz]"] == "" and decaying["zeta [1]"] == "1"
    assert integrator["f_n [Hz]"] == "" and integrator["zeta [1]"] == "" and integrator["tau [s]"] == "inf"
    # |lambda| = 5 1/s: f_n = 5/(2*pi) Hz, zeta = 3/5
    assert float(pair["f_n [Hz]"]) == pytest.approx(5 / (2 * math.pi), rel=1e-9)  # written to 10 digits
    assert float(pair["zeta [1]"]) == pytest.approx(0.6, rel=1e-6)
