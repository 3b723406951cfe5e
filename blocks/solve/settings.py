"""Solver settings, read from a netlist's ``simulation:`` section (units parsed here, SI after)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from blocks.units import UnitError, quantity


@dataclass(frozen=True)
class SolverSettings:
    t_start: float = 0.0
    t_end: float = 1.0
    dt_out: float = 1e-3
    solver: str = "rodas"  # rodas (stiff, variable step, compiled), fixed, lsoda, bdf, radau (scipy)
    rtol: float = 1e-6
    atol: float = 1e-6  # relative to each state's nominal magnitude
    fixed_step: float = 0.0
    max_step: float = 0.0
    max_steps: int = 2_000_000
    fixed_step_check: bool = True  # solver fixed: a second run at twice the step (blocks.solve.step_check)

    def with_(self, **changes) -> "SolverSettings":
        return replace(self, **changes)

    def problem(self) -> tuple[str, str] | None:
        """(setting, what is wrong) if the settings cannot run, else None."""
        if not self.t_end > self.t_start:
            return "t_end", f"{self.t_end:g} s must be after t_start ({self.t_start:g} s)"
        if not self.dt_out > 0:
            return "dt_out", "must be positive"
        if (self.t_end - self.t_start) / self.dt_out > 5e6:
            return "dt_out", "gives more than 5 million output samples"
        if self.fixed_step < 0:
            return "fixed_step", "must be positive"
        if self.solver == "fixed" and not self.fixed_step > 0:
            return "fixed_step", "solver 'fixed' needs a positive fixed_step (e.g. '0.1 ms')"
        if self.max_step < 0:
            return "max_step", "must be positive (or left out)"
        return None


def read_settings(flat) -> SolverSettings:
    return settings_of(flat.netlist.simulation, flat.source)


def settings_of(sim, located) -> SolverSettings:
    """The settings a netlist's ``simulation:`` section (``sim``, a spec.Simulation) gives, checked; errors
    placed in ``located`` (the file the section is in). A time written is finite; a ``fixed_step`` or
    ``max_step`` written is positive (left out, there is none)."""

    def seconds(key: str, raw) -> float:
        try:
            value = quantity(raw, "s")
        except UnitError as exc:
            raise located.error(("simulation", key), f"simulation.{key}: {exc}") from None
        if not math.isfinite(value):
            raise located.error(("simulation", key), f"simulation.{key}: {raw} is not finite")
        return value

    t_start, t_end, dt_out = seconds("t_start", sim.t_start), seconds("t_end", sim.t_end), seconds("dt_out", sim.dt_out)
    fixed = seconds("fixed_step", sim.fixed_step) if sim.fixed_step is not None else 0.0
    max_step = seconds("max_step", sim.max_step) if sim.max_step is not None else 0.0
    settings = SolverSettings(t_start, t_end, dt_out, sim.solver, sim.rtol, sim.atol, fixed, max_step, sim.max_steps,
                              sim.fixed_step_check)
    problem = settings.problem()
    if problem is None and sim.max_step is not None and not max_step > 0:  # 0 would mean none: write none
        problem = "max_step", "must be positive (or left out)"
    if problem is None and sim.fixed_step is not None and not fixed > 0:
        problem = "fixed_step", "must be positive (or left out)"
    if problem:
        key, message = problem
        raise located.error(("simulation", key), f"simulation.{key}: {message}")
    return settings
