"""bench/rerun_seeds.py: what a rerun is compared with (the seed's latest rerun, else its record), and a
seed with nothing to compare with refused before anything runs."""

import importlib.util
import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def rerun(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT / "bench"))
    spec = importlib.util.spec_from_file_location("rerun_seeds", ROOT / "bench" / "rerun_seeds.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    monkeypatch.setattr(module.mc, "RECORDS", tmp_path)
    (tmp_path / "archive").mkdir()
    return module


def _record(case: str, seed: int, chi2nu: float, **extra) -> dict:
    return {"case": case, "seed": seed, "accepted": ["a"], "found": [True], "recovered": [True],
            "unexplained": False, "chi2nu_after": chi2nu, "heldout_ratio": 1.0, "estimates": {"a": [1.0, 0.1]},
            "seconds": 5.0, **extra}


def _archive(path: Path, rows: list[dict]) -> None:
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))


def test_the_latest_rerun_of_the_seed_in_the_same_records_file_is_the_reference(rerun, tmp_path, monkeypatch):
    """Two archives hold seed 1 of steady_two; the one listed last in RERUNS wins. Seed 2, in no archive,
    and seed 1 of the 60-point file (another records file) are compared with their records."""
    def row(file, seed, chi2nu):
        return {"file": file, "case": "steady_two", "seed": seed, "before": {}, "after": {"chi2nu_after": chi2nu}}

    _archive(tmp_path / "archive" / "old.jsonl", [row("results.jsonl", 1, 0.5)])
    _archive(tmp_path / "archive" / "new.jsonl", [row("results.jsonl", 1, 0.6), row("results.jsonl", 3, 0.7)])
    monkeypatch.setattr(rerun.mc, "RERUNS", (("old.jsonl", ""), ("new.jsonl", "")))
    assert rerun.latest("results.jsonl", _record("steady_two", 1, 0.4)) == ({"chi2nu_after": 0.6}, "new.jsonl")
    before, source = rerun.latest("results.jsonl", _record("steady_two", 2, 0.4))
    assert source == "record" and before["chi2nu_after"] == 0.4 and "seconds" not in before
    assert rerun.latest("results_flows20.jsonl", _record("steady_two", 1, 0.4))[1] == "record"


def test_a_seed_without_a_record_is_refused_before_any_run(rerun, tmp_path, monkeypatch, capsys):
    """Seed 1 has a record, seed 2's record is an error, seed 3 has none: exit 2, naming 2 and 3, no run
    started and no archive written."""
    records = [_record("steady_none", 1, 0.7, planted={}, **{"lambda": None}),
               {"case": "steady_none", "seed": 2, "error": "RuntimeError: x"}]
    monkeypatch.setattr(rerun.mc, "load_results", lambda: records)
    monkeypatch.setattr(rerun.mc, "_worker", lambda job: pytest.fail("a run was started"))
    assert rerun.main(["s.jsonl", "--cases", "steady_none", "--seeds", "1", "2", "3"]) == 2
    err = capsys.readouterr().err
    assert "steady_none seed 2" in err and "steady_none seed 3" in err and "seed 1" not in err
    assert not (tmp_path / "archive" / "s.jsonl").exists()


@pytest.mark.parametrize("argv", [["../x.jsonl", "--cases", "steady_none", "--seeds", "1"],
                                  ["x.json", "--cases", "steady_none", "--seeds", "1"],
                                  ["x.jsonl", "--cases", "steady_nope", "--seeds", "1"]])
def test_a_bad_archive_name_or_case_is_a_usage_error(rerun, argv, capsys):
    with pytest.raises(SystemExit) as stop:
        rerun.main(argv)
    assert stop.value.code == 2 and capsys.readouterr().err.count("error:") == 1


def test_a_seed_archived_from_another_records_file_is_still_rerun(rerun, monkeypatch):
    """The archive holds seed 1 of steady_none from results.jsonl (the 21-point rows); with --flows 20 the
    same case and seed are another record (results_flows20.jsonl) and must be rerun; seed 2 from the same
    file as the archive's is skipped. (The first version keyed the archive by case and seed alone and
    planned 0 reruns here.)"""
    rerun.mc.configure(20, False)
    monkeypatch.setattr(rerun.mc, "load_results", lambda: [_record("steady_none", k, 0.7, planted={},
                                                                   **{"lambda": None}) for k in (1, 2)])
    archived = [{"file": "results.jsonl", "case": "steady_none", "seed": 1},
                {"file": "results_flows20.jsonl", "case": "steady_none", "seed": 2}]
    try:
        jobs, missing = rerun.plan(["steady_none"], [1, 2], archived)
    finally:
        rerun.mc.configure(None, False)
    assert missing == [] and [(name, seed) for name, seed, _sizes, _record in jobs] == [("steady_none", 1)]


def test_changes_between_equivalent_places_are_explained_and_any_other_change_is_not(rerun):
    def moved(before, after):
        return {"before": {"accepted": before}, "after": {"accepted": after}}

    port = moved(["line_loss_turbulent@motors.b"], ["line_loss_turbulent@motors.a"])
    delay = moved(["transport_delay@xs"], ["transport_delay@u"])
    other = moved(["flow_force@relief"], ["leakage@R-V"])
    text = rerun.mc._why_moved([port, delay])
    assert rerun.mc.PORT_SIDES in text and rerun.mc.DELAY_SIDES in text
    assert rerun.mc._why_moved([port]) == f" (each between the two ports of one element: {rerun.mc.PORT_SIDES})"
    assert rerun.mc._why_moved([delay]) == f" ({rerun.mc.DELAY_SIDES})"
    assert rerun.mc._why_moved([port, other]) == (" (the losses that moved between the two ports of one element: "
                                                   f"{rerun.mc.PORT_SIDES})")
    assert rerun.mc._why_moved([other]) == "" and rerun.mc._why_moved([]) == ""


def test_a_records_file_whose_rows_moved_far_more_is_said_apart(rerun, monkeypatch):
    """chi^2/nu moved 1e-6 in the first table's rows and 1e-3 in the recorded-command rows (over 100 times
    more): each group gets its own maxima; when they moved alike, one sentence covers them."""
    def row(file, case, moved):
        side = {"accepted": [], "found": [], "unexplained": False, "heldout_ratio": 1.0, "estimates": {}}
        return {"file": file, "case": case, "seed": 1, "before": {**side, "chi2nu_after": 1.0},
                "after": {**side, "chi2nu_after": 1.0 + moved}}

    rows = [row("results.jsonl", "time_none", 1e-6), row("results_recorded.jsonl", "time_none", 1e-3)]
    monkeypatch.setattr(rerun.mc, "_archived", lambda name: rows)
    text = rerun.mc._rerun_paragraph("x.jsonl", "Intro.")
    assert "the first table's rows: chi^2/nu moved by at most 1e-06" in text
    assert "the recorded-command rows: chi^2/nu moved by at most 0.001" in text
    rows[1] = row("results_recorded.jsonl", "time_none", 2e-6)
    text = rerun.mc._rerun_paragraph("x.jsonl", "Intro.")
    assert "; chi^2/nu moved by at most 2e-06," in text and "recorded-command rows:" not in text
