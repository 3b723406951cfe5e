"""The netlist reference, generated from the code so that it cannot drift from it.

``vphs docs`` writes it to ``docs/netlist-reference.md``; a test compares the committed file with
:func:`reference_text`. What is generated, and from where:

- the file format: the sections, keys, shapes and defaults from the pydantic models of
  :mod:`blocks.netlist.spec`, the example from that module's docstring, the solver names from
  ``Simulation.solver``; the meaning of each key is the text in :data:`FIELD_TEXT` (a test makes sure
  every key of the schema has one);
- the value syntax: the known units from :data:`blocks.units.UNITS`, the functions and constants of
  :mod:`blocks.expressions`;
- the calibration experiment file and the optimisation job file: the annotated examples and the rules
  in the docstrings of :mod:`blocks.calibrate.experiment` and :mod:`blocks.optimise.job`;
- the blocks: every registered type (:mod:`blocks.registry`) with its docstring, ports, parameters,
  states and feedthrough, grouped by library.
"""

from __future__ import annotations

import inspect
import re
import types
import typing
from pathlib import Path

from pydantic import BaseModel
from pydantic_core import PydanticUndefined

from blocks.block import ACROSS, CAPACITY, THROUGH, Block, Param
from blocks.result import atomic_write_text

# ---------------------------------------------------------------- what each key of the schema means
FIELD_TEXT: dict[tuple[str, str], str] = {
    ("Netlist", "description"): "Free text about the circuit (not interpreted).",
    ("Netlist", "fluid"): "The fluid's properties; blocks with fluid parameters (rho, nu, beta) take them from "
                          "here unless a component sets its own.",
    ("Netlist", "defaults"): "Defaults for nets that do not set their own.",
    ("Netlist", "parameters"): "Named values (with units or expressions) that components, nets and other "
                               "parameters refer to by name. Overridable with `--set name=value`.",
    ("Netlist", "components"): "The blocks, by instance name: `{type: <block type>, params: {...}, initial: {...}}`.",
    ("Netlist", "subsystems"): "Other netlist files used as components, by instance name.",
    ("Netlist", "nets"): "The connections: each net joins ports `<component>.<port>` (or a subsystem's exposed "
                         "port `<subsystem>.<port>`). Long form `{ports: [...], volume:, bulk_modulus:, initial:}`, "
                         "short form a plain list of ports.",
    ("Netlist", "ports"): "What this file exposes when it is used as a subsystem: `<exposed name>: <net>` or "
                          "`<exposed name>: <component>.<port>`.",
    ("Netlist", "outputs"): "The logged signals, by column name: `{of: <reference>, unit: <display unit>}` or "
                            "just the reference.",
    ("Netlist", "simulation"): "Time span, output interval and solver.",
    ("Fluid", "rho"): "Density [kg/m^3].",
    ("Fluid", "nu"): "Kinematic viscosity [m^2/s].",
    ("Fluid", "beta"): "Bulk modulus [Pa]: the stiffness of the oil in every hydraulic net that does not set "
                       "its own `bulk_modulus`.",
    ("Fluid", "vapour_pressure"): "Vapour pressure [Pa], gauge: a net whose pressure falls below it is "
                                  "reported as cavitating (a warning after the run). Top-level netlist only.",
    ("Fluid", "cavitation"): "`true` (the default): a net drawn down to the vapour pressure holds a vapour "
                             "cavity, which the oil flowing back fills before the pressure rises again; "
                             "below the vapour pressure the net's stiffness gives way to the cavity's "
                             "(the pressure 0.1 bar lower per litre of vapour; "
                             "`blocks/library/hydraulic/cavitation.py`). "
                             "`false`: the liquid's bulk modulus at every pressure (the thesis's Simulink "
                             "model), so a net drawn empty goes into a tension oil cannot carry. Top-level "
                             "netlist only; blocks' own internal nodes are not affected.",
    ("Fluid", "air"): "Free air entrained in the oil, as a volume fraction at atmospheric pressure (`\"0.5 %\"`); "
                      "absent (the default): the pure liquid. Each net's bulk modulus is then the mixture's, "
                      "beta*(1 + r)/(1 + r*beta/(n*p_abs)) with r the air's volume over the liquid's at the net's "
                      "pressure: soft near the tank's pressure, the liquid's at working pressure "
                      "(`blocks/library/hydraulic/entrained_air.py`). Top-level netlist only.",
    ("Fluid", "air_index"): "Polytropic index n of the entrained air: 1 isothermal (the default, slow "
                            "changes), 1.4 adiabatic (fast ones). Top-level netlist only.",
    ("Defaults", "volume"): "Volume [m^3] of every hydraulic net that neither sets `volume:` nor has a block "
                            "storing oil on it (without it such a net is an error).",
    ("Component", "type"): "The block type: one of the names in [Blocks](#blocks).",
    ("Component", "preset"): "A named parameter set of the block type (data-sheet or thesis values, listed "
                             "under each block); `params` given beside it override the preset's values.",
    ("Component", "params"): "Parameter values by name; a parameter left out takes its default (or the "
                             "netlist's fluid property); a parameter without default must be given. Array "
                             "parameters take a list or `{csv: <file>, column: <name>}`.",
    ("Component", "initial"): "Start values of the block's scalar states by name (array states start at their "
                              "default).",
    ("Subsystem", "netlist"): "The netlist file, relative to this file's folder.",
    ("Subsystem", "parameters"): "Overrides of that file's `parameters:` (`m_load: ...`), of a component's "
                                 "parameter inside it (`valve.A_max: ...`, as `--set` names it) or, through "
                                 "a subsystem of it, of anything that one takes (`lift.valve.Cd: ...`); the "
                                 "values are read in this file's scope (they may use this file's parameter "
                                 "names), and the outermost file's word is the last.",
    ("Net", "ports"): "The ports the net joins: `<component>.<port>` or `<subsystem>.<exposed port>`.",
    ("Net", "volume"): "Hydraulic nets: the oil volume of the node [m^3], added to what blocks store on it.",
    ("Net", "bulk_modulus"): "Hydraulic nets: the node's bulk modulus [Pa] (default: `fluid.beta`).",
    ("Net", "initial"): "The across variable's start value: pressure [Pa] of a hydraulic net, speed [rad/s] "
                        "or [m/s] of a mechanical one (default 0).",
    ("Output", "of"): "What to log: a net name (its pressure or speed; for a signal net its driving output), "
                      "`<component>.<port>`, `<component>.<state>` (scalar states), or "
                      "`<component>.<port>.flow` / `.torque` / `.force`: what the block delivers to the net at "
                      "that port (positive into the net, the engine's sign convention); for a source's `port` "
                      "(`speed_source`, `velocity_source`, `pressure_source`, `pressure_source_signal`, `tank`), "
                      "the torque, force or flow it delivers to hold its speed or pressure.",
    ("Output", "unit"): "The unit of the CSV column and the plot (default: the SI unit; for a generic signal, "
                        "the unit the ports reading it agree on, e.g. `1`, else `SI`). It must have the "
                        "dimension of what is logged where that is known: a net's pressure or speed, a port, "
                        "state or flow declared in a unit, or a generic signal on a net where a port declares "
                        "one (a command read by a valve's `x` [1] is a plain number). A generic signal (declared "
                        "`SI`: a gain's or a sum's output) that no port on its net declares has no known "
                        "dimension: its unit is taken as written (the values are divided by the unit's SI "
                        "factor and the header shows it) and not checked, and a job's cost terms on it take "
                        "that unit's dimension.",
    ("Simulation", "t_start"): "Start time [s].",
    ("Simulation", "t_end"): "End time [s] (`--t-end` overrides it).",
    ("Simulation", "dt_out"): "Interval of the logged samples [s] (not the solver's step).",
    ("Simulation", "solver"): "The integrator: see [Solvers](#solvers) (`--solver` overrides it).",
    ("Simulation", "rtol"): "Relative tolerance of the variable-step solvers.",
    ("Simulation", "atol"): "Absolute tolerance, relative to each state's nominal size (1 bar for a pressure, "
                            "1 rad/s for a speed, a block's declared nominal for its states; a generic signal "
                            "block's state, a filter's or an integrator's, takes the nominal of the quantity its "
                            "signal carries where a port's unit or a value written in a unit fixes it: 1e-4 "
                            "m^3/s for a flow, 1 bar for a pressure).",
    ("Simulation", "fixed_step"): "Step [s] of the `fixed` solver (required by it, ignored by the others).",
    ("Simulation", "max_step"): "Largest step [s] the variable-step solvers may take (default: unlimited).",
    ("Simulation", "max_steps"): "The run fails after this many steps.",
    ("Simulation", "fixed_step_check"): "With the `fixed` solver, run again at twice the step and warn if an "
                                        "output moves by over 1 % of its range (costs half a run; `false` "
                                        "skips it). An optimisation's evaluations and a calibration's fits "
                                        "skip it; the best design, a sweep's points and the calibrated "
                                        "model are checked.",
    ("CsvColumn", "csv"): "The CSV file, relative to the netlist's folder; header cells `name [unit]`.",
    ("CsvColumn", "column"): "The column's name (with or without its `[unit]`); the values are converted from "
                             "the header's unit to the parameter's SI unit.",
}

