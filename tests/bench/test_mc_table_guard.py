"""The Monte Carlo table is written from its per-seed records; a checkout or a run that lacks some records
must not replace the committed rows of those cases by nothing (bench/calibrate_mc.py: would_lose)."""

import importlib.util
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _bench():
    spec = importlib.util.spec_from_file_location("calibrate_mc", ROOT / "bench" / "calibrate_mc.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


COMMITTED = """# table
| case | planted | lambda | seeds | pass |
|---|---|---|---|---|
| steady_none | none | - | 2 | PASS |
| steady_two | two | 106 | 1 | FAIL |

Per-seed records: bench/records/results.jsonl. Rerun: ...

## MCV

What the held-out criterion asks of the right model: ...

| case | planted | lambda | seeds | pass |
|---|---|---|---|---|
| mcv_none | none | - | 1 | PASS |

Records: out/calibrate_mc/results_mcv.jsonl. Rerun: ...
"""


def _write(path: Path, cases):
    path.write_text("".join(json.dumps({"case": c, "seed": k}) + "\n" for k, c in enumerate(cases)))


def test_nothing_lost_when_every_row_has_its_seeds(tmp_path, monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    _write(tmp_path / "results.jsonl", ["steady_none", "steady_none", "steady_two"])
    _write(tmp_path / "results_mcv.jsonl", ["mcv_none"])
    (tmp_path / "heldout_expected_results_mcv.json").write_text("[]")
    assert mc.would_lose(COMMITTED) == []


def test_a_missing_file_a_missing_case_fewer_seeds_and_the_heldout_file_are_named(tmp_path, monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    _write(tmp_path / "results.jsonl", ["steady_none"])
    assert mc.would_lose(COMMITTED) == ["results.jsonl: steady_none (1 of 2 seeds), steady_two (0 of 1 seeds)",
                                        "results_mcv.jsonl: mcv_none (0 of 1 seeds)",
                                        "heldout_expected_results_mcv.json (run bench/heldout_expected.py)"]


def test_a_seed_that_failed_does_not_count(tmp_path, monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    (tmp_path / "results.jsonl").write_text(
        "".join(json.dumps(r) + "\n" for r in ({"case": "steady_none", "seed": 1}, {"case": "steady_two", "seed": 1},
                                               {"case": "steady_none", "seed": 2, "error": "ValueError: x"})))
    assert mc.would_lose(COMMITTED)[0] == "results.jsonl: steady_none (1 of 2 seeds)"


def test_the_table_is_left_untouched(tmp_path, monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    table = tmp_path / "table.md"
    table.write_text(COMMITTED)
    monkeypatch.setattr(mc, "TABLE", table)
    monkeypatch.setattr(mc, "OUT", tmp_path / "out")
    assert mc.write_table() is False
    assert table.read_text() == COMMITTED
    assert (tmp_path / "out" / "table_partial.md").exists()


def test_a_run_whose_table_is_refused_exits_non_zero(tmp_path, monkeypatch, capsys):
    """A run that leaves the table unwritten says so and exits 2, so a script does not take the committed
    table for the run's (here every asked-for seed is already recorded, so the run is the table step alone)."""
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    monkeypatch.setattr(mc, "MCV_RESULTS", tmp_path / "results_mcv.jsonl")
    table = tmp_path / "table.md"
    table.write_text(COMMITTED)
    monkeypatch.setattr(mc, "TABLE", table)
    monkeypatch.setattr(mc, "OUT", tmp_path / "out")
    (tmp_path / "results_mcv.jsonl").write_text(  # its seed 0 (failed): nothing left to run
        json.dumps({"case": "mcv_none", "seed": 0, "error": "ValueError: x"}) + "\n")
    assert mc.main(["--cases", "mcv_none", "--seeds", "1", "--first-seed", "0"]) == 2
    err = capsys.readouterr().err
    assert "not writing" in err and "the table was not rewritten" in err
    assert table.read_text() == COMMITTED
