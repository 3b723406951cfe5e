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


def read_settings(flat) -> SolverSettings:
    sim = flat.netlist.simulation
    located = flat.source

    def seconds(key: str, raw) -> float:
        try:
            return quantity(raw, "s")
        except UnitError as exc:
            raise located.error(("simulation", key), f"simulation.{key}: {exc}") from None

    t_start, t_end, dt_out = seconds("t_start", sim.t_start), seconds("t_end", sim.t_end), seconds("dt_out", sim.dt_out)
    if not t_end > t_start:
        raise located.error(("simulation", "t_end"), f"simulation.t_end ({t_end:g} s) must be after t_start ({t_start:g} s)")
    if not dt_out > 0:
        raise located.error(("simulation", "dt_out"), "simulation.dt_out must be positive")
    if (t_end - t_start) / dt_out > 5e6:
        raise located.error(("simulation", "dt_out"), "simulation.dt_out gives more than 5 million output samples")
    fixed = seconds("fixed_step", sim.fixed_step) if sim.fixed_step is not None else 0.0
    if sim.solver == "fixed" and not fixed > 0:
        raise located.error(("simulation", "solver"), "solver 'fixed' needs simulation.fixed_step (e.g. '0.1 ms')")
    max_step = seconds("max_step", sim.max_step) if sim.max_step is not None else 0.0
    return SolverSettings(t_start, t_end, dt_out, sim.solver, sim.rtol, sim.atol, fixed, max_step, sim.max_steps)
