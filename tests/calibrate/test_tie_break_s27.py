"""Ties between equivalent places are broken by name, not by rounding (blocks.calibrate.selection.tie_broken).

A turbulent loss on either side of one valve (the same flow through it) is the same effect: its two places
screen and refit alike to 1e-12, and which came first followed the last digits, so the same data gave
`line_loss_turbulent@meter.b` on one machine and `...@meter.a` on another (the Monte Carlo's seed 1 of
`steady_line_loss_turbulent`, rerun on newer numpy/scipy in session 27). Here each order of the rounding
noise, and each input order, must give the same choice: the first place by name. A real difference (over
0.01 in BIC) still ranks by BIC."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import test_elimination as elimination_harness
import test_exchange as exchange_harness

from blocks.calibrate import selection
from blocks.calibrate.elimination import try_removals
from blocks.calibrate.exchange import try_exchanges
from blocks.calibrate.experiment import Free
from blocks.calibrate.screening import Score

NOISE = 1e-12  # the relative size of the rounding that separated the two places


def _score(key: str, T: float) -> Score:
    return Score(SimpleNamespace(key=key, zero=0.0, plausible=(-1e9, 1e9)), "screened", T=T)


@pytest.mark.parametrize("noise", [NOISE, -NOISE])
@pytest.mark.parametrize("reverse", [False, True])
def test_tied_screening_scores_send_the_first_place_by_name_to_the_refit(noise, reverse):
    """top = 1 and two tied scores: the refit goes to meter.a whichever scored higher by rounding."""
    scores = [_score("loss@meter.b", 80.0 * (1 + noise)), _score("loss@meter.a", 80.0), _score("leak", 30.0)]
    chosen = selection.candidates_to_refit(scores[::-1] if reverse else scores, 1)
    assert [s.place.key for s in chosen] == ["loss@meter.a"]


def test_a_score_higher_by_more_than_rounding_is_refitted_first_whatever_its_name():
    scores = [_score("loss@meter.a", 80.0), _score("loss@meter.b", 80.001)]
    assert [s.place.key for s in selection.candidates_to_refit(scores, 2)] == ["loss@meter.b", "loss@meter.a"]


def _decide(monkeypatch, dbic: dict[str, float], order: list[str]):
    """decide() with refits standing in for the fits: each place's dBIC given, every one 20 SE from zero."""
    def fake_refit(model, x0, column, base, score):
        fitted = SimpleNamespace(run_failure=lambda beyond: "", n=100, p=3)
        key = score.place.key
        return selection.Refit(score, None, fitted, 20.0, 1.0, dbic[key] - 5.0, dbic[key], True)

    monkeypatch.setattr(selection, "refit", fake_refit)
    monkeypatch.setattr(selection, "restarted", lambda rf: rf)
    monkeypatch.setattr(selection, "_aligned", lambda base, base_model, model: base)
    monkeypatch.setattr(selection, "separate", lambda a, b: [])
    monkeypatch.setattr(selection, "choice_moves", lambda a, b: None)
    scores = [_score(key, 50.0 - i) for i, key in enumerate(order)]
    return selection.decide(scores, 5, None, None, None, lambda s: (None, None, 0), with_heldout=False)


@pytest.mark.parametrize("noise", [1e-10, -1e-10, 0.009, -0.009])
@pytest.mark.parametrize("order", [["loss@meter.b", "loss@meter.a", "leak"], ["leak", "loss@meter.a", "loss@meter.b"]])
def test_refits_tied_in_bic_accept_the_first_place_by_name_and_call_the_other_ambiguous(monkeypatch, noise, order):
    decision = _decide(monkeypatch, {"loss@meter.b": -116.444 + noise, "loss@meter.a": -116.444, "leak": -71.5},
                       order)
    assert [rf.score.place.key for rf in decision.refits] == ["loss@meter.a", "loss@meter.b", "leak"]
    assert decision.accepted.score.place.key == "loss@meter.a"
    assert decision.ambiguous == ["loss@meter.b"]


def test_a_refit_better_by_over_the_tie_margin_is_accepted_whatever_its_name(monkeypatch):
    decision = _decide(monkeypatch, {"loss@meter.b": -116.444 - 0.011, "loss@meter.a": -116.444, "leak": -71.5},
                       ["loss@meter.a", "loss@meter.b", "leak"])
    assert decision.accepted.score.place.key == "loss@meter.b"