SOLVER_TEXT = {
    "rodas": "Default. A compiled, L-stable Rosenbrock method (hydraulic circuits are stiff) with variable "
             "step and error control, finite-difference Jacobian grouped by the netlist's sparsity.",
    "fixed": "The same Rosenbrock method at the constant step `fixed_step`, without error control; a run "
             "whose pressure leaves hydraulics (over 10000 bar: a step too long for the circuit) is an error "
             "(with the other solvers a warning). A step too long rarely fails: it gives other numbers. So the "
             "run is repeated at twice the step, and a warning names the output that moves most, if one "
             "moves by over 1 % of its range (`fixed_step_check`). The run at the step itself is then "
             "usually off by much less once the step is short enough for the method's order to show, but "
             "a step past a fast mode is not: it may be too long, and rodas, which controls its error, "
             "says. Like rodas, a fixed step ends on each time an input jumps or kinks "
             "(the grid goes on after it).",
    "lsoda": "scipy's `solve_ivp(method='LSODA')` on the same compiled right-hand side (switches between "
             "stiff and non-stiff methods).",
    "bdf": "scipy's `solve_ivp(method='BDF')`, given the Jacobian's sparsity from the netlist graph.",
    "radau": "scipy's `solve_ivp(method='Radau')`, given the Jacobian's sparsity from the netlist graph.",
}

