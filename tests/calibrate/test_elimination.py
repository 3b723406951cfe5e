"""The elimination check after the trace (blocks.calibrate.elimination), on a hand-made final model: which
effects are refitted without, which one is removed, the pass after it, and why the others stay. Sensor
places (no netlist patch) and a stand-in fit whose chi^2 is that of a linear model: removing an effect
raises chi^2 by its z^2."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np

from blocks.calibrate.elimination import try_removals
from blocks.calibrate.experiment import Free

RIG = Path(__file__).resolve().parents[2] / "netlists" / "experiments" / "circuits" / "relief_rig.yaml"
N = 100  # residual rows: ln n = 4.6, the Wald bar 4*(10 + ln n) = 58.4 in z^2


def _place(key):
    return SimpleNamespace(key=key, param=f"p:{key}", kind="channel", zero=0.0)


def _stage(z: dict, chi2: float):
    """A fitted model holding the effects of ``z`` (name -> |value|/SE) beside one declared parameter."""
    names = ["k_s"] + [f"p:{key}" for key in z]
    x = np.array([1.0] + list(z.values()))
    fit = SimpleNamespace(x=x, se=np.ones(len(names)), n=N, chi2=chi2,
                          bic=lambda: chi2 + len(names) * np.log(N))
    return SimpleNamespace(fit=fit, model=SimpleNamespace(layout=SimpleNamespace(index=names.index)),
                           effects=dict(z))


def test_the_weakest_effect_is_removed_and_the_rest_tested_again(tmp_path):
    """A at 0.5 SE (a stand-in a later effect took over), B at 3.5 SE (removing it costs 12.25 - 4.6 = 7.6 in
    BIC: under the bar of 10, so it would not be accepted now), C at 20 SE (Wald: stays, not refitted).
    Pass 1 removes A (its removal lowers BIC by 4.4, the lowest); B qualifies too and is tested again in pass
    2, where (the stand-in moves B to 3.8 SE once A is out) its removal still costs 7.6: removed. One effect
    left: no pass 3."""
    seen = []

    def fit_stage(netlist, globals_, x_prev, prev_model):
        assert Path(netlist).is_file()  # rebuilt from the declared netlist
        kept = [g.name.split(":", 1)[1] for g in globals_ if g.name.startswith("p:")]
        seen.append(kept)
        z = {key: {"A": 0.5, "B": 3.8 if "A" not in kept else 3.5, "C": 20.0}[key] for key in kept}
        return _stage(z, 50.0 + sum(v * v for k, v in {"A": 0.5, "B": 3.5, "C": 20.0}.items() if k not in kept))

    final = _stage({"A": 0.5, "B": 3.5, "C": 20.0}, 50.0)
    effects = [(_place("A"), 1), (_place("B"), 2), (_place("C"), 3)]
    globals_ = [Free(n, 0.0, -1e9, 1e9, 1.0, "") for n in ["k_s", "p:A", "p:B", "p:C"]]
    tests = try_removals(final, effects, globals_, RIG, tmp_path, fit_stage)
    assert [(t.check, t.key, t.refitted, t.removed) for t in tests] == [
        (1, "A", True, True), (1, "B", True, False), (1, "C", False, False),
        (2, "B", True, True), (2, "C", False, False)]
    assert seen == [["B", "C"], ["A", "C"], ["C"]]  # A out, then B out; C never refitted without
    assert np.isclose(tests[0].dbic, 0.25 - np.log(N)) and np.isclose(tests[1].dbic, 12.25 - np.log(N))
    assert tests[1].reasons == ["A is removed first (its removal costs less); tested again after it"]
    assert tests[2].reasons[0].startswith("20 SE from zero: removing it would raise BIC by about 395 (not refitted)")
    assert tests[3].globals_ and [g.name for g in tests[3].globals_] == ["k_s", "p:C"]
    assert (tmp_path / "elimination" / "pass2_without_B.yaml").is_file()


def test_effects_that_pass_both_tests_stay(tmp_path):
    """B at 4 SE: its removal costs 16 - 4.6 = 11.4 in BIC (over 10) and it is over 3 SE: it stays. D's
    removal costs over 10 too (15 - 4.6; a nonlinear effect, where z^2 and the chi^2 rise differ), but it is
    at 2.9 SE: an effect must pass both tests to stay, so D goes."""
    def fit_stage(netlist, globals_, x_prev, prev_model):
        kept = [g.name.split(":", 1)[1] for g in globals_ if g.name.startswith("p:")]
        (removed,) = set(in_final) - set(kept)
        cost = {"B": 16.0, "D": 15.0}[removed]  # D: a removal that costs 15 in chi^2 (nonlinear), yet only 2.9 SE
        return _stage({k: 1.0 for k in kept}, 50.0 + cost)

    in_final = ["B", "C"]
    final = _stage({"B": 4.0, "C": 20.0}, 50.0)
    globals_ = [Free(n, 0.0, -1e9, 1e9, 1.0, "") for n in ["k_s", "p:B", "p:C"]]
    tests = try_removals(final, [(_place("B"), 1), (_place("C"), 2)], globals_, RIG, tmp_path, fit_stage)
    assert not any(t.removed for t in tests)
    assert tests[0].reasons == ["removing it raises BIC by 11.4 (over 10) and it is 4 SE from zero (over 3)"]
    in_final = ["D", "C"]
    final = _stage({"D": 2.9, "C": 20.0}, 50.0)
    globals_ = [Free(n, 0.0, -1e9, 1e9, 1.0, "") for n in ["k_s", "p:D", "p:C"]]
    tests = try_removals(final, [(_place("D"), 1), (_place("C"), 2)], globals_, RIG, tmp_path, fit_stage)
    assert [(t.key, t.removed) for t in tests] == [("D", True), ("C", False)]


def test_nothing_is_tested_with_one_effect(tmp_path):
    final = _stage({"A": 0.5}, 50.0)
    assert try_removals(final, [(_place("A"), 1)], [], RIG, tmp_path, lambda *args: None) == []