def test_a_run_of_ties_is_measured_from_its_first_so_small_steps_do_not_chain():
    """Values 0, 0.006, 0.012 (each step under 0.01, the span over it): 0 and 0.006 are tied and ordered by
    name; 0.012 is not tied with 0 and stays last although its name comes first."""
    items = [("c", 0.0), ("b", 0.006), ("a", 0.012)]
    assert selection.tie_broken(items, lambda i: i[1], lambda i: i[0]) == [("b", 0.006), ("c", 0.0), ("a", 0.012)]


@pytest.mark.parametrize("first", ["B", "A"])
def test_of_two_effects_whose_removals_cost_the_same_the_first_by_name_is_removed(tmp_path, first):
    """The elimination check (blocks.calibrate.elimination) on test_elimination's stand-in fit: A and B both at
    0.5 SE, so removing either lowers BIC by the same 0.25 - ln n; the effects listed in either order, A goes
    first (before, the first listed went)."""
    _place, _stage = elimination_harness._place, elimination_harness._stage

    def fit_stage(netlist, globals_, x_prev, prev_model):
        kept = [g.name.split(":", 1)[1] for g in globals_ if g.name.startswith("p:")]
        return _stage({key: {"A": 0.5, "B": 0.5, "C": 20.0}[key] for key in kept},
                      50.0 + sum(0.25 for key in "AB" if key not in kept))

    order = [first, "B" if first == "A" else "A", "C"]
    final = _stage({key: {"A": 0.5, "B": 0.5, "C": 20.0}[key] for key in order}, 50.0)
    effects = [(_place(key), i + 1) for i, key in enumerate(order)]
    globals_ = [Free(n, 0.0, -1e9, 1e9, 1.0, "") for n in ["k_s"] + [f"p:{key}" for key in order]]
    tests = try_removals(final, effects, globals_, elimination_harness.RIG, tmp_path, fit_stage)
    assert [t.key for t in tests if t.removed][0] == "A"
    (b_first,) = [t for t in tests if t.key == "B" and t.check == 1]
    assert b_first.reasons == ["A is removed first (its removal costs as little, and its name comes first); "
                               "tested again after it"]


@pytest.mark.parametrize("noise", [1e-9, -1e-9])
def test_of_two_exchanges_that_fit_the_same_the_first_by_name_is_made(tmp_path, noise):
    """The exchange check (blocks.calibrate.exchange) on test_exchange's hand-made rounds: round 1 took A, and
    swapping it for Z or for B lowers BIC by the same 13 (to rounding); B is made whichever rounds lower and
    although Z is listed first."""
    _refit, _round = exchange_harness._refit, exchange_harness._round
    rounds = [_round(1, _refit("A"), _refit("Z"), _refit("B")), _round(2, _refit("D"))]
    names = ["k_s", "p:A", "p:D"]
    final = SimpleNamespace(fit=SimpleNamespace(x=np.array([1.0, 2.0, 3.0]), bic=lambda: 100.0, failed_rows=0),
                            model=SimpleNamespace(layout=SimpleNamespace(index=names.index)))
    cal = SimpleNamespace(rounds=rounds, final=final, out=tmp_path, exp=SimpleNamespace(netlist=exchange_harness.RIG))
    bic = {"p:Z": 87.0, "p:B": 87.0 + noise}

    def fit_stage(netlist, globals_, x_prev, prev_model):
        new = [g.name for g in globals_]
        (put_in,) = [n for n in new if n in bic]
        x = np.zeros(len(new))
        x[new.index(put_in)] = 5.0
        return SimpleNamespace(model=SimpleNamespace(layout=SimpleNamespace(index=new.index)),
                               fit=SimpleNamespace(x=x, se=np.ones(len(new)), bic=lambda: bic[put_in],
                                                   run_failure=lambda beyond: ""))

    tried = try_exchanges(cal, [Free(n, 0.0, -1.0, 1.0, 1.0, "") for n in names], fit_stage)
    assert [ex.in_key for ex in tried] == ["Z", "B"]
    assert [(ex.out_key, ex.in_key) for ex in tried if ex.made] == [("A", "B")]
    assert tried[0].reasons == ["A -> B fits as well, and comes first by name"]