LIBRARIES = (  # module prefix -> section title, in the order they appear
    ("blocks.library.hydraulic", "Hydraulic blocks"),
    ("blocks.library.mechanical", "Mechanical blocks"),
    ("blocks.library.signal", "Signal blocks"),
    ("vphs_blocks", "Crane components"),
)

HEADER = """# Netlist reference

Generated by `vphs docs` from the code (the netlist schema in `blocks/netlist/spec.py` and the block
registry): do not edit by hand; run `vphs docs` after changing a block or the schema.
"""


# ---------------------------------------------------------------- one block
def block_reference(cls: type[Block], level: int = 2) -> str:
    """A block's reference: docstring, ports, parameters, states, feedthrough (``level``: heading depth)."""
    doc = (inspect.getdoc(cls) or "").split("\n", 1)
    lines = [f"{'#' * level} `{cls.type_name}`", "", doc[0].strip(), ""]
    if len(doc) > 1 and doc[1].strip():  # the equations, verbatim (Markdown would reflow them)
        lines += ["```text", doc[1].strip("\n"), "```", ""]
    lines += ["| port | kind | carries | description |", "|---|---|---|---|"]
    for p in cls.ports:
        kind = p.kind.value + (f" {p.direction}" if p.direction else "") + (" (optional)" if p.optional else "")
        carries = p.unit if not p.physical else f"{ACROSS[p.kind][0]} [{ACROSS[p.kind][1]}]" + (" + stores" if p.stores else "")
        lines.append(f"| `{p.name}` | {kind} | {carries} | {_cell(p.description)} |")
    if cls.params:
        lines += ["", "| parameter | unit | default | bounds | description |", "|---|---|---|---|---|"]
        for p in cls.params:
            default = f"fluid.{p.fluid}" if p.fluid else ("required" if p.default is None else _fmt(p.default))
            bounds = bounds_text(p)
            kind = " (array)" if p.array else (" (integer)" if p.integer else "")
            lines.append(f"| `{p.name}`{kind} | {p.unit} | {default} | {bounds} | {_cell(p.description)} |")
    if cls.states:
        lines += ["", "| state | unit | start | description |", "|---|---|---|---|"]
        for s in cls.states:
            lines.append(f"| `{s.name}`{' (array)' if s.size else ''} | {s.unit} | {_fmt(s.start)} | {_cell(s.description)} |")
    feed = cls.feedthrough()
    lines += ["", f"Direct feedthrough: {', '.join(f'`{f}`' for f in feed) if feed else 'none'}."]
    if cls.prescribes:
        lines.append(f"Prescribes the across variable of: {', '.join(f'`{p}`' for p in cls.prescribes)}.")
    if cls.rigid_link:
        lines.append(f"Rigid link: `{cls.rigid_link[1]}` moves at ratio(params) times `{cls.rigid_link[0]}`.")
    if cls.checked:
        lines.append(f"Checked after a run against its valid range (a warning if it leaves it): "
                     f"{', '.join(f'`{c}`' for c in cls.checked)}.")
    if cls.regularised:
        lines.append(f"Smooths a jump at zero of {', '.join(f'`{c}`' for c in cls.regularised)} over a band "
                     f"(`vphs linearise` about a point inside it says so).")
    for group in cls.same_quantity:
        lines.append(f"{', '.join(f'`{p}`' for p in group)} carry the same quantity (one tolerance scale).")
    for port, given_by in cls.signal_dimensions.items():
        lines.append(f"`{port}` is in the dimension {' and '.join(f'`{g}`' for g in given_by)} "
                     f"{'is' if len(given_by) == 1 else 'are'} written in; a port on its net that declares another "
                     f"is an error.")
    if cls.presets:
        lines += ["", "| preset | values |", "|---|---|"]
        for name, values in cls.presets.items():
            shown = ", ".join(f"{k} = {v}" for k, v in values.items())
            lines.append(f"| `{name}` | {_cell(shown)} |")
    return "\n".join(lines) + "\n"


