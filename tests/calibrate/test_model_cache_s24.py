"""A calibration model's cache of simulated signals is bounded in bytes as well as in entries
(blocks/calibrate/model.py, ``Model._remember``).

Found by the memory review (session 24): the cache was capped at 2000 runs whatever their size; a run of
100 s at 1 kHz with 5 signals is 4 MB, so a long time series could hold 8 GB before the cap emptied it.
"""

from __future__ import annotations

import numpy as np

import blocks.calibrate.model as model_module
from blocks.calibrate.model import Model


def _bare_model() -> Model:
    model = object.__new__(Model)  # the cache alone: no circuit, no data
    model._cache, model._cache_bytes = {}, 0
    return model


def test_the_cache_never_holds_more_than_its_bytes(monkeypatch):
    monkeypatch.setattr(model_module, "CACHE_BYTES", 1e6)
    model = _bare_model()
    run = np.zeros((1000, 5))  # 40 kB
    held = []
    for k in range(200):
        model._remember(("time", "run", k), run.copy(), 2000)
        held.append(sum(v.nbytes for v in model._cache.values() if v is not None))
    assert max(held) <= 1e6 and model._cache_bytes == held[-1]
    assert max(held) > 0.9e6  # it did fill up to the bound


def test_the_entry_count_still_bounds_small_entries():
    model = _bare_model()
    for k in range(30):
        model._remember((k,), None if k % 2 else np.zeros(3), 10)
        assert len(model._cache) <= 10
