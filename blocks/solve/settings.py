"""Solver settings, read from a netlist's ``simulation:`` section (units parsed here, SI after)."""

from __future__ import annotations

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
    sim = flat.netlist.simulation
    located = flat.source

    def seconds(key: str, raw) -> float:
        try:
            return quantity(raw, "s")
        except UnitError as exc:
            raise located.error(("simulation", key), f"simulation.{key}: {exc}") from None

    t_start, t_end, dt_out = seconds("t_start", sim.t_start), seconds("t_end", sim.t_end), seconds("dt_out", sim.dt_out)
    fixed = seconds("fixed_step", sim.fixed_step) if sim.fixed_step is not None else 0.0
    max_step = seconds("max_step", sim.max_step) if sim.max_step is not None else 0.0
    settings = SolverSettings(t_start, t_end, dt_out, sim.solver, sim.rtol, sim.atol, fixed, max_step, sim.max_steps)
    problem = settings.problem()
    if problem:
        key, message = problem
        raise located.error(("simulation", key), f"simulation.{key}: {message}")
    return settings
