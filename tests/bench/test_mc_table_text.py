"""Sentences of the Monte Carlo table that are computed from the records (bench/calibrate_mc.py) say what the
records hold: sizes named as the sizes they were measured at, counts with their own plural."""

import json

from tests.bench.test_mc_table_guard import _bench


def _write(path, records):
    path.write_text("".join(json.dumps(r) + "\n" for r in records))


def test_recorded_sizes_name_the_size_each_lambda_was_measured_at(tmp_path, monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    key = "viscous_friction@shaft"
    resized = {"case": "time_viscous", "seed": 1, "planted": {key: 0.0022}, "lambda": {key: 107.0},
               "lambda_levels": {key: 100.4}}
    kept = {"case": "time_coulomb", "seed": 1, "planted": {"coulomb_friction@shaft": 0.166},
            "lambda": {"coulomb_friction@shaft": 101.4}, "lambda_levels": {"coulomb_friction@shaft": 106.1}}
    first_table = [{"case": "time_viscous", "seed": 1, "planted": {key: 0.00208}},
                   {"case": "time_coulomb", "seed": 1, "planted": {"coulomb_friction@shaft": 0.166}}]
    _write(tmp_path / "results.jsonl", first_table)
    text = mc._recorded_sizes([resized, kept])
    assert "`time_viscous` 0.00208 (lambda 100 with the levels) -> 0.0022 (lambda 107 with the recording)" in text
    assert "`time_coulomb` 0.166 (lambda 106 with the levels) kept (lambda 101 with the recording)" in text


def _seed(case, first_best, best, ambiguous):
    """A record whose round's best by BIC was ``first_best`` from the first starts and ``best`` after them."""
    refits = [{"key": first_best, "dbic": -88.3, "dbic_first_start": -88.3, "starts": 3},
              {"key": best, "dbic": -89.8, "dbic_first_start": -85.8, "starts": 3}]
    return {"case": case, "seed": 1, "fit": "restarts", "rounds": [{"refits": refits, "ambiguous": ambiguous}]}


def test_restarts_count_seeds_in_the_singular_and_say_whether_the_rerank_was_within_an_ambiguity(tmp_path,
                                                                                                monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    _write(tmp_path / "results_recorded.jsonl",
           [_seed("time_viscous", "line_loss_laminar@motors.a", "viscous_friction@shaft",
                  ["line_loss_laminar@motors.a"])])
    text = mc._restarts()
    assert "lowered a refit's chi^2 by over 1 in 1 seed (the recorded-command `time_viscous` 1)" in text
    assert ("changed a round's best by BIC by over 1 in 1 seed (the recorded-command `time_viscous` 1), 1 of them "
            "between places the round reports ambiguous with each other, and by 1 or less in no seed.") in text


def test_the_seeds_rerun_for_a_stuck_refit_are_compared_with_their_records_from_before(tmp_path, monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    (tmp_path / "archive").mkdir()

    def seed(k, dbic):
        return {"case": "time_leakage", "seed": k, "expect": "found", "accepted": ["leakage@A-B"], "found": [True],
                "recovered": [True], "chi2nu_after": 1.0, "heldout_ratio": 1.0, "unexplained": False,
                "planted": {"leakage@A-B": 4.5e-14}, "estimates": {"leakage@A-B": [4.5e-14, 4e-15]},
                "rounds": [{"refits": [{"key": "leakage@A-B", "dbic": -91.0},
                                       {"key": "line_loss_turbulent@refill_B.b", "dbic": dbic}]}]}

    _write(tmp_path / "archive" / "s13_results_before_retreat.jsonl", [seed(2, 6.8e9), seed(4, 6.8e9)])
    _write(tmp_path / "results.jsonl", [seed(2, 1.62), seed(3, -5.0), seed(4, 2.68e6)])
    text = mc._stuck_refits()
    assert "rerun with it: `time_leakage` 2, 4. Against their records from before it (the same 2 seeds;" in text
    assert text.endswith("the accepted effects changed in 0 seeds, and no column's count changed; the 2 refits "
                         "whose dBIC moved by over 1 had dBIC 6.8e+09 before and 1.62 to 2.68e+06 now.")
