"""A compiled circuit: built once per netlist structure, evaluated for any parameter vector.

    circuit = Circuit.from_file("netlists/examples/drive_line.yaml")
    result = circuit.simulate({"ctrl.Kp": 4.0, "m_load": 15000.0})

The path is one straight line: YAML -> pydantic spec -> flat circuit (:mod:`blocks.netlist.flatten`) ->
structure and order (:mod:`blocks.compiler.structure`) -> generated, numba-compiled rhs
(:mod:`blocks.compiler.codegen`) + parameter vector -> stiff solver (:mod:`blocks.solve`) ->
:class:`~blocks.result.Result`. Optimisers and calibrators call :meth:`Circuit.simulate` with overrides
(named values in SI) and read the result; they never touch the solver or the blocks.
"""

from __future__ import annotations

import os
import re
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from blocks import interrupt
from blocks.block import Block, PortKind
from blocks.compiler.codegen import Generator, OutputExpr
from blocks.compiler.structure import Structure, analyse, cavitation, jacobian_pattern
from blocks.errors import SimulationError
from blocks.library.hydraulic.cavitation import cavity_volume
from blocks.netlist.flatten import FlatCircuit, flatten
from blocks.netlist.signal_dimensions import check_signal_dimensions
from blocks.netlist.yaml_source import shown_key
from blocks.result import Result, column_name_problem
from blocks.solve.run import nominal_vector
from blocks.solve.settings import SolverSettings, read_settings
from blocks.units import GENERIC, UnitError, parse_unit
from blocks.valid_ranges import monitors, parameter_warnings, range_warnings

P_BEYOND = 1e9  # Pa (10000 bar): a pressure no hydraulic circuit reaches (Circuit._beyond_hydraulics)


def cache_dir() -> Path:
    """Where generated modules and numba's compiled code are kept (``VPHS_CACHE_DIR`` overrides)."""
    env = os.environ.get("VPHS_CACHE_DIR")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "vphs"


@dataclass
class Vectors:
    theta: np.ndarray
    x0: np.ndarray
    values: dict


