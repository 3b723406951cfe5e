"""Cost terms (eqs. 4.1, 4.2) against closed forms, and the offline high-pass against the highpass2 block."""

from pathlib import Path

import numpy as np
import pytest

from blocks.optimise.costs import Term, combine, evaluate_term, highpass

HERE = Path(__file__).parent
T = np.linspace(0.0, 2.0, 4001)  # 0.5 ms
A = 0.003  # m
W = 2 * np.pi * 5.0  # 10 whole periods in 2 s


def test_ise_of_a_sine_error_in_mm():
    # e = 3 mm * sin(w t) over whole periods: int e^2 dt = (3 mm)^2 / 2 * 2 s = 9 mm^2*s
    signals = {"x": 1.0 + A * np.sin(W * T), "x_ref": np.full_like(T, 1.0)}
    term = Term("pos", "ise", "x", reference="x_ref", scale=1e-3, unit="mm")
    assert evaluate_term(term, T, signals) == pytest.approx(9.0, rel=1e-5)
    constant = Term("pos", "ise", "x", offset=1.0, scale=1e-3, unit="mm")  # the same against a constant
    assert evaluate_term(constant, T, signals) == pytest.approx(9.0, rel=1e-5)


def test_max_abs_and_window():
    signals = {"x": A * np.sin(W * T) * (T < 1.0) + 2 * A * np.sin(W * T) * (T >= 1.0)}
    assert evaluate_term(Term("m", "max_abs", "x", scale=1e-3), T, signals) == pytest.approx(6.0, rel=1e-4)
    early = Term("m", "max_abs", "x", scale=1e-3, t_to=0.999)
    assert evaluate_term(early, T, signals) == pytest.approx(3.0, rel=1e-4)
    # int over [1, 2] s of (6 mm sin)^2 = 36/2 * 1 s = 18 mm^2*s
    late = Term("p", "ise", "x", scale=1e-3, t_from=1.0)
    assert evaluate_term(late, T, signals) == pytest.approx(18.0, rel=1e-4)


def test_highpass_of_a_constant_is_zero_from_the_start():
    t = np.arange(0, 1.0 + 1e-12, 1e-3)
    y = highpass(t, np.full_like(t, 20e5), 100.0, 0.7071)  # 20 bar: no step at t = 0
    assert np.max(np.abs(y)) < 1e-6 * 20e5


@pytest.mark.parametrize("w", [100.0 / 3, 100.0, 300.0])
def test_highpass_gain_and_phase_match_H_of_jw(w):
    """y = H(jw) u in steady state, H(s) = s^2/(s^2 + 2 zeta wn s + wn^2). Sampling at dt makes the
    offline filter's gain low by about (wn*dt)^2/12 (measured: 8.3e-4 at 100 rad/s and 1 ms, scaling with
    dt^2), so the gain is checked to 1e-3 and the phase to 5 mrad."""
    wn, zeta, dt = 100.0, 0.7071, 1e-3
    t = np.arange(0, 4.0 + 1e-12, dt)
    y = highpass(t, 20e5 + 1e5 * np.sin(w * t), wn, zeta)
    s = 1j * w
    H = s * s / (s * s + 2 * zeta * wn * s + wn * wn)
    keep = t >= 2.0  # transients (exp(-zeta*wn*t)) long gone
    M = np.column_stack([np.sin(w * t[keep]), np.cos(w * t[keep])])
    a, b = np.linalg.lstsq(M, y[keep], rcond=None)[0]
    G = complex(a, b) / 1e5
    assert abs(G) == pytest.approx(abs(H), rel=1e-3)
    assert abs(np.angle(G / H)) < 5e-3
    # and the cost term: int over whole periods of y^2 = |H|^2 * (1e5)^2 / 2 * duration
    periods = int((t[-1] - 2.0) * w / (2 * np.pi))
    t_to = 2.0 + periods * 2 * np.pi / w
    fine = np.linspace(0, t_to, int(round(t_to / 1e-4)) + 1)  # whole periods on the sample grid
    J = evaluate_term(Term("vib", "hp_ise", "p", wn=wn, zeta=zeta, t_from=2.0),
                      fine, {"p": 20e5 + 1e5 * np.sin(w * fine)})
    assert J == pytest.approx(abs(H) ** 2 * 1e10 / 2 * (t_to - 2.0), rel=2e-3)


