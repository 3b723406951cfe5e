"""Predictions of every measured channel by simulation, normalised residuals and their finite-difference
Jacobian, for a parameter vector x. Calibration only swaps parameters (``Circuit.simulate(overrides)``)
and reads the logged signals: it never reaches into the solver or the blocks.

The parameter vector
--------------------
x = [globals..., latent inputs of the steady points]. Globals are the declared free parameters, accepted
or screened candidate parameters, sensor corrections (``offset:<channel>``, ``gain:<channel>``) and, for a
time series, the latent levels of the imposed input (netlist parameters of its command profile) or the
knots of its latent trace (``latent: trace``: the profile that reads the recorded column gets, in place
of the recording, the knots' times and values as its breakpoints; see :mod:`blocks.calibrate.latent_trace`).
A declared parameter fitted per group (``per: group``) is one global per group, ``<name>[<group>]``, which
sets ``<name>`` for that group's points or run only. Steady points carry one latent value per imposed input
and point: the true input, of which the measured column is a noisy reading (errors-in-variables).

Residuals (normalised by each channel's noise sigma):
    output channel c, point or sample k:  r = (g_c*y_c(x, k) + o_c - y_meas) / sigma_c,  g_c = 1 + gain:c
    steady input channel i, point k:       r = (g_i*u_true(k, i) + o_i - u_meas) / sigma_i
    time-series input channel i, sample k: r = (g_i*u_sim(x, t_k) + o_i - u_meas) / sigma_i
so chi^2 = r.r is the errors-in-variables likelihood (the true inputs are fitted with the parameters, and the
inputs' noise counts as much as the outputs'). Sensor corrections are applied here, to the logged signal,
not in the netlist.

Steady points: a point's outputs are those of the circuit at rest with the point's imposed inputs and group
values as parameters. With ``steady.method: equilibrium`` (the default) that is the equilibrium f(x) = 0 of
the circuit, found by Newton (:meth:`Circuit.equilibrium`): at the point's first evaluation in a model a
settling run (``simulation.t_end`` of the netlist or ``steady.t_end``) shows which equilibrium the circuit
reaches from its initial state; Newton is started from the run's end and from a start moved 0.1 % off it,
and the equilibrium is used if both converge to the same state, it is stable (every eigenvalue of the Jacobian in
the left half-plane) and each compared output is within one sigma of the run's end (plus what the run still
moved over its last 20 %). That state is then the point's reference: every later evaluation in the model
starts Newton from it, so the outputs are a function of x alone, exact to the solver's tolerance (no
settling error for finite differences to amplify), and faster than a run: 12-21 times on the MCV rig's
21 points at its declared start (``python bench/steady_points.py``), more where runs are slower. An evaluation
whose Newton fails or ends on an unstable equilibrium falls back to the settling run (counted).
Points without a usable equilibrium (a family of equilibria such as a spool held anywhere in its friction
band, whose rest depends on the way there; a limit cycle) and ``method: settle`` use settling runs: the
outputs read at the end of the run; a point counts as settled when every compared signal moved less than
``settle_tol`` * sigma over the last 20 % of the run. A point not settled at its first evaluation in a
model is run again with its run doubled, up to ``steady.t_max`` (default 8 x t_end), and the length that
settled it is then fixed for that point in this model: every later evaluation (finite differences
included) reads the same run length, so the residual is a function of x alone, whatever was evaluated
before (an optimiser needs that). Points unsettled at their fixed length are counted and reported (never
silently used as if steady).
Time series: one run per group of the data (one without a grouping column), with the group's parameter
values and, with several runs, each run's own latent levels or latent trace knots (the profile that reads
the recording gets each run's knots as its breakpoints for that run); logged signals are interpolated
linearly onto the data's times, which must lie inside the simulated span.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from blocks.calibrate.data import Dataset
from blocks.calibrate.experiment import Experiment, Free
from blocks.errors import SimulationError, VphsError
from blocks.netlist.parameters import ParameterError

CACHE_BYTES = 256e6  # the simulated signals a model keeps for parameter vectors it meets again, at most
FAILED_RESIDUAL = 1e3
"""Normalised residual given to every row of a point whose simulation failed (or was refused)."""


@dataclass
class Layout:
    """Which entry of x is what."""

    globals: list[Free]
    n_points: int = 0
    inputs: list[str] = field(default_factory=list)  # steady input channels with latent values

    @property
    def n_globals(self) -> int:
        return len(self.globals)

    @property
    def size(self) -> int:
        return self.n_globals + self.n_points * len(self.inputs)

    def latent_index(self, point: int, k_input: int) -> int:
        return self.n_globals + point * len(self.inputs) + k_input

    def index(self, name: str) -> int:
        for k, f in enumerate(self.globals):
            if f.name == name:
                return k
        raise KeyError(name)

    def names(self) -> list[str]:
        out = [f.name for f in self.globals]
        for k in range(self.n_points):
            out += [f"{i}[{k}]" for i in self.inputs]
        return out


class Model:
    """Evaluates the residual vector of an experiment for parameter vectors x (see the module docstring)."""

    def __init__(self, circuit, exp: Experiment, data: Dataset, globals_: list[Free], fixed: dict | None = None):
        self.circuit, self.exp, self.data = circuit, exp, data
        self.fixed = dict(exp.overrides)
        self.fixed.update(fixed or {})
        steady_inputs = [c.name for c in exp.inputs if c.parameter is not None]
        if any(f.per_group for f in globals_):
            raise ValueError("a per: group parameter reaches the model unexpanded "
                             "(blocks.calibrate.run.per_group_globals makes its copies)")
        self.layout = Layout(list(globals_), data.n if data.kind == "steady" else 0, steady_inputs)
        self.names = circuit.parameter_names
        settings = circuit.settings
        changes = {}
        if exp.spec.solver.rtol is not None:
            changes["rtol"] = exp.spec.solver.rtol
        if exp.spec.solver.atol is not None:
            changes["atol"] = exp.spec.solver.atol
        self.t_max = settings.t_end
        if data.kind == "steady":
            from blocks.units import quantity

            if exp.spec.steady.t_end is not None:
                changes["t_end"] = quantity(exp.spec.steady.t_end, "s")
            t_end = changes.get("t_end", settings.t_end)
            changes["dt_out"] = (t_end - settings.t_start) / 10.0
            span = t_end - settings.t_start
            self.t_max = quantity(exp.spec.steady.t_max, "s") if exp.spec.steady.t_max is not None \
                else settings.t_start + 8.0 * span
            if self.t_max < t_end:
                raise VphsError(f"{exp.file}: steady.t_max = {self.t_max:g} s is shorter than the settling run "
                                f"({t_end:g} s)")
        # a fixed step's doubled-step check would cost every run half a run more: the final model alone is
        # checked (run_warnings)
        self.settings = settings.with_(fixed_step_check=False, **changes)
        self.runs = data.groups if data.kind == "time" else {}  # a time series: its runs (one unless grouped)
        for label, idx in self.runs.items():
            self._check_span(label, idx)
        # residual rows: channel-major, one row per point (or sample) per channel
        self.channels = list(exp.channels)
        n = data.n
        self.row_channel = np.repeat(np.arange(len(self.channels)), n)
        self.row_point = np.tile(np.arange(n), len(self.channels))
        self.n_rows = n * len(self.channels)
        self.sigma = np.array([data.sigma[c.name] for c in self.channels])
        self.measured = np.concatenate([data.measured[c.name] for c in self.channels])
        self.row_sigma = np.repeat(self.sigma, n)
        self.signal_index = {o.name: k for k, o in enumerate(circuit.outputs)}
        self.traces = self._traces(globals_)
        self._cache: dict = {}
        self._cache_bytes = 0
        self.unsettled: set[int] = set()
        self.run_end: dict[int, float] = {}  # steady point -> the end time of its lengthened settling run
        self._length_fixed: set[int] = set()  # steady points whose run length is decided
        self.method = exp.spec.steady.method
        self.reference: dict[int, np.ndarray] = {}  # steady point -> the equilibrium state Newton starts from
        self.reference_time: dict[int, float] = {}
        self.failures: list[str] = []
        self.simulations = 0
        self.equilibria = 0  # Newton solves
        self.fallbacks = 0  # evaluations of a point with a reference equilibrium that fell back to a run

    def _check_span(self, label: str, idx: np.ndarray) -> None:
        """A run's samples must lie inside the simulated span: the error names the first sample outside it by
        its file and line (a run of several files is its file, named by its stem)."""
        from blocks.datafile import read_table

        t, t0, t1 = self.data.t[idx], self.settings.t_start, self.settings.t_end
        outside = np.nonzero((t < t0 - 1e-12) | (t > t1 + 1e-12))[0]
        if outside.size == 0:
            return
        k = int(outside[0])
        message = (f"t = {t[k]:g} s lies outside the simulated span {t0:g} ... {t1:g} s of {self.exp.spec.netlist} "
                   f"(the run's times: {t[0]:g} ... {t[-1]:g} s); set the netlist's simulation: t_start and t_end "
                   f"to cover the data, or cut the data to the span")
        files = self.exp.data_files
        if len(files) <= 1:
            raise self.data.table.error(message, "t", int(idx[k]))
        file = next(f for f in files if label in (Path(f).stem, str(f)))
        raise read_table(file).error(message, "t", k)

    # ---- the parameter vector -------------------------------------------------------------------------
    def initial(self) -> np.ndarray:
        x = np.empty(self.layout.size)
        for k, f in enumerate(self.layout.globals):
            x[k] = f.initial
        for k in range(self.layout.n_points):
            for i, name in enumerate(self.layout.inputs):
                x[self.layout.latent_index(k, i)] = self.data.measured[name][k]
        return x

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        lo = np.full(self.layout.size, -np.inf)
        hi = np.full(self.layout.size, np.inf)
        for k, f in enumerate(self.layout.globals):
            lo[k], hi[k] = f.lower, f.upper
        return lo, hi

    def steps(self) -> np.ndarray:
        h = np.empty(self.layout.size)
        for k, f in enumerate(self.layout.globals):
            h[k] = f.step
        for k in range(self.layout.n_points):
            for i, name in enumerate(self.layout.inputs):
                h[self.layout.latent_index(k, i)] = 0.1 * self.data.sigma[name]
        return h

    def rows_of_points(self, points) -> np.ndarray:
        """Boolean mask of the residual rows of the given points (or samples)."""
        mask = np.zeros(self.n_rows, dtype=bool)
        sel = np.zeros(self.data.n, dtype=bool)
        sel[np.asarray(points, dtype=int)] = True
        mask[sel[self.row_point]] = True
        return mask

    def output_rows(self) -> np.ndarray:
        roles = np.array([c.role == "output" for c in self.channels])
        return roles[self.row_channel]

    # ---- overrides and simulation ---------------------------------------------------------------------
    def _traces(self, globals_: list[Free]) -> dict:
        """Latent traces: (profile, run) -> (x indices of its knot values, of its knot times (-1: fixed), the
        fixed times, the length of the profile's arrays), for :meth:`_trace_overrides`; run None for a series
        of one run, else each run's own knots."""
        knots: dict = {}
        for k, f in enumerate(globals_):
            if f.kind in ("trace", "trace_time"):
                param, label = f.name.split("[", 1)
                entry = knots.setdefault((param.rsplit(".", 1)[0], f.run), {}).setdefault(label, [-1, -1, f.at])
                entry[0 if f.kind == "trace" else 1] = k
        if not knots:
            return {}
        values = self.circuit.flat.parameters.evaluate(self.fixed)
        out = {}
        for (profile, run), members in knots.items():
            table = np.array([(v, t, np.nan if at is None else at) for v, t, at in members.values()])
            out[profile, run] = (table[:, 0].astype(int), table[:, 1].astype(int), table[:, 2],
                                 len(values[f"{profile}.times"]))
        return out

    def trace_knots(self, x: np.ndarray) -> dict:
        """Latent traces at x: (profile, run) -> (knot times s, knot values SI), in time order (run None: a
        series of one run)."""
        return {key: (np.where(time_index >= 0, x[np.maximum(time_index, 0)], fixed_times), x[value_index])
                for key, (value_index, time_index, fixed_times, _) in self.traces.items()}

    def _trace_overrides(self, x: np.ndarray, run: str | None) -> dict:
        """The breakpoints of each profile that a latent trace of ``run`` drives: the spline's knots; the
        arrays keep their length, so the rest of the breakpoints hold the last value beyond the knots (1 s
        apart)."""
        over = {}
        for (profile, of_run), (times, values) in self.trace_knots(x).items():
            if of_run != run:
                continue
            beyond = np.arange(1.0, self.traces[profile, run][3] - len(times) + 1.0)
            over[f"{profile}.times"] = tuple(np.concatenate([times, times[-1] + beyond]))
            over[f"{profile}.values"] = tuple(np.concatenate([values, np.full(beyond.size, values[-1])]))
        return over

    def _net_overrides(self, x: np.ndarray) -> dict:
        over = dict(self.fixed)
        for k, f in enumerate(self.layout.globals):
            if f.kind not in ("correction", "trace", "trace_time") and f.run is None:
                over[f.name] = float(x[k])
        over.update(self._trace_overrides(x, None))
        return over

    def _corrections(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        gain = np.ones(len(self.channels))
        offset = np.zeros(len(self.channels))
        index = {c.name: k for k, c in enumerate(self.channels)}
        for ch, corr in self.exp.corrections.items():
            gain[index[ch]] += corr.get("gain", 0.0)
            offset[index[ch]] += corr.get("offset", 0.0)
        for k, f in enumerate(self.layout.globals):
            if f.kind == "correction":
                what, ch = f.name.split(":", 1)
                if what == "gain":
                    gain[index[ch]] += x[k]
                else:
                    offset[index[ch]] += x[k]
        return gain, offset

    def _run(self, overrides: dict, settings=None):
        self.simulations += 1
        return self.circuit.simulate(overrides, settings=settings or self.settings)

    def _settling_run(self, k: int, over: dict, lengthen: bool = True):
        """Point k's settling run: (end values, settled, result). At the point's first evaluation (and with
        ``lengthen``) a run that has not settled is lengthened (:meth:`_lengthened`) and its length fixed.
        Only the end and the 80 % point are read: ten output intervals keep a run one call of the compiled
        integrator (blocks/solve/run.py slices runs of 20 or more output times)."""
        first = lengthen and k not in self._length_fixed
        self._length_fixed.add(k)
        result = self._run_to(over, self.run_end.get(k, self.settings.t_end))
        if first:
            result = self._lengthened(k, over, result)
        return result.values[-1, :].copy(), self._settled(result), result

    def _run_to(self, over: dict, t_end: float):
        t0 = self.settings.t_start
        return self._run(over, self.settings.with_(t_end=t_end, dt_out=(t_end - t0) / 10.0))

    def _lengthened(self, k: int, over: dict, result):
        """Point k's run doubled while it has not settled, up to t_max; the length reached is kept in run_end."""
        t0 = self.settings.t_start
        while not self._settled(result) and result.t[-1] < self.t_max:
            t_end = min(t0 + 2.0 * (result.t[-1] - t0), self.t_max)
            self.run_end[k] = t_end
            result = self._run_to(over, t_end)
        return result

    def _settled(self, result) -> bool:
        return bool(self._motion(result).max(initial=0.0) <= self.exp.spec.steady.settle_tol)

    def _motion(self, result) -> np.ndarray:
        """How far each compared output moved over the last 20 % of a run, in its noise sigmas."""
        back = int(0.8 * (len(result.t) - 1))
        return np.array([abs(result.values[-1, self.signal_index[c.signal]]
                             - result.values[back, self.signal_index[c.signal]]) / self.data.sigma[c.name]
                         for c in self.channels if c.role == "output"])

    def _first_equilibrium(self, over: dict, result):
        """The equilibrium a point's first settling run is heading for, or None if there is no isolated,
        stable one it would reach. Newton is started from the run's end and again from that state moved by
        0.1 % of each state's size (signs alternating): both must converge to the same state (a family of
        equilibria, e.g. a friction state that rests anywhere in its stick band, gives two different ones;
        a state that acts on no other state is left out of the comparison: it may rest anywhere, see
        :mod:`blocks.solve.equilibrium`; what it does to the outputs is checked against the run),
        that state must be stable (every eigenvalue of the Jacobian with a negative real part), and each
        compared output must lie within one noise sigma of the run's end, plus however far the run still
        moved over its last 20 %."""
        t_eq = float(result.t[-1])
        nominal = self.circuit.nominal
        x_end = result.states[-1]
        end = self.circuit.equilibrium(over, guess=x_end, t=t_eq)
        self.equilibria += 1
        if not end.stable:
            return None
        signs = np.where(np.arange(len(x_end)) % 2 == 0, 1.0, -1.0)
        moved_start = end.states + 1e-3 * signs * np.maximum(np.abs(end.states), nominal)
        again = self.circuit.equilibrium(over, guess=moved_start, t=t_eq)
        self.equilibria += 1
        live = ~(end.sinks | again.sinks)  # acting on nothing, it may rest anywhere; the outputs are compared below
        if again.status != 0 or np.max(np.abs(end.states - again.states)[live] / nominal[live], initial=0.0) > 1e-6:
            return None
        outputs = [c for c in self.channels if c.role == "output"]
        for c, motion in zip(outputs, self._motion(result)):
            col = self.signal_index[c.signal]
            if abs(end.values[col] - result.values[-1, col]) > (1.0 + motion) * self.data.sigma[c.name]:
                return None
        return end

    def _steady_values(self, k: int, over: dict) -> tuple[np.ndarray, bool]:
        """The outputs of point k and whether they are steady (see the module docstring)."""
        if k in self.reference:
            eq = self.circuit.equilibrium(over, guess=self.reference[k], t=self.reference_time[k])
            self.equilibria += 1
            if eq.stable:
                return eq.values.copy(), True
            self.fallbacks += 1
            values, settled, _ = self._settling_run(k, over, lengthen=False)
            return values, settled
        if k not in self._length_fixed and self.method == "equilibrium":
            self._length_fixed.add(k)
            result = self._run_to(over, self.settings.t_end)
            eq = self._first_equilibrium(over, result)
            if eq is not None:
                self.reference[k], self.reference_time[k] = eq.states, float(result.t[-1])
                return eq.values.copy(), True
            result = self._lengthened(k, over, result)  # no equilibrium to use: the run, lengthened if need be
            return result.values[-1, :].copy(), self._settled(result)
        values, settled, _ = self._settling_run(k, over)
        return values, settled

    def _steady_point(self, k: int, x: np.ndarray, base: dict) -> np.ndarray | None:
        over = dict(base)
        over.update(self.exp.groups.get(self.data.labels[k], {}))
        over.update(self._group_values(x, self.data.labels[k]))
        for i, name in enumerate(self.layout.inputs):
            param = next(c.parameter for c in self.channels if c.name == name)
            over[param] = float(x[self.layout.latent_index(k, i)])
        key = (k, tuple(sorted(over.items())))
        if key in self._cache:
            return self._cache[key]
        try:
            values, settled = self._steady_values(k, over)
        except (SimulationError, ParameterError, VphsError) as exc:
            self.failures.append(f"point {k + 1}: {exc}")
            self._remember(key, None, 200_000)
            return None
        if not settled:
            self.unsettled.add(k)
        else:
            self.unsettled.discard(k)
        self._remember(key, values, 200_000)
        return values

    def _remember(self, key, value: np.ndarray | None, most: int) -> None:
        """Keep a point's or a run's signals under ``key``; the cache is emptied beyond ``most`` entries or
        CACHE_BYTES of arrays (a run's entry is samples x signals x 8 bytes: 100 s at 1 kHz of 5 signals is 4 MB,
        and 2000 of those would be 8 GB)."""
        self._cache[key] = value
        self._cache_bytes += 0 if value is None else value.nbytes
        if len(self._cache) > most or self._cache_bytes > CACHE_BYTES:
            self._cache.clear()
            self._cache_bytes = 0

    def signals(self, x: np.ndarray, points=None) -> np.ndarray:
        """Every logged signal (columns, SI) at every point or data sample (rows); NaN where a run failed."""
        base = self._net_overrides(x)
        n_sig = len(self.circuit.outputs)
        out = np.full((self.data.n, n_sig), np.nan)
        if self.data.kind == "steady":
            todo = range(self.data.n) if points is None else np.unique(np.asarray(points, dtype=int))
            for k in todo:
                values = self._steady_point(int(k), x, base)
                if values is not None:
                    out[k] = values
            return out
        for label, idx in self.runs.items():
            out[idx] = self._run_signals(label, self._run_overrides(label, base, x), idx)
        return out

    def _run_overrides(self, label: str, base: dict, x: np.ndarray) -> dict:
        """One run of a time series: the overrides of every run, its group's values, its latent levels and
        its latent traces' knots."""
        over = dict(base)
        over.update(self.exp.groups.get(label, {}))
        over.update(self._group_values(x, label))
        over.update(self._trace_overrides(x, label))
        return over

    def run_warnings(self, x: np.ndarray) -> list[str]:
        """Each run of a time series at ``x`` simulated again, ``solver: fixed`` with its doubled-step check
        (:mod:`blocks.solve.step_check`; the fits ran without it): what those runs warn of (a vapour cavity, a
        pressure beyond hydraulics, a fixed step too long), which the fits' runs do not say. [] for steady
        points: an equilibrium, and a run settled at it, do not depend on the step, and a settling run's
        transient is not the data's."""
        if self.data.kind != "time":
            return []
        base, lines = self._net_overrides(x), []
        for label in self.runs:
            try:
                result = self._run(self._run_overrides(label, base, x), self.settings.with_(fixed_step_check=True))
            except VphsError:  # a run that fails is the fit's to report
                continue
            lines += [w if len(self.runs) == 1 else f"run {label}: {w}" for w in result.warnings]
        return lines

    def _group_values(self, x: np.ndarray, label: str) -> dict:
        """The globals of one group (or run): its latent command levels and its values of the declared
        parameters fitted per group (``<name>[<group>]`` sets ``<name>``; a parameter's name holds no '[',
        a group's label may: a run file ``run[1].csv``)."""
        return {f.name.split("[", 1)[0]: float(x[k]) for k, f in enumerate(self.layout.globals)
                if f.run == label and f.kind in ("latent", "declared")}

    def _run_signals(self, label: str, over: dict, idx: np.ndarray) -> np.ndarray:
        """Every logged signal at the samples ``idx`` of run ``label``, simulated with ``over`` (cached)."""
        key = ("time", label, tuple(sorted(over.items())))
        if key in self._cache:
            return self._cache[key]
        out = np.full((idx.size, len(self.circuit.outputs)), np.nan)
        try:
            result = self._run(over)
        except (SimulationError, ParameterError, VphsError) as exc:
            self.failures.append(str(exc) if len(self.runs) == 1 else f"run {label}: {exc}")
            self._remember(key, out, 2000)
            return out
        for j in range(out.shape[1]):
            out[:, j] = np.interp(self.data.t[idx], result.t, result.values[:, j])
        self._remember(key, out, 2000)
        return out

    def predictions(self, x: np.ndarray, points=None) -> np.ndarray:
        """The predicted value of every residual row (SI, corrections applied); NaN where not computed."""
        sig = self.signals(x, points)
        gain, offset = self._corrections(x)
        pred = np.full(self.n_rows, np.nan)
        n = self.data.n
        for c_idx, c in enumerate(self.channels):
            rows = slice(c_idx * n, (c_idx + 1) * n)
            if c.role == "input" and c.parameter is not None:
                i = self.layout.inputs.index(c.name)
                raw = np.array([x[self.layout.latent_index(k, i)] for k in range(n)])
            else:
                raw = sig[:, self.signal_index[c.signal]]
            pred[rows] = gain[c_idx] * raw + offset[c_idx]
        if points is not None and self.data.kind == "steady":
            keep = self.rows_of_points(points)
            pred[~keep] = np.nan
        return pred

    def residuals(self, x: np.ndarray, points=None) -> np.ndarray:
        """Normalised residuals of every row; rows not computed (other points) are 0, failed runs large."""
        pred = self.predictions(x, points)
        r = (pred - self.measured) / self.row_sigma
        computed = np.ones(self.n_rows, dtype=bool) if points is None or self.data.kind != "steady" \
            else self.rows_of_points(points)
        r[computed & ~np.isfinite(r)] = FAILED_RESIDUAL
        r[~computed] = 0.0
        return r

    def jacobian(self, x: np.ndarray, cols, points=None, r0: np.ndarray | None = None) -> np.ndarray:
        """Forward-difference Jacobian d r / d x[cols] with the absolute steps of :meth:`steps` (backward
        where a bound is in the way). Latent inputs of different points are perturbed together: each point's
        rows depend on its own latent values only, so one sweep gives all of their columns."""
        cols = list(cols)
        if r0 is None:
            r0 = self.residuals(x, points)
        h = self.steps()
        lo, hi = self.bounds()
        J = np.zeros((self.n_rows, len(cols)))
        G = self.layout.n_globals
        latent_sweeps: dict[int, list[tuple[int, int]]] = {}
        for j, col in enumerate(cols):
            if col < G:
                step = h[col] if x[col] + h[col] <= hi[col] else -h[col]
                xp = x.copy()
                xp[col] += step
                J[:, j] = (self.residuals(xp, points) - r0) / step
            else:
                point, k_input = divmod(col - G, len(self.layout.inputs))
                latent_sweeps.setdefault(k_input, []).append((j, point))
        for k_input, members in latent_sweeps.items():
            xp = x.copy()
            for _, point in members:
                xp[self.layout.latent_index(point, k_input)] += h[self.layout.latent_index(point, k_input)]
            rp = self.residuals(xp, points)
            for j, point in members:
                rows = self.row_point == point
                step = h[self.layout.latent_index(point, k_input)]
                J[rows, j] = (rp[rows] - r0[rows]) / step
        return J

    def extend(self, x: np.ndarray, other: "Model", values: dict | None = None) -> np.ndarray:
        """x of this model carried over to ``other`` (same data): globals by name, latents as they are;
        globals new in ``other`` take ``values`` or their initial value."""
        values = values or {}
        y = other.initial()
        for k, f in enumerate(other.layout.globals):
            if f.name in values:
                y[k] = values[f.name]
            else:
                try:
                    y[k] = x[self.layout.index(f.name)]
                except KeyError:
                    pass
        y[other.layout.n_globals:] = x[self.layout.n_globals:]
        return y
