"""The levels of a command profile that a time series's samples read (latent inputs of a time series).

A level of a profile (``values: [0, u1, u1, u2, ...]``) is in force between breakpoint times; a sample
reads it when the profile at the sample's time changes with it. A level no sample reads is fixed by
nothing in the data: blocks.calibrate.run does not fit one in force only after a run's last sample, and
blocks.calibrate.heldout holds one its held-out run's input samples do not read.
"""

from __future__ import annotations

import numpy as np


def level_read(table, over: dict, name: str, times: np.ndarray, until: float | None = None) -> bool:
    """Whether some sample time reads the command level ``name``: a profile whose values read it gives
    another value at one of ``times`` when the level moves by 1 (with ``until``: at any time up to it, the
    profile's breakpoints there included, so also between samples). A level read by any other signal block
    (a constant's value) is read at every time."""
    base = table.evaluate(over)
    moved = table.evaluate(dict(over, **{name: float(base[name]) + 1.0}))
    for reader, _items in table.readers(name):
        breakpoints = base.get(reader.name.rsplit(".", 1)[0] + ".times") if reader.elements is not None else None
        if breakpoints is None:
            return True
        t = np.asarray(breakpoints, dtype=float)
        if until is not None:  # piecewise linear: equal at every breakpoint up to ``until`` is equal throughout
            times = np.concatenate([times, t[t <= until], [0.0, until]])
        if np.any(np.interp(times, t, np.asarray(base[reader.name], dtype=float))
                  != np.interp(times, t, np.asarray(moved[reader.name], dtype=float))):
            return True
    return False
