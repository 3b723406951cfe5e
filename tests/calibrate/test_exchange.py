"""The exchange check after the trace (blocks.calibrate.exchange), on hand-made rounds: which swaps are
tried, which one is made, and why the others are not. Sensor places (no netlist patch) and a stand-in fit."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np

from blocks.calibrate.exchange import try_exchanges
from blocks.calibrate.experiment import Free

RIG = Path(__file__).resolve().parents[2] / "netlists" / "experiments" / "circuits" / "relief_rig.yaml"


def _place(key):
    return SimpleNamespace(key=key, param=f"p:{key}", kind="channel", zero=0.0, lower=-1e9, upper=1e9, step=1.0,
                           unit="Pa", plausible=(-1e6, 1e6), candidate="sensor_offset")


def _refit(key, passes=True, phi=5.0):
    return SimpleNamespace(score=SimpleNamespace(place=_place(key), step=None), passes_fit_tests=passes, phi=phi)


def _round(index, accepted, *others):
    return SimpleNamespace(index=index, decision=SimpleNamespace(accepted=accepted, refits=[accepted, *others]))


def test_the_swaps_tried_and_the_one_made(tmp_path):
    """Round 1 took A (alternatives: B passes the fit tests, C does not, D is accepted later anyway); round 2
    took D (alternatives G, H); round 3 took E (alternative F, never tried: the last accepting round's
    alternatives were refitted beside exactly the final model's other effects). The stand-in fit gives the
    exchanged models' BIC minus the final's: A->B -13, D->G +4, D->H -20 with H at 2 SE. Made: A->B, and
    the others say why not; with A->B at -5 it is still made, but ambiguous (within 10); at -0.5 it is a
    tie and nothing is swapped."""
    a, b, c = _refit("A"), _refit("B"), _refit("C", passes=False)
    d, g, h = _refit("D"), _refit("G"), _refit("H")
    e, f = _refit("E"), _refit("F")
    rounds = [_round(1, a, b, c, _refit("D")), _round(2, d, g, h), _round(3, e, f)]
    names = ["k_s", "p:A", "p:D", "p:E"]
    final_fit = SimpleNamespace(x=np.array([1.0, 2.0, 3.0, 4.0]), bic=lambda: 100.0, failed_rows=1)
    final = SimpleNamespace(fit=final_fit, model=SimpleNamespace(layout=SimpleNamespace(index=names.index)))
    cal = SimpleNamespace(rounds=rounds, final=final, out=tmp_path, exp=SimpleNamespace(netlist=RIG))
    outcome = {"p:B": (87.0, 5.0, 1.0), "p:G": (104.0, 5.0, 1.0), "p:H": (80.0, 2.0, 1.0)}  # BIC, phi, se
    failing = {}  # rows failing at an exchanged model's end (the final model: 1)
    seen = []

    def fit_stage(netlist, globals_, x_prev, prev_model):
        new = [g.name for g in globals_]
        seen.append(new)
        (put_in,) = [n for n in new if n in outcome]
        bic, phi, se = outcome[put_in]
        x = np.zeros(len(new))
        x[new.index(put_in)] = phi
        se_all = np.full(len(new), se)
        rows = failing.get(put_in, 1)
        return SimpleNamespace(model=SimpleNamespace(layout=SimpleNamespace(index=new.index)),
                               fit=SimpleNamespace(x=x, se=se_all, bic=lambda: bic,
                                                   run_failure=lambda beyond: f"{rows} fail" if rows > beyond else ""))

    globals_ = [Free(n, 0.0, -1.0, 1.0, 1.0, "") for n in names]
    tried = try_exchanges(cal, globals_, fit_stage)
    assert [(ex.out_key, ex.in_key) for ex in tried] == [("A", "B"), ("D", "G"), ("D", "H")]
    assert seen[0] == ["k_s", "p:D", "p:E", "p:B"]  # A's parameter out, B's in, the rest kept
    made = [ex for ex in tried if ex.made]
    assert [(ex.out_key, ex.in_key, ex.dbic) for ex in made] == [("A", "B", -13.0)] and made[0].ambiguous is False
    reasons = {ex.in_key: ex.reasons for ex in tried}
    assert reasons["B"] == [] and reasons["G"] == ["BIC +4: not lower than the final model's by over 1"]
    assert reasons["H"] == ["|phi| = 2 SE (needs > 3)"]
    outcome["p:B"] = (95.0, 5.0, 1.0)
    (made,) = [ex for ex in try_exchanges(cal, globals_, fit_stage) if ex.made]
    assert (made.in_key, made.dbic, made.ambiguous) == ("B", -5.0, True)
    outcome["p:B"] = (99.5, 5.0, 1.0)  # a tie (two places that act alike): nothing is swapped
    assert not any(ex.made for ex in try_exchanges(cal, globals_, fit_stage))
    outcome["p:B"], failing["p:B"] = (87.0, 5.0, 1.0), 3  # better by BIC, but runs fail that the final's do not
    tried = try_exchanges(cal, globals_, fit_stage)
    assert not any(ex.made for ex in tried) and tried[0].reasons == ["3 fail"]


def test_nothing_is_tried_with_fewer_than_two_effects(tmp_path):
    a = _refit("A")
    cal = SimpleNamespace(rounds=[_round(1, a, _refit("B")), _round(2, None)], final=SimpleNamespace(), out=tmp_path)
    assert try_exchanges(cal, [], lambda *args: None) == []
