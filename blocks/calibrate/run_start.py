"""Whether a time series's run starts off the data: the model's state when its samples begin is not the machine's.

Every run of a time series is simulated from the netlist's start (``simulation: t_start``) with the netlist's
initial values (rest, unless written). Before a run's first sample its inputs are what the netlist gives
them: a recorded command (``latent: trace``) is held at its first sample, a profile gives its own levels. A
machine already moving, or a spool already open, when the recording began then starts the run off the
data, and the samples after it carry that error until the model forgets its start. The fit cannot say so
(it has no parameter for it) and no library effect explains it; this check names it.

The test, per output channel of each run: over some ``M = 3`` consecutive samples among the run's first
``W`` (5 % of the run, at least M, at most ``W_MAX = 25``) the mean of |r|/sigma is over ``Z_START = 5`` (for a
model at the noise such a mean passes 5 with a probability below 1e-11) and over ``WORSE = 2`` times the RMS of
r/sigma over the whole run (the start misses clearly worse than the run does: a model wrong throughout is
another matter, which the rest of the verdict reports). The window lets the misfit build: a position freed at
the start matches the first sample, and a wrong start speed shows a few samples later.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from blocks.calibrate.model import FAILED_RESIDUAL
from blocks.units import display_factor

M = 3
W_MAX = 25
Z_START = 5.0
WORSE = 2.0
LISTED = 8  # initial values named in the advice, at most


@dataclass
class StartMisfit:
    """A run whose first samples miss: the worst output channel there, its measured and simulated values at
    its worst sample among them (SI, at t_worst), and its mean |r|/sigma over the worst M consecutive samples
    against its RMS over the run."""

    run: str
    several_runs: bool
    t_first: float
    t_start: float
    channel: str
    unit: str
    measured: float
    simulated: float
    z_start: float
    z_run: float
    t_worst: float | None = None  # the sample the values are read at (None: the first)

    def line(self, initial_values: list[str]) -> str:
        f = display_factor(self.unit)
        unit = "" if self.unit in ("", "1", "SI") else f" {self.unit}"
        run = f"run '{self.run}'" if self.several_runs else "the run"
        first = self.t_worst is None or self.t_worst == self.t_first
        at = (f"at its first sample (t = {self.t_first:g} s)" if first else
              f"at t = {self.t_worst:g} s, soon after its first sample (t = {self.t_first:g} s),")
        said = (f"{run} starts off the data: {at} {self.channel} is "
                f"{self.measured / f:.4g}{unit} measured and {self.simulated / f:.4g}{unit} simulated "
                f"({self.z_start:.3g} sigma over {M} samples {'from the first' if first else 'there'}, against "
                f"{self.z_run:.3g} over the run): the model's state when the samples begin is not the machine's. ")
        if self.t_first > self.t_start + 1e-9:
            return said + (f"The simulation starts at {self.t_start:g} s, before the run's first sample, and the "
                           f"inputs in between are not measured (a recorded command is held at its first value): "
                           f"start the netlist at the run's first sample (simulation: t_start: {self.t_first:g} s"
                           + ("; the runs share the netlist: in an experiment of its own" if self.several_runs
                              else "") + ") and give or free the initial values there")
        names = ", ".join(initial_values[:LISTED]) + (", ..." if len(initial_values) > LISTED else "")
        shared = " (each run its own: per: group)" if self.several_runs else ""
        return said + (f"If the machine was moving or loaded when the recording began, give the netlist's initial "
                       f"values or free them{shared}" + (f": {names}" if names else ""))


def start_misfits(stage) -> list[StartMisfit]:
    """The runs of a time-series fit (``stage``: a blocks.calibrate.run.Stage) whose first samples miss (the
    module's test), each by its worst output channel there; none for steady points."""
    model, fit = stage.model, stage.fit
    data = model.data
    if data.kind != "time":
        return []
    n, found = data.n, []
    for label, idx in model.runs.items():
        worst = None
        for c, ch in enumerate(model.channels):
            if ch.role != "output":
                continue
            r = fit.r[c * n + idx]
            if r.size <= M or np.any(r == FAILED_RESIDUAL):  # a failed run holds a penalty, not a misfit
                continue
            window = np.abs(r[:min(max(M, r.size // 20), W_MAX)])
            means = np.convolve(window, np.ones(M) / M, mode="valid")  # each M consecutive samples' mean
            k = int(np.argmax(means))
            z_start = float(means[k])
            z_run = float(np.sqrt(np.mean(r ** 2)))
            if z_start > Z_START and z_start > WORSE * z_run and (worst is None or z_start > worst.z_start):
                j = k + int(np.argmax(window[k:k + M]))  # the worst sample of those M
                row = c * n + idx[j]
                measured = float(model.measured[row])
                worst = StartMisfit(str(label), len(model.runs) > 1, float(data.t[idx[0]]),
                                    float(model.settings.t_start), ch.name, ch.unit, measured,
                                    measured + float(r[j]) * float(model.row_sigma[row]), z_start, z_run,
                                    float(data.t[idx[j]]))
        if worst is not None:
            found.append(worst)
    return found


def initial_values(stage) -> list[str]:
    """The netlist's initial values (the nets' and the blocks' states' start values), by qualified name."""
    return [n for n in stage.model.circuit.parameter_names if n.endswith(".initial") or ".initial." in n]