def bounds_text(p: Param) -> str:
    """A parameter's bounds as an interval, as :meth:`Param.check` applies them: ``[0, 10]`` accepts 0 and 10,
    ``(0, 10]`` refuses 0 itself (``positive``), ``(-inf, inf)`` has no bound."""
    lower = "(-inf" if p.lower is None else f"({_fmt(p.lower)}" if p.positive else f"[{_fmt(p.lower)}"
    upper = f"{_fmt(p.upper)}]" if p.upper is not None else "inf)"
    return f"{lower}, {upper}"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _fmt(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, tuple):
        return "[" + ", ".join(f"{v:g}" for v in value) + "]"
    return f"{value:g}"


def anchor(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = heading.strip().lower().replace("`", "")
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def library_of(cls: type[Block]) -> str:
    for prefix, title in LIBRARIES:
        if cls.__module__ == prefix or cls.__module__.startswith(prefix + "."):
            return title
    return "Other blocks"


# ---------------------------------------------------------------- the file format
def _shape(annotation) -> str:
    """A reader's name for a schema type: value, list of ports, mapping name -> ..."""
    from blocks.netlist import spec

    if annotation == spec.Value or annotation == typing.Optional[spec.Value]:
        return "value"
    if annotation is str:
        return "text"
    if annotation is bool:
        return "true or false"
    if annotation is float:
        return "number"
    if annotation is int:
        return "integer"
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return "mapping (below)"
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is typing.Literal:
        return "one of " + ", ".join(f"`{a}`" for a in args)
    if origin is dict:
        return f"mapping name: {_shape(args[1])}"
    if origin is list:
        return f"list of {_shape(args[0])}s"
    if origin in (typing.Union, types.UnionType):
        members = [a for a in args if a is not type(None)]
        scalars = {float, int, str}
        if set(members) >= scalars:
            rest = [a for a in members if a not in scalars]
            return " or ".join(["value"] + [_shape(a) for a in rest])
        return " or ".join(_shape(a) for a in members)
    return str(annotation)


def _default(field) -> str:
    if field.default_factory is not None:
        made = field.default_factory()
        return "{}" if made == {} else ("[]" if made == [] else "see below")
    if field.default is PydanticUndefined:
        return "required"
    if field.default is None:
        return "-"
    if field.default == "":
        return '`""`'
    if isinstance(field.default, bool):
        return f"`{str(field.default).lower()}`"
    return f"`{field.default}`" if isinstance(field.default, str) else f"`{field.default:g}`" \
        if isinstance(field.default, float) else f"`{field.default}`"


def schema_table(model: type[BaseModel]) -> str:
    lines = ["| key | shape | default | meaning |", "|---|---|---|---|"]
    for name, field in model.model_fields.items():
        text = FIELD_TEXT.get((model.__name__, name)) or field.description or ""
        lines.append(f"| `{name}` | {_shape(field.annotation)} | {_default(field)} | {_cell(text)} |")
    return "\n".join(lines) + "\n"


def schema_models() -> list[type[BaseModel]]:
    from blocks.netlist import spec

    return [spec.Netlist, spec.Fluid, spec.Defaults, spec.Component, spec.CsvColumn, spec.Subsystem, spec.Net,
            spec.Output, spec.Simulation]


def undocumented_fields() -> list[str]:
    """Schema keys without a meaning in FIELD_TEXT or a pydantic description (a test keeps this empty)."""
    return [f"{m.__name__}.{name}" for m in schema_models() for name, field in m.model_fields.items()
            if not (FIELD_TEXT.get((m.__name__, name)) or field.description)]


def _example() -> str:
    from blocks.netlist import spec

    doc = inspect.getdoc(spec) or ""
    block = doc.split("::", 1)[1].split("\n\n", 2)[1] if "::" in doc else ""
    return "```yaml\n" + inspect.cleandoc(block) + "\n```\n"


def _units_table() -> str:
    from blocks.units import DIMENSION_NAMES, UNITS

    groups: dict[tuple, list[str]] = {}
    for name, unit in UNITS.items():
        groups.setdefault(unit.dims, []).append(name)
    lines = ["| dimension | units |", "|---|---|"]
    for dims, names in groups.items():
        parts = [f"{n}^{e:g}" if e != 1 else n for n, e in zip(DIMENSION_NAMES, dims) if e]
        lines.append(f"| {'*'.join(parts) or '1'} | {', '.join(f'`{n}`' for n in names)} |")
    return "\n".join(lines) + "\n"


def file_format() -> str:
    from blocks import expressions
    from blocks.netlist import spec

    solvers = typing.get_args(spec.Simulation.model_fields["solver"].annotation)
    across = ", ".join(f"{k.value}: {ACROSS[k][0]} [{ACROSS[k][1]}] / {THROUGH[k][0]} [{THROUGH[k][1]}] / "
                       f"{CAPACITY[k][0]} [{CAPACITY[k][1]}]" for k in ACROSS)
    sections = [
        "## The netlist file",
        "",
        "A netlist is a YAML file (the safe subset: no tags, no duplicate keys) describing a circuit as its "
        "drawing sheet does: components, the nets joining their ports, and what to log. Every section is "
        "optional. An example with every section:",
        "",
        _example(),
        "### Sections",
        "",
        schema_table(spec.Netlist),
        "### Values and units",
        "",
        "Everything inside is SI; units are read where values enter. A value is",
        "",
        "- a number: taken as SI (`0.7`, `2e-4`);",
        "- a string `\"<number> <unit>\"`: converted to SI and checked against the declared unit's dimension "
        "(`\"207 bar\"`, `\"30 cm^3/rev\"`, `\"52.6 rad/s\"`); a wrong dimension is an error that names both;",
        "- an expression over parameter names (SI), which may contain quantities: "
        "`\"0.085 + m_load*r_pinion**2/n_gear**2\"`, `\"23000 kg + m_payload\"`. Operators `+ - * / ** %`, "
        "parentheses, the functions " + ", ".join(f"`{f}`" for f in expressions.FUNCTIONS) +
        " and the constants " + ", ".join(f"`{c}`" for c in expressions.CONSTANTS) + ". A name may also "
        "be a component's scalar parameter or a net's written `initial` of the same file, by its dotted "
        "name: `initial: supply.p` (the net starts at the supply's pressure, and follows an override of it), "
        "`p_set: A.initial + 20 bar`; not a name inside a subsystem (`bridge.ctrl.k2`). Nothing else (no other "
        "attributes, no calls of "
        "anything else): a netlist cannot run code.",
        "",
        "Units combine with `*` (or a space), `/` and `^` (`\"m^3/(s*Pa)\"`, `\"N*m*s/rad\"`). Angle is a "
        "dimension of its own, so `rev`, `rpm` and `Hz` convert to radians (1 Hz = 2π rad/s) and a "
        "displacement in `cm^3/rev` fits a parameter in `m^3/rad`. Hand formulas carry the radian along: "
        "a motor's torque D*dp is in `N*m/rad` as written, so a torque from it is `\"D*dp*(1 rad)\"` "
        "(`\"m*g*r/n/D/(1 rad)\"` for the pressure that holds a load), and a rotational damping is in "
        "`N*m*s/rad`. Pressures are gauge. Known units:",
        "",
        _units_table(),
        "Array parameters (tables, coefficients) take a list of values (`[0, 0.5 s, t_acc]`) or a column "
        "of a CSV file:",
        "",
        schema_table(spec.CsvColumn),
        "Netlist parameters (`parameters:`) may carry any unit (`\"7500 kg\"`) and are stored in SI; the "
        "parameter that uses them checks the dimension. Every value has a qualified name that `vphs run "
        "--set` overrides, everything depending on it following: `m_load`, `valve.A_max`, "
        "`bridge.valve.A_max` (inside subsystem `bridge`), `A.volume`, `A.initial`, `valve.initial.x`, "
        "`fluid.rho`. A value given from outside (`--set`, a job's `set:` and bounds, an experiment's "
        "overrides) may carry a unit too, checked against the parameter's declared unit, the unit its value is "
        "written in, or for a bare number the dimension its readers take it in: `n_gear` in `J: \"0.085 + "
        "m_load*r_pinion**2/n_gear**2\"` is a plain number, so `--set \"n_gear=39 rpm\"` is an error. A bare "
        "number read only where any unit goes (a generic signal block's `SI` parameter) takes any unit, "
        "converted to SI unchecked. `--set` values, a job's `set:` and load-case values and an experiment's "
        "`overrides:` and `groups:` values may also be expressions over the netlist's parameters by their "
        "qualified names (`--set Kvp=Kv/4`, `--set \"p_c=p_crack + 10 bar\"`), evaluated once with the "
        "netlist's values and the section's plain values in their place (see the optimisation job file and "
        "the calibration experiment below); one that reads another expression of its section, or a parameter "
        "the command changes (a job's varied one, an experiment's free one, linearise's `--input`), is refused: "
        "it would not follow it.",
        "",
        "### Fluid and defaults",
        "",
        schema_table(spec.Fluid),
        schema_table(spec.Defaults),
        "### Components",
        "",
        schema_table(spec.Component),
        "A parameter's bounds (in the block tables below) are checked when values are evaluated, and so are "
        "the relations between parameters a block checks (a table's breakpoints increasing, a lower limit "
        "below the upper). `[0, 10]` accepts 0 and 10 themselves; `(0, 10]` refuses 0 (the value must be "
        "positive); `-inf` or `inf`: no bound on that side.",
        "",
        "### Nets",
        "",
        schema_table(spec.Net),
        "A net's kind is the kind of the ports it joins (all must agree). Across / through / capacity per "
        f"kind: {across}.",
        "",
        "- A **hydraulic** net is a node with a pressure state: dp/dt = β/V·Σq, V its `volume` plus what "
        "blocks store on it (cylinder chambers, `volume` blocks). A net with a pressure source on it has no "
        "state.",
        "- A **rotational** or **translational** net is a rigid node: J·dω/dt = Στ (m·dv/dt = Σf), the "
        "inertia (mass) the sum of what is attached; it needs at least one block that stores inertia or "
        "mass. Gears and rack-and-pinions join nets into one rigid body.",
        "- A **signal** net joins exactly one output to any number of inputs (an optional input may stay "
        "unconnected and reads 0).",
        "",
        "Sign convention: the through value a block returns at a port is what it delivers to the net (flow "
        "into the node, torque or force acting on it).",
        "",
        "### Subsystems",
        "",
        schema_table(spec.Subsystem),
        "A subsystem is another netlist file used as a component. Its names are qualified by the "
        "subsystem's name (`bridge.valve`, `bridge.A`, `bridge.m_load`); its `ports:` section says which of "
        "its nets or ports the outer file may connect (`P: P` exposes net `P` as `bridge.P`). Nets merged "
        "through an exposed port add their volumes; an outer `initial` wins. A file may not include itself, "
        "and nesting is limited in depth. A subsystem file's own `simulation:` section (for when it is run "
        "alone) is not used where it is a part, but is checked there as well.",
        "",
        "### Outputs",
        "",
        schema_table(spec.Output),
        "With no `outputs:` section every net's across variable is logged under the net's name (pressures "
        "in bar); `vphs run` writes the logged signals to CSV (header `t [s]`, then `name [unit]` for each) "
        "and, with `--plot`, a PNG. An output's name is its column's name, read back by `vphs diff`: "
        "it may not be `t` (the time column), have spaces around it, or contain `[`, `]`, `,` or a tab. "
        "No name in a netlist (of a component, net, parameter, subsystem or output) may have spaces "
        "around it.",
        "",
        "Valid ranges. Some blocks know where their equations stop describing the machine (a lookup "
        "table's breakpoints, the LGA jib's angle range): each signal such a block lists as checked is "
        "computed at every output sample whether or not it is logged, and a run in which it leaves its range "
        "ends with a warning, one line per signal: when it first left the range, its value furthest "
        "outside it, and what the block does there (`table: u left its valid range (0 to 1.5) at t = "
        "1.51 s, reaching 2 at t = 2 s; outside it the table's end value is held`). A limit of your own "
        "(a hose's rated pressure, a motor's top speed) is a `range_check` block on the signal. The "
        "warnings reach `vphs run`'s console, an optimisation's records and report, a sweep's report and "
        "a calibration's verdict, as a cavity does. Between two samples nothing is seen: the check is as "
        "fine as `dt_out`. A parameter allowed but outside what a block was made for (the motion-control "
        "valve's flow force at a crack setting beyond those of its fit) is said the same way, once per run.",
        "",
        "### Simulation",
        "",
        schema_table(spec.Simulation),
        "### Solvers",
        "",
        "| solver | what it is |",
        "|---|---|",
    ]
    for name in solvers:
        sections.append(f"| `{name}` | {SOLVER_TEXT.get(name, '')} |")
    sections += [
        "",
        "`rodas` (and `fixed`) ends a step on each time a `step`, `ramp` or `profile` jumps or kinks (a step's time, a "
        "ramp's start and end, a profile's points where its slope changes), so a short pulse is never "
        "stepped over, however long the quiet run before it. The scipy solvers are restarted there, but "
        "at most 100 times a run, no closer than 1/100 of it (a multistep method restarts at its lowest "
        "order): a pulse closer than that to another breakpoint is left to their error control. A change "
        "that no such block declares (a signal crossing a threshold) is found by error control alone; "
        "`max_step` bounds the step where that is not enough.",
        "",
    ]
    return "\n".join(sections) + "\n"


# ---------------------------------------------------------------- the whole reference
def experiment_format() -> str:
    """The calibration experiment file (``vphs calibrate``), from the annotated example that
    blocks.calibrate.experiment's docstring keeps beside the code that reads it."""
    from blocks.calibrate import experiment

    doc = inspect.getdoc(experiment) or ""
    block = doc.split("::", 1)[1].split("\n\nErrors name", 1)[0] if "::" in doc else ""
    return "\n".join([
        "## The calibration experiment file", "",
        "`vphs calibrate EXPERIMENT` reads a YAML file that names the netlist, the measured data and what to "
        "fit; the README's Calibration section says what the command does with it. Paths are relative to the "
        "file; every value may carry a unit of its parameter's or channel's dimension. Every key, annotated "
        "(the held-out schemes are `leave_one_group_out`, `leave_one_experiment_out`: each data file in turn, "
        "`kfold_experiments` and `kfold`):", "",
        "```yaml", inspect.cleandoc(block), "```", ""])


def job_format() -> str:
    """The optimisation and sweep job file (``vphs optimise``, ``vphs sweep``): the docstring of
    blocks.optimise.job, which keeps the annotated example, the cost terms, the methods' settings and
    how to express a limit beside the code that reads them."""
    from blocks.optimise import job

    doc = inspect.getdoc(job) or ""
    body = doc.split("\n\n", 1)[1] if "\n\n" in doc else ""
    return "\n".join(["## The optimisation job file", "",
                      "What the commands write and how they run: the README's Optimisation jobs section.", "",
                      docstring_markdown(body), ""])


def docstring_markdown(text: str) -> str:
    """A docstring's reStructuredText as Markdown: ``code`` and :role:`name` as `code`; a paragraph ending
    in '::' followed by an indented block as the paragraph and a fenced YAML block; any other indented
    block (a table of settings) as a fenced text block; in prose, * and < escaped (not emphasis or HTML)."""
    out, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        if lines[i].startswith("    "):
            block = []
            while i < len(lines) and (lines[i].startswith("    ") or not lines[i].strip()):
                block.append(lines[i])
                i += 1
            while out and not out[-1].strip():
                out.pop()
            language = "yaml" if out and out[-1].endswith("::") else "text"
            if language == "yaml":
                out[-1] = out[-1][:-1]
            out += ["", f"```{language}", inspect.cleandoc("\n".join(block)), "```", ""]
            continue
        if lines[i].strip() or (out and out[-1].strip()):  # one blank line between paragraphs
            out.append(_prose_markdown(lines[i]))
        i += 1
    return "\n".join(out).strip("\n")


def _prose_markdown(line: str) -> str:
    line = re.sub(r":\w+:`~?([^`]+)`", r"``\1``", line)
    parts = line.split("``")  # odd parts are code
    return "`".join(part if k % 2 else re.sub(r"<(?=[A-Za-z/!?])", r"\\<", part.replace("*", "\\*"))
                    for k, part in enumerate(parts))


def reference_text() -> str:
    """The whole netlist reference (Markdown): contents, the file format, every registered block."""
    from blocks import registry

    types = registry.all_types()
    grouped: dict[str, list[type[Block]]] = {}
    order = [title for _, title in LIBRARIES] + ["Other blocks"]
    for cls in types.values():
        grouped.setdefault(library_of(cls), []).append(cls)
    fmt = file_format() + "\n" + experiment_format() + "\n" + job_format()

    toc = ["## Contents", ""]
    for line in fmt.splitlines():
        if line.startswith("## ") or line.startswith("### "):
            title = line.lstrip("#").strip()
            indent = "  " if line.startswith("### ") else ""
            toc.append(f"{indent}- [{title}](#{anchor(title)})")
    toc.append("- [Blocks](#blocks)")
    for title in order:
        if title in grouped:
            names = ", ".join(f"[`{c.type_name}`](#{anchor(c.type_name)})" for c in grouped[title])
            toc.append(f"  - [{title}](#{anchor(title)}): {names}")
    toc.append("")

    blocks = ["## Blocks", "",
              f"{len(types)} block types. Each lists its ports (what a net connects), parameters (SI units, "
              "defaults, bounds), states, and its direct feedthrough: the inputs its outputs read at once "
              "(an algebraic loop through feedthrough inputs is an error).", ""]
    for title in order:
        if title not in grouped:
            continue
        blocks += [f"### {title}", ""]
        for cls in grouped[title]:
            blocks.append(block_reference(cls, level=4))
    return "\n".join([HEADER, "\n".join(toc), fmt.rstrip("\n") + "\n", "\n".join(blocks)]).rstrip("\n") + "\n"


def write_reference(path: str | Path) -> None:
    atomic_write_text(Path(path), reference_text())