class Circuit:
    """A netlist compiled to a right-hand side over flat state and parameter vectors."""

    def __init__(self, flat: FlatCircuit, quiet: bool = True, compile: bool = True, regularised: bool = False):
        """Analyse, order and generate the circuit; ``compile=False`` stops before numba (``vphs validate``).
        ``regularised``: observe the blocks' regularised signals too (:mod:`blocks.regularisation`), which only
        a linearisation reads; a run or an optimiser's evaluation does not carry them at every sample."""
        self.flat = flat
        self.structure: Structure = analyse(flat)
        check_signal_dimensions(flat)
        self.generator = Generator(self.structure)
        self.outputs = self._resolve_outputs()
        self.regularised = regularised
        self.monitors = monitors(self, regularised)  # observed after the outputs (blocks.valid_ranges)
        self.settings: SolverSettings = read_settings(flat)
        self.pattern = jacobian_pattern(self.structure)
        self.nominal = nominal_vector(self)  # each state's nominal magnitude, SI (Newton's scale)
        self.groups, self.n_groups = _colour_columns(self.pattern)
        self._timed = [(name, comp.cls) for name, comp in flat.components.items()  # blocks with breakpoints
                       if comp.cls.breakpoints.__func__ is not Block.breakpoints.__func__]
        self.source = self.generator.source([OutputExpr(o.name, o.expr, o.unit) for o in self.outputs]
                                            + [OutputExpr(m.name, m.expr, m.unit) for m in self.monitors])
        self.module = None
        if compile:
            self.compile(quiet)

    def compile(self, quiet: bool = True) -> None:
        """Compile (or load from the disk cache) the generated right-hand side."""
        from blocks.solve.generated import build_module

        announce = None if quiet else lambda: print(
            "vphs: compiling the circuit (once per structure; cached afterwards)...", file=sys.stderr, flush=True)
        self.module = build_module(self.source, cache_dir(), Path(self.flat.file).stem, on_compile=announce)
        interrupt.check()  # a Ctrl-C during compilation that a ctypes callback printed and dropped

    @classmethod
    def from_file(cls, file: str | Path, quiet: bool = True, compile: bool = True,
                  regularised: bool = False) -> "Circuit":
        return cls(flatten(file), quiet=quiet, compile=compile, regularised=regularised)

    @property
    def n_observed(self) -> int:
        """The values ``observe`` writes: the logged outputs, then the checked signals and, in a circuit built
        to be linearised, the regularised ones (:attr:`monitors`)."""
        return len(self.outputs) + len(self.monitors)

    # ---- parameters -----------------------------------------------------------------------------------
    @property
    def parameter_names(self) -> list[str]:
        return list(self.flat.parameters.entries)

    def block_values(self, comp: str, values: dict) -> dict:
        """Block ``comp``'s parameters by their own names, from a run's evaluated ``values``."""
        return {p.name: values[f"{comp}.{p.name}"] for p in self.flat.components[comp].cls.params}

    def vectors(self, overrides: dict[str, float] | None = None) -> Vectors:
        """Evaluate the parameter table (with ``overrides``) into theta and the initial state x0."""
        st = self.structure
        values = self.flat.parameters.evaluate(overrides)
        theta = np.empty(st.theta_size)
        for name, (a, b) in st.theta_index.items():
            theta[a:b] = values[name]
        for net in st.net_state:
            if f"{net}.volume" in values and values[f"{net}.volume"] <= 0:
                entry = self.flat.parameters.entries[f"{net}.volume"]
                raise entry.error(f"net '{net}': volume must be positive, got {values[f'{net}.volume']:g} m^3")
        for comp_name, comp in self.flat.components.items():
            checked = self.block_values(comp_name, values)
            checked.update({f"initial.{s.name}": values.get(f"{comp_name}.initial.{s.name}", s.start)
                            for s in comp.cls.states if s.size is None})
            problem = comp.cls.check_values(checked)
            if problem:
                raise comp.source.error(comp.path + ("params",), f"{comp_name}: {problem}"
                                        + self._data_file_places(comp_name, problem))
        x0 = np.zeros(st.n_states)
        for net, slot in st.net_state.items():
            x0[slot.index] = values.get(f"{net}.initial", 0.0)
        for body in st.bodies:
            if body.state is None:
                continue
            given = [net for net in body.members if f"{net}.initial" in values]
            if len(given) > 1:
                entry = self.flat.parameters.entries[f"{given[1]}.initial"]
                raise entry.error(f"nets {', '.join(given)} move rigidly together; give the initial speed "
                                  f"on one of them only")
            if given:
                net = given[0]
                x0[body.state.index] = values[f"{net}.initial"] / self._ratio_value(body, net, values)
        for comp, slots in st.block_states.items():
            cls = self.flat.components[comp].cls
            for state in cls.states:
                slot = slots[state.name]
                x0[slot.index:slot.index + slot.size] = values.get(f"{comp}.initial.{state.name}", state.start)
        self._check_start_pressures(x0, values)
        return Vectors(theta, x0, values)

    def _check_start_pressures(self, x0: np.ndarray, values: dict) -> None:
        """Under the cavitation law, no net starts below the fluid's vapour pressure: such a start is a vapour
        cavity of 0.1 bar per litre, not a pressure (-5 bar in a 0.5 l net: 40 l of vapour, which a 30 l/min
        pump took 80 s to fill, while the run read -5 bar). Without the law (``cavitation: false``, the
        thesis's model) a pressure is the liquid's at any value, and a run below the vapour pressure is warned
        of, as before; a block's own pressure node keeps the liquid law either way."""
        if not cavitation(self.structure):
            return
        p_vap = values["fluid.vapour_pressure"]
        for net, slot in self.structure.net_state.items():
            start = x0[slot.index]
            if start < p_vap:
                raise self.flat.parameters.entries[f"{net}.initial"].error(
                    f"net '{net}' starts at {start / 1e5:.4g} bar, below the fluid's vapour pressure "
                    f"{p_vap / 1e5:.4g} bar (gauge): under the cavitation law that is a vapour cavity of "
                    f"{_volume_text(cavity_volume(start, p_vap))}, not a pressure; give one at or above it")

    def breakpoints(self, vec: Vectors) -> np.ndarray:
        """The times at which a block's output jumps or kinks in time (:meth:`Block.breakpoints`), sorted,
        each once, from the evaluated parameters: the solver lands a step on each."""
        times = [t for name, cls in self._timed
                 for t in cls.breakpoints(self.block_values(name, vec.values))]
        return np.unique(np.array(times, dtype=float))

    def _ratio_value(self, body, net, values) -> float:
        ratio = 1.0
        while True:
            parent, link, forward = body.members[net]
            if parent is None:
                return ratio
            cls = self.flat.components[link].cls
            from blocks.block import argument_names

            r = cls.ratio(**{a: values[f"{link}.{a}"] for a in argument_names(cls.ratio)})
            ratio = ratio * r if forward else ratio / r
            net = parent

    # ---- simulation -----------------------------------------------------------------------------------
    def simulate(self, overrides: dict[str, float] | None = None, settings: SolverSettings | None = None,
                 progress=None) -> Result:
        """Run the circuit; raise :class:`SimulationError` if the solver fails.

        ``progress(fraction, seconds)`` is called as the run advances, if given."""
        settings = settings or self.settings
        vec = self.vectors(overrides)
        if self.module is None:
            self.compile()
        from blocks.solve.run import solve, warm_up

        compiling = warm_up(self, vec, settings)  # the integrator's first compilation: not on the run's clock
        started = time.perf_counter()
        outcome = solve(self, vec, settings, progress)
        elapsed = time.perf_counter() - started
        result = Result(
            file=self.flat.file,
            t=outcome.t,
            names=[o.name for o in self.outputs],
            units=[o.unit for o in self.outputs],
            display_units=[o.display_unit for o in self.outputs],
            values=outcome.Y[:, :len(self.outputs)],
            states=outcome.X,
            state_names=[s.name for s in self.structure.states for _ in range(s.size)],
            stats=outcome.stats,
            seconds=elapsed,
            compile_seconds=compiling,
            warnings=self._cavitation(outcome, vec) + parameter_warnings(self, vec.values)
            + range_warnings(self, outcome.t, outcome.Y[:, len(self.outputs):], vec.values),
        )
        if outcome.status != 0:
            raise SimulationError(self._failure_message(outcome, vec)) from None
        beyond = self._beyond_hydraulics(outcome)
        if beyond and settings.solver == "fixed":
            raise SimulationError(f"{self.flat.file}: {beyond}: either the fixed step of {settings.fixed_step:g} s, "
                                  f"without error control, is too long for this circuit (shorten simulation."
                                  f"fixed_step, or run it with solver rodas to see), or the circuit cannot hold the "
                                  f"pressure (a closed volume driven with no relief valve?)")
        if beyond:
            result.warnings.append(f"{beyond}: check the circuit (a closed volume driven with no relief valve?)")
        if settings.solver == "fixed" and settings.fixed_step_check:
            from blocks.solve.step_check import doubled_step_warning

            result.step_check = doubled_step_warning(self, vec, settings, outcome)
            if result.step_check:
                result.warnings.append(result.step_check)
        return result

    def equilibrium(self, overrides: dict[str, float] | None = None, guess: np.ndarray | None = None,
                    t: float | None = None, tol: float = 1e-10, max_iter: int = 50) -> "Equilibrium":
        """The equilibrium f(t, x) = 0 nearest (in Newton's sense) to the state ``guess`` (default: the
        netlist's initial state), with inputs held at their values at ``t`` (default: the end of the
        simulation); see :mod:`blocks.solve.equilibrium`. Never raises for a failed solve: the status says
        it. Stability is judged from the Jacobian's eigenvalues (``growth`` = the largest real part, 1/s)."""
        vec = self.vectors(overrides)
        if self.module is None:
            self.compile()
        x_guess = np.array(vec.x0 if guess is None else guess, dtype=float)
        t_eq = self.settings.t_end if t is None else float(t)
        status, x, y, J, iterations, sinks, growth_sinks = self.module.equilibrium(
            x_guess, vec.theta, t_eq, self.nominal, float(tol), int(max_iter), self.n_observed)
        interrupt.check()
        sinks = np.array(sinks, dtype=bool)
        rest = ~sinks  # J is block triangular: each state that acts on nothing counts by its own slope
        growth = max(float(np.max(np.linalg.eigvals(J[np.ix_(rest, rest)]).real)) if rest.any() else -np.inf,
                     float(growth_sinks)) if status == 0 else float("nan")
        return Equilibrium(int(status), x, y[:len(self.outputs)], [o.name for o in self.outputs], growth,
                           int(iterations), sinks)

    def _pressures(self) -> list[tuple[str, object]]:
        """Every pressure state: the hydraulic nets' and the blocks' internal pressure nodes."""
        return list(self.structure.net_state.items()) + [
            (slot.name, slot) for slots in self.structure.block_states.values() for slot in slots.values()
            if slot.unit == "Pa" and slot.size == 1]

    def _pressure_name(self, net: str) -> str:
        return f"net '{net}'" if net in self.structure.net_state else f"the pressure {net}"

    def _beyond_hydraulics(self, outcome) -> str:
        """'' or what says the run left hydraulics: a pressure over P_BEYOND in magnitude at an output sample.
        No hydraulic machine comes near it (components are rated to some hundreds of bar, the oil's bulk modulus
        is some 15000 bar); such a value is an integration that went wrong (a fixed step too long) or a circuit
        that cannot hold (a closed volume driven with no relief)."""
        if not outcome.X.size:
            return ""
        peaks = [(float(np.max(np.abs(outcome.X[:, slot.index]))), net, slot) for net, slot in self._pressures()]
        peak, net, slot = max(peaks, key=lambda item: item[0], default=(0.0, None, None))
        if not peak > P_BEYOND:
            return ""
        k = int(np.argmax(np.abs(outcome.X[:, slot.index])))
        return (f"{self._pressure_name(net)} reached {outcome.X[k, slot.index] / 1e5:.3g} bar at t = "
                f"{outcome.t[k]:.4g} s, beyond any hydraulic pressure (over {P_BEYOND / 1e5:g} bar)")

    def _data_file_places(self, comp: str, problem: str) -> str:
        """For a check's message naming array elements (``times[2]``) read from a data file: where in that
        file each one is (`` (times[2] is ref.csv:5)``), else ''."""
        places = []
        for name, index in dict.fromkeys(re.findall(r"\b([A-Za-z_]\w*)\[(\d+)\]", problem)):
            entry = self.flat.parameters.entries.get(f"{comp}.{name}")
            place = entry.element_place(int(index)) if entry is not None else None
            if place:
                places.append(f"{name}[{index}] is {place}")
        return f" ({'; '.join(places)})" if places else ""

    def _cavitation(self, outcome, vec: Vectors) -> list[str]:
        """A line for each pressure state that fell below the vapour pressure. With the cavitation law on
        (blocks.library.hydraulic.cavitation) a net's is a vapour cavity, said with its largest size; a
        block's own pressure node, or any net with the law off, went into a tension oil cannot carry."""
        p_vap = vec.values["fluid.vapour_pressure"]
        modelled = cavitation(self.structure)
        found = []
        for net, slot in self._pressures():
            low = outcome.x_min[slot.index]
            if low < p_vap:
                column = outcome.X[:, slot.index]
                below = np.nonzero(column < p_vap)[0]
                when = f" first seen at t = {outcome.t[below[0]]:.4g} s" if below.size else " between output samples"
                if modelled and net in self.structure.net_state:
                    found.append(f"cavitation: {self._pressure_name(net)} reached the vapour pressure "
                                 f"{p_vap / 1e5:.3g} bar,{when}; a vapour cavity of up to "
                                 f"{_volume_text(cavity_volume(low, p_vap))} formed there (modelled: fluid "
                                 f"cavitation)")
                else:
                    found.append(f"cavitation: {self._pressure_name(net)} fell to {low / 1e5:.3g} bar, below the "
                                 f"vapour pressure {p_vap / 1e5:.3g} bar,{when}" + (
                                     "" if modelled else " (fluid cavitation: false, so that pressure is a "
                                     "tension the oil cannot carry)"))
        return found

    def _failure_message(self, outcome, vec: Vectors) -> str:
        why = {1: "the step size fell below its minimum", 2: "the maximum number of steps was reached",
               3: "a state or derivative became NaN or infinite"}.get(outcome.status, f"status {outcome.status}")
        msg = f"{self.flat.file}: the solver failed at t = {outcome.t_reached:.6g} s: {why}"
        if outcome.bad_index >= 0:
            slot = next(s for s in self.structure.states if s.index <= outcome.bad_index < s.index + s.size)
            owners = self._owners(slot)
            value = outcome.x_end[outcome.bad_index] if outcome.x_end is not None else float("nan")
            unit = f" {slot.unit}" if slot.unit not in ("1", "", "SI") else ""
            msg += f"; state {slot.name} = {value:.4g}{unit} ({owners})" + self._no_inertia(slot, vec)
        finite = outcome.x_end is not None and np.all(np.isfinite(outcome.x_end))
        if outcome.x_end is not None and not finite:
            bad = [s.name for s in self.structure.states
                   if not np.all(np.isfinite(outcome.x_end[s.index:s.index + s.size]))]
            msg += f"; non-finite states: {', '.join(bad[:8])}"
        return msg

    def _no_inertia(self, slot, vec: Vectors) -> str:
        """'' or what says a rigid body's speed had nothing to accelerate (:meth:`_inertia_holders`)."""
        body = self.structure.body_of.get(slot.owner) if slot.kind == "speed" else None
        if body is None or body.state is not slot:
            return ""
        holders = self._inertia_holders(body, vec)
        return (f"; nothing on it has inertia ({', '.join(f'{name} = 0' for name in holders)}): a rigid body "
                f"needs a mass or an inertia") if holders else ""

    def _inertia_holders(self, body, vec: Vectors) -> list[str]:
        """The parameters holding a rigid body's inertia when every one of them is 0, so that dw/dt =
        sum(tau)/0; else []. Every block storing on the body (an inertia, a mass, a motor's rotating group)
        must declare its inertia or mass as a parameter: said only when that is certain."""
        holders = []
        for net in body.members:
            for comp, port in self.flat.nets[net].ports:
                cls = self.flat.components[comp].cls
                if not any(p.name == port and p.stores for p in cls.ports):
                    continue
                found = [f"{comp}.{p.name}" for p in cls.params if p.unit in ("kg", "kg*m^2")]
                if not found:
                    return []  # a capacity computed some other way: not certain
                holders += found
        return holders if holders and all(vec.values[name] == 0.0 for name in holders) else []

    def check_inertia(self, overrides: dict[str, float] | None = None) -> None:
        """Raise the netlist's error, at the first of its parameters, for a rigid body with nothing to
        accelerate (every mass and inertia on it 0): bad input, said before any run."""
        vec = self.vectors(overrides)
        for body in self.structure.bodies:
            holders = self._inertia_holders(body, vec) if body.state is not None else []
            if holders:
                raise self.flat.parameters.entries[holders[0]].error(
                    f"{', '.join(f'{name} = 0' for name in holders)}: nothing on the rigid body "
                    f"{', '.join(sorted(body.members))} has inertia, and it needs a mass or an inertia")

    def _owners(self, slot) -> str:
        if slot.kind == "block":
            return f"block {slot.owner}"
        ports = self.flat.nets[slot.owner].ports
        blocks = sorted({c for c, _ in ports})
        return f"net {slot.owner}, joining {', '.join(blocks)}"

    # ---- logged signals -------------------------------------------------------------------------------
    def _resolve_outputs(self) -> list["ResolvedOutput"]:
        """The logged signals: each output's expression, SI unit and display unit, checked.

        An output's name heads a CSV column (:func:`~blocks.result.column_name_problem`). A display unit
        must have the dimension of what is logged where that is known: a net's across variable, a port or
        state declared in a unit, or a generic signal ("SI") on a net where a port declares one (a spool
        command read by a valve's ``x`` [1] is a plain number, not mm). A generic signal that no port
        declares has no known dimension: its display unit is taken as written (the netlist reference says
        so)."""
        resolved = []
        for out in self.flat.outputs:
            problem = column_name_problem(out.name)
            if problem:
                raise out.source.error(out.path, f"output '{shown_key(out.name)}': {problem}")
            try:
                expr, unit = self.generator.resolve_output(out.of)
            except KeyError as exc:
                raise out.source.error(out.path, f"output '{out.name}': {exc.args[0]}") from None
            declared = self._declared_units(out.of) if unit in ("", GENERIC) else []
            if out.unit is not None:
                self._check_display_unit(out, unit, declared)
            resolved.append(ResolvedOutput(out.name, expr, unit, out.unit or self._agreed_unit(declared) or unit,
                                           declared[0][1] if declared else None))
        if not resolved:
            resolved = self._default_outputs()
        return resolved

    def _check_display_unit(self, out, unit: str, declared: list[tuple[str, str]]) -> None:
        """Refuse a display unit that cannot be read, or that does not fit the logged signal's dimension
        (its SI ``unit``, or for a generic signal the units ``declared`` by the ports on its net)."""
        where = out.path + ("unit",)
        try:
            display = parse_unit(out.unit)
            known = [(out.of, unit)] if unit not in ("", GENERIC) else declared
            if known and not any(display.same_dimension(parse_unit(u)) for _, u in known):
                port, declared = known[0]
                declared = "1 (a plain number)" if declared == "1" else declared
                which = f"which is in {declared}" if port == out.of else f"which {port} reads in {declared}"
                raise out.source.error(where, f"output '{out.name}': unit '{out.unit}' does not fit {out.of}, {which}")
        except UnitError as exc:
            raise out.source.error(where, f"output '{out.name}': {exc}") from None

    def _declared_units(self, ref: str) -> list[tuple[str, str]]:
        """For a generic signal: (port, unit) of each port on its signal net that declares a unit.

        ``ref`` names a signal net or a signal port on one (a state has no net); a generic output ("SI")
        carries whatever its readers take, so a reader declared in a unit fixes the signal's dimension."""
        ref = self.flat.resolve_alias(ref)
        comp, _, name = ref.rpartition(".")
        if ref in self.flat.nets:
            net = ref
        elif name in self.structure.block_states.get(comp, {}):
            return []
        else:
            net = self.structure.port_net.get((comp, name))
        if net is None or self.flat.nets[net].kind is not PortKind.SIGNAL:
            return []
        ports = [(f"{c}.{p}", self.flat.components[c].cls.port(p).unit) for c, p in self.flat.nets[net].ports]
        return [(port, unit) for port, unit in ports if unit not in ("", GENERIC)]

    def _default_outputs(self) -> list["ResolvedOutput"]:
        """With no outputs: section, log every net's across variable (pressures in bar), named by the net."""
        out = []
        for net in self.flat.nets.values():
            problem = column_name_problem(net.name)
            if problem:
                raise net.source.error(net.path, f"net '{shown_key(net.name)}' would be logged as a column of its "
                                       f"own name (there is no outputs: section): {problem}; rename it or "
                                       f"list the outputs")
            expr, unit = self.generator.resolve_output(net.name)
            declared = self._declared_units(net.name) if unit in ("", GENERIC) else []
            display = "bar" if unit == "Pa" else self._agreed_unit(declared) or unit
            out.append(ResolvedOutput(net.name, expr, unit, display, declared[0][1] if declared else None))
        return out

    def agreed_unit(self, ref: str) -> str | None:
        """The unit of a generic signal ``ref`` that the ports reading it agree on, if they do."""
        return self._agreed_unit(self._declared_units(ref))

    @staticmethod
    def _agreed_unit(declared: list[tuple[str, str]]) -> str | None:
        """The unit the ports reading a generic signal declare, if they agree on its dimension: the signal
        is shown in it, not as "SI" (a spool command read by a valve's ``x`` [1] is a plain number)."""
        if declared and all(parse_unit(u).same_dimension(parse_unit(declared[0][1])) for _, u in declared):
            return declared[0][1]
        return None


