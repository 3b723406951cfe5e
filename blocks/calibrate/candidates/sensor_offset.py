"""Sensor offset on a measured channel: y' = y + o, applied to the logged signal (post-processing)."""

import numpy as np

from blocks.calibrate.candidates.base import Candidate, Place, register
from blocks.units import parse_unit


@register
class SensorOffset(Candidate):
    name = "sensor_offset"
    title = "sensor offset"
    description = "a constant offset o of a measured channel, y' = y + o (on the logged signal, not in the netlist)"

    def places(self, ctx):
        out = []
        for ch in ctx.exp.channels:
            span = float(np.max(np.abs(ctx.data.measured[ch.name])))
            sigma = ctx.data.sigma[ch.name]
            limit = 0.05 * span + 3.0 * sigma
            out.append(Place(self.name, f"{self.name}@{ch.name}", f"channel {ch.name}", f"offset:{ch.name}",
                             ch.si_unit or "1", 0.0, -np.inf, np.inf, 0.1 * sigma, (-limit, limit), kind="channel",
                             target={"channel": ch.name}, one_sided=False, meaning="added to the logged signal",
                             plot_against=ch.name))
        return out

    def patch(self, doc, place):
        raise TypeError("a sensor offset patches the compared signal, not the netlist")


def shown(exp, key: str, value: float, unit: str) -> tuple[float, str]:
    """A value of the effect ``key`` as a report shows it: a sensor offset in its channel's unit (an offset of
    p1 in bar, of Q in l/min, as the data are), anything else as given (SI). JSON reports stay in SI."""
    candidate, _, where = key.partition("@")
    channel = next((c for c in exp.channels if c.name == where), None) if candidate == SensorOffset.name else None
    if channel is None or channel.unit in ("", "1"):
        return value, unit
    return value / parse_unit(channel.unit).factor, channel.unit


def range_text(exp, place) -> str:
    """'[-1.2, 1.2] bar': a candidate's plausible range as people read it, in the unit :func:`shown` gives
    (without an experiment, ``exp`` None: in SI)."""
    factor, unit = shown(exp, place.key, 1.0, place.unit) if exp is not None else (1.0, place.unit)
    lo, hi = (bound * factor for bound in place.plausible)
    return f"[{lo:.3g}, {hi:.3g}]" + ("" if unit in ("", "1", "SI") else f" {unit}")


def shown_text(exp, key: str, value: float, se: float, unit: str) -> str:
    """'0.5342 +- 0.13 bar': a fitted value of the effect ``key`` and its standard error (SI) as people read them
    (the console's progress, the verdict, a written netlist's header), in the unit the report shows it in
    (:func:`shown`: a sensor offset in its channel's unit, not 5.342e+04 Pa); no unit for a plain number."""
    factor, unit = shown(exp, key, 1.0, unit)
    return f"{value * factor:.4g} +- {se * factor:.2g}" + ("" if unit in ("", "1", "SI") else f" {unit}")
