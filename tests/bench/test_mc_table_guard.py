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
| case | planted | pass |
|---|---|---|
| steady_none | none | PASS |
| steady_two | two | FAIL |

Per-seed records: bench/records/results.jsonl. Rerun: ...

## MCV
| case | planted | pass |
|---|---|---|
| mcv_none | none | PASS |

Records: out/calibrate_mc/results_mcv.jsonl. Rerun: ...
"""


def _write(path: Path, cases):
    path.write_text("".join(json.dumps({"case": c, "seed": 1}) + "\n" for c in cases))


def test_nothing_lost_when_every_row_has_records(tmp_path, monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    _write(tmp_path / "results.jsonl", ["steady_none", "steady_two"])
    _write(tmp_path / "results_mcv.jsonl", ["mcv_none"])
    assert mc.would_lose(COMMITTED) == []


def test_a_missing_file_and_a_missing_case_are_named(tmp_path, monkeypatch):
    mc = _bench()
    monkeypatch.setattr(mc, "RECORDS", tmp_path)
    _write(tmp_path / "results.jsonl", ["steady_none"])
    assert mc.would_lose(COMMITTED) == ["results.jsonl: steady_two", "results_mcv.jsonl: mcv_none"]


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