def _volume_text(volume: float) -> str:
    """A cavity's size for a message: '98.6 cm^3', '2.35 l', 'under 0.001 cm^3'."""
    if volume < 1e-9:
        return "under 0.001 cm^3"
    return f"{volume * 1e6:.3g} cm^3" if volume < 1e-3 else f"{volume * 1e3:.3g} l"


@dataclass
class Equilibrium:
    """An equilibrium of the circuit (:meth:`Circuit.equilibrium`); status 0 when Newton converged."""

    status: int  # 0 converged, 1 singular, 2 no convergence, 3 non-finite, 4 a state acting on nothing not at rest
    states: np.ndarray
    values: np.ndarray  # the logged signals at the equilibrium, SI (NaN unless converged)
    names: list[str]
    growth: float  # the largest real part of J's eigenvalues, 1/s: < 0 stable (states resting anywhere left out)
    iterations: int
    sinks: np.ndarray  # bool per state: acts on no other state, solved after the rest (blocks.solve.equilibrium)

    @property
    def stable(self) -> bool:
        return self.status == 0 and self.growth < 0.0

    def __getitem__(self, name: str) -> float:
        return float(self.values[self.names.index(name)])


@dataclass
class ResolvedOutput:
    name: str
    expr: str
    unit: str
    display_unit: str
    declared: str | None = None
    """For a generic signal ("SI"): the unit a port on its net declares (its dimension), if one does."""


def _colour_columns(pattern: np.ndarray) -> tuple[np.ndarray, int]:
    """Group Jacobian columns whose row patterns do not overlap (one rhs call per group)."""
    n = pattern.shape[0]
    groups = np.full(n, -1, dtype=np.int64)
    rows_of_group: list[np.ndarray] = []
    for j in range(n):
        col = pattern[:, j]
        for g, rows in enumerate(rows_of_group):
            if not np.any(rows & col):
                groups[j] = g
                rows_of_group[g] = rows | col
                break
        else:
            groups[j] = len(rows_of_group)
            rows_of_group.append(col.copy())
    return groups, len(rows_of_group)