def test_highpass_on_a_ragged_grid_matches_the_uniform_one():
    t = np.arange(0, 1.0 + 1e-12, 1e-3)
    u = np.sin(60 * t) + 0.3 * np.sin(250 * t)
    ragged = np.append(t, 1.0004)  # a short last step, as when t_end is not a multiple of dt_out
    y_uniform = highpass(t, u, 100.0, 0.7)
    y_ragged = highpass(ragged, np.append(u, np.sin(60 * 1.0004) + 0.3 * np.sin(250 * 1.0004)), 100.0, 0.7)
    np.testing.assert_allclose(y_ragged[:-1], y_uniform, atol=2e-2 * np.max(np.abs(y_uniform)))


def test_offline_highpass_matches_the_simulated_highpass2_block():
    """The same drive line with pA also passed through a highpass2 block (corner 100 rad/s, started at
    20 bar): the cost term's offline filter of the logged pA (1 ms samples) against the block's output,
    which sees the continuous pA. Expected difference in int y^2: -(wn*dt)^2/6 = -0.17 % (see above)."""
    from blocks.circuit import Circuit

    circuit = Circuit.from_file(HERE / "netlists" / "drive_line_hp.yaml")
    term = Term("vib", "hp_ise", "pA", wn=100.0, zeta=0.7071)
    block = Term("vib_block", "ise", "pA_high")  # the block's output, squared and integrated as is
    for overrides in ({}, {"Kp": 20.0, "Kvp": 1.5}):
        r = circuit.simulate(overrides)
        offline, simulated = evaluate_term(term, r.t, r), evaluate_term(block, r.t, r)
        assert offline == pytest.approx(simulated, rel=3e-3)
        assert simulated > 1e9  # the check is not 0 == 0: the motion does excite pA
        y = highpass(r.t, r["pA"], 100.0, 0.7071)
        assert np.max(np.abs(y - r["pA_high"])) < 3e-3 * np.max(np.abs(r["pA_high"]))


def test_combine_load_cases():
    assert combine([1.0, 2.0, 6.0], "sum") == 9.0
    assert combine([1.0, 2.0, 6.0], "mean") == 3.0
    assert combine([1.0, 2.0, 6.0], "worst") == 6.0
    with pytest.raises(ValueError):
        combine([1.0], "median")


def test_a_sweep_maps_each_term_combined_over_the_load_cases_as_the_job_combines_its_cost():
    """The sweep plot's term panels showed the mean over the load cases even for a job whose cost takes the
    worst case (a usability review)."""
    from blocks.optimise.report import _combined_term

    record = {"cases": {"empty": {"terms": {"pos": 1.0}}, "full": {"terms": {"pos": 3.0}}}}
    got = {how: _combined_term(record, "pos", ["empty", "full"], how) for how in ("sum", "mean", "worst")}
    assert got == {"sum": 4.0, "mean": 2.0, "worst": 3.0}


def test_a_failed_evaluation_is_numbered_by_its_place_on_the_path():
    """The log's index also counts evaluations discarded on the way (several workers); the report numbers
    the path's evaluations by their place on it, the failures too."""
    from blocks.optimise.report import _distinct_errors

    records = [{"index": 0, "status": "ok"}, {"index": 3, "status": "failed", "error": "solver"},
               {"index": 5, "status": "failed", "error": "solver"}, {"index": 6, "status": "failed", "error": "nan"}]
    assert _distinct_errors(records) == ["evaluation 1: solver", "evaluation 3: nan"]
