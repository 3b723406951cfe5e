"""What a block is: declared ports, parameters and states, and two numba-compilable equation functions.

A block is a definition only (as a Drake System is): parameter and state values live in the compiled
circuit's vectors and arrive at evaluation time, so one compiled circuit runs any number of parameter
vectors without being rebuilt.

Ports
-----
- ``signal``: causal. An input reads a wire; an output drives one.
- ``hydraulic``: across variable pressure p [Pa] (gauge), through variable volume flow q [m^3/s].
- ``rotational``: across variable angular speed w [rad/s], through variable torque [N*m].
- ``translational``: across variable velocity v [m/s], through variable force [N].

Sign convention (one for every physical kind): the through value a block returns for a port is what it
**delivers to the net** at that port: flow into the hydraulic node, torque or force acting on the rigid
node. A net sums what its ports deliver: dp/dt = beta/V * sum(q), J * dw/dt = sum(tau), m * dv/dt = sum(f).
A port declared ``stores=True`` also returns its contribution to the net's capacity: volume [m^3] for
hydraulic, inertia [kg*m^2] for rotational, mass [kg] for translational.

Equation functions
------------------
Both are plain Python functions of scalars (and of array views for array parameters and states), written
so that numba can compile them; the code generator calls them by argument *name*:
``t``, each state's name, each signal input's name, each physical port's name (its across variable), each
parameter's name, and for an array state ``x`` also ``der_x`` (a view of its derivative, filled in place).

- ``outputs(...)`` returns the tuple :meth:`Block.output_names`: each signal output, then the across value
  of each port the block prescribes (a pressure or speed source). Which inputs it takes *is* its direct
  feedthrough: the ordering graph reads the signature, so the declaration cannot drift from the code.
- ``derivatives(...)`` returns the tuple :meth:`Block.derivative_names`: the through value of each physical
  port it does not prescribe, the capacity of each storing port, then the derivative of each scalar state.
"""

from __future__ import annotations

import inspect
import math
from dataclasses import dataclass, field
from enum import Enum
from typing import Callable, ClassVar


class PortKind(str, Enum):
    SIGNAL = "signal"
    HYDRAULIC = "hydraulic"
    ROTATIONAL = "rotational"
    TRANSLATIONAL = "translational"


# kind -> (across name, unit), (through name, unit), (capacity name, unit)
ACROSS = {
    PortKind.HYDRAULIC: ("p", "Pa"),
    PortKind.ROTATIONAL: ("w", "rad/s"),
    PortKind.TRANSLATIONAL: ("v", "m/s"),
}
THROUGH = {
    PortKind.HYDRAULIC: ("q", "m^3/s"),
    PortKind.ROTATIONAL: ("tau", "N*m"),
    PortKind.TRANSLATIONAL: ("f", "N"),
}
CAPACITY = {
    PortKind.HYDRAULIC: ("V", "m^3"),
    PortKind.ROTATIONAL: ("J", "kg*m^2"),
    PortKind.TRANSLATIONAL: ("m", "kg"),
}


@dataclass(frozen=True)
class Port:
    """A connection point. ``direction`` is "in"/"out" for signals, None for physical ports."""

    name: str
    kind: PortKind
    description: str
    direction: str | None = None
    unit: str = "SI"  # a signal's unit; "SI" = generic (any dimension, in SI), "1" = dimensionless
    stores: bool = False
    optional: bool = False
    """An optional signal input reads 0 when nothing is connected."""

    @property
    def physical(self) -> bool:
        return self.kind is not PortKind.SIGNAL

    @property
    def unit_of_value(self) -> str:
        """The unit of what the port carries: a signal's own unit, or the across variable's."""
        return self.unit if not self.physical else ACROSS[self.kind][1]


def signal_in(name: str, description: str, unit: str = "SI", optional: bool = False) -> Port:
    return Port(name, PortKind.SIGNAL, description, "in", unit, optional=optional)


def signal_out(name: str, description: str, unit: str = "SI") -> Port:
    return Port(name, PortKind.SIGNAL, description, "out", unit)


def hydraulic(name: str, description: str, stores: bool = False) -> Port:
    return Port(name, PortKind.HYDRAULIC, description, stores=stores)


def rotational(name: str, description: str, stores: bool = False) -> Port:
    return Port(name, PortKind.ROTATIONAL, description, stores=stores)


def translational(name: str, description: str, stores: bool = False) -> Port:
    return Port(name, PortKind.TRANSLATIONAL, description, stores=stores)


@dataclass(frozen=True)
class Param:
    """One parameter: name, SI unit, default, bounds [lower, upper] (None: no bound on that side), description.

    Both bounds are accepted values, except the lower one where ``positive`` is set: then the value must lie
    above it, (lower, upper] (a length, a time constant: 0 would divide by zero). The docs write it so.

    ``fluid`` names a netlist-level fluid property (rho, nu, beta, vapour_pressure) whose value the parameter
    takes unless the component overrides it. ``array`` parameters are vectors (tables, polynomial coefficients) whose
    length is fixed when the circuit is built; their default is a tuple. ``integer`` parameters are switches
    (a table's ``extrapolate``): whole numbers only, never free in an optimisation or a calibration.
    """

    name: str
    unit: str
    default: float | tuple | None
    lower: float | None
    upper: float | None
    description: str
    fluid: str | None = None
    array: bool = False
    integer: bool = False
    positive: bool = False  # the lower bound itself is excluded (for a lower bound 0: the value must be positive)

    def check(self, value) -> str | None:
        """None if ``value`` is inside the bounds, else what is wrong."""
        values = value if self.array else (value,)
        unit = f" {self.unit}" if self.unit not in ("1", "") else ""
        for v in values:
            if not math.isfinite(v):
                return f"{self.name} = {v} is not finite"
            if self.lower is not None and self.positive and v <= self.lower:
                above = "be positive" if self.lower == 0 else f"lie above {self.lower:g}{unit}"
                return f"{self.name} = {v:g}{unit} must {above}"
            if self.lower is not None and v < self.lower:
                return f"{self.name} = {v:g}{unit} is below its lower bound {self.lower:g}{unit}"
            if self.upper is not None and v > self.upper:
                return f"{self.name} = {v:g}{unit} is above its upper bound {self.upper:g}{unit}"
            if self.integer and v != math.floor(v):
                return f"{self.name} = {v:g} must be a whole number ({self.description})"
        return None


@dataclass(frozen=True)
class State:
    """A continuous state: name, SI unit, default initial value, nominal magnitude (scales the absolute
    tolerance), description. ``size`` (a function of the block's array lengths) makes it an array state.

    ``scale_of`` (generic "SI" states only) names the signal port whose quantity the state carries: where
    the netlist fixes that quantity's dimension, the state's nominal is that dimension's nominal magnitude
    (:mod:`blocks.compiler.signal_scale`: a flow's 1e-4 m^3/s, a pressure's 1 bar), else ``nominal``."""

    name: str
    unit: str
    start: float
    nominal: float
    description: str
    size: Callable[[dict[str, int]], int] | None = None
    scale_of: str | None = None


def fluid_params() -> tuple[Param, ...]:
    """The fluid properties as parameters that default to the netlist's ``fluid:`` section."""
    return (
        Param("rho", "kg/m^3", None, 1.0, 5000.0, "fluid density", fluid="rho"),
        Param("nu", "m^2/s", None, 1e-8, 1e-2, "kinematic viscosity", fluid="nu"),
        Param("beta", "Pa", None, 1e6, 1e11, "bulk modulus", fluid="beta"),
    )


class Block:
    """Base of every block type. Subclasses set the class attributes and the equation functions."""

    type_name: ClassVar[str] = ""
    ports: ClassVar[tuple[Port, ...]] = ()
    params: ClassVar[tuple[Param, ...]] = ()
    states: ClassVar[tuple[State, ...]] = ()
    prescribes: ClassVar[tuple[str, ...]] = ()
    """Physical ports whose across value this block sets (ideal pressure or speed sources)."""
    presets: ClassVar[dict[str, dict[str, float | str]]] = {}
    """Named parameter sets from data sheets or the thesis's tables (``preset:`` in a netlist); values are
    SI numbers or '<number> <unit>' strings; the component's own ``params`` override them."""
    signal_dimensions: ClassVar[dict[str, tuple[str, ...]]] = {}
    """Generic ("SI") signal ports whose dimension is that of parameters as written: a constant's output
    is in its ``value``'s unit, a lookup table's input in its breakpoints'. A netlist whose port on the net
    declares another dimension is refused (a constant of "6 bar" driving a flow source's ``q``)."""
    same_quantity: ClassVar[tuple[tuple[str, ...], ...]] = ()
    """Groups of generic signal ports that carry the same quantity (a filter's input and output, a sum's
    inputs and output): the nets they join share one nominal magnitude (:mod:`blocks.compiler.signal_scale`).
    Only blocks that pass a quantity through declare it; a gain, product, integrator or table does not."""
    checked: ClassVar[tuple[str, ...]] = ()
    """Signals whose valid range :meth:`valid_ranges` gives, each named as an output logs it relative to
    the block (a signal port ``u``, a port's flow ``C1.flow``): they are observed at the output samples,
    and a run in which one leaves its range says so in a warning (a table's input beyond its breakpoints,
    a model outside the range it was fitted on)."""
    regularised: ClassVar[tuple[str, ...]] = ()
    """Signals, named as ``checked``'s are (a port ``port``, a port's flow ``a.flow``), across whose zero the
    block smooths a law that jumps there (a Coulomb friction's sign(v) as tanh(v/v_w)): :meth:`regularisations`
    gives, from the parameters, each one's band and the slope the smoothing gives the law in it. A
    simulation is right to cross such a band (the law outside it is the machine's); a linearisation about a
    point inside it takes the smoothing's slope as the machine's (a friction's Fc/v_w as a damper), and
    `vphs linearise` says so (:mod:`blocks.regularisation`). Only a smoothing whose slope the machine does
    not have is declared: not a square-root orifice law's near dp = 0 (a real orifice is laminar there,
    :func:`blocks.library.hydraulic.flow.turbulent_flow`)."""
    regularised_reads: ClassVar[tuple[str, ...]] = ()
    """Ports or scalar states whose values at the point a regularised law's size reads (a motor's friction,
    (1 - eta_hm)*D*|p_a - p_b|, reads ``a`` and ``b``): observed with the regularised signals."""
    rigid_link: ClassVar[tuple[str, str] | None] = None
    """(a, b): the two ports are joined rigidly, w_b = ratio(params) * w_a (gears, rack and pinion)."""
    outputs: ClassVar[Callable | None] = None
    derivatives: ClassVar[Callable | None] = None
    ratio: ClassVar[Callable | None] = None

    # ---- derived views of the declarations (used by the compiler, the docs and the contract tests) ----
    @classmethod
    def port(cls, name: str) -> Port:
        for p in cls.ports:
            if p.name == name:
                return p
        raise KeyError(name)

    @classmethod
    def signal_inputs(cls) -> list[Port]:
        return [p for p in cls.ports if p.direction == "in"]

    @classmethod
    def signal_outputs(cls) -> list[Port]:
        return [p for p in cls.ports if p.direction == "out"]

    @classmethod
    def physical_ports(cls) -> list[Port]:
        return [p for p in cls.ports if p.physical]

    @classmethod
    def output_names(cls) -> list[str]:
        return [p.name for p in cls.signal_outputs()] + list(cls.prescribes)

    @classmethod
    def through_ports(cls) -> list[Port]:
        linked = set(cls.rigid_link or ())
        return [p for p in cls.physical_ports() if p.name not in cls.prescribes and p.name not in linked]

    @classmethod
    def storing_ports(cls) -> list[Port]:
        return [p for p in cls.physical_ports() if p.stores]

    @classmethod
    def scalar_states(cls) -> list[State]:
        return [s for s in cls.states if s.size is None]

    @classmethod
    def derivative_names(cls) -> list[str]:
        return (
            [f"{THROUGH[p.kind][0]}_{p.name}" for p in cls.through_ports()]
            + [f"{CAPACITY[p.kind][0]}_{p.name}" for p in cls.storing_ports()]
            + [f"der_{s.name}" for s in cls.scalar_states()]
        )

    @classmethod
    def feedthrough(cls) -> list[str]:
        """Signal inputs and physical ports that the outputs read directly (from the signature)."""
        if cls.outputs is None:
            return []
        args = argument_names(cls.outputs)
        return [p.name for p in cls.ports if p.name in args and p.direction != "out"]

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """Checks across parameters (a table's lengths, a lower limit below the upper): None if the
        values fit together, else what is wrong. ``values`` holds each parameter by name and each scalar
        state's start as ``initial.<state>``. Runs when parameter values are evaluated, not per step."""
        return None

    @classmethod
    def breakpoints(cls, values: dict) -> tuple[float, ...]:
        """The times [s] at which this block's outputs jump or kink as functions of time (a step, a
        profile's points), from its parameter ``values`` by name. The solver lands a step on each, so that
        no step jumps over a pulse shorter than itself. Only blocks whose outputs read t declare any."""
        return ()

    @classmethod
    def valid_ranges(cls, values: dict) -> tuple["ValidRange", ...]:
        """Where this block's equations still describe the machine, for the signals it declares ``checked``,
        from its parameter ``values`` by name: a table's breakpoints, a fit's data. Runs once per run, not per
        step. A signal with no range here (this parameter set has none) is not checked."""
        return ()

    @classmethod
    def regularisations(cls, values: dict) -> tuple["Regularisation", ...]:
        """The regularisation band of each signal the block declares ``regularised``, from its parameter
        ``values`` by name (none where these values leave no jump to smooth: a friction of 0). Runs once per
        linearisation, not per step."""
        return ()

    @classmethod
    def parameter_warnings(cls, values: dict) -> tuple[str, ...]:
        """What these parameter ``values`` (by name) take the block outside of what its equations were made
        for, though they are allowed (a setting beyond those a fit was made at): each said as a warning after
        a run, never an error. Runs once per run, not per step."""
        return ()

    @classmethod
    def param(cls, name: str) -> Param:
        for p in cls.params:
            if p.name == name:
                return p
        raise KeyError(name)

    @classmethod
    def summary(cls) -> str:
        doc = inspect.getdoc(cls) or ""
        return doc.splitlines()[0] if doc else ""


@dataclass(frozen=True)
class ValidRange:
    """A checked signal's valid range [lower, upper] (SI), and what the block does outside it, as the
    warning says it: "the table's end value is held", "the jib angle is clamped"."""

    signal: str
    lower: float
    upper: float
    outside: str


@dataclass(frozen=True)
class Regularisation:
    """A regularised signal's band, |signal| < width (SI), in which the block's law is its smoothing's, not
    the machine's, and what a linearisation inside it takes for physics, as the note says it: "fric: the
    point lies inside the Coulomb friction's smoothing band (|v| = 6.59e-06 m/s < 3*v_w = 0.003 m/s): there
    its slope, 3e+05 N*s/m (Fc/v_w = 3e+05 N*s/m at v = 0), is the regularisation's, not physics: a mode
    that moves v takes it for a damper (a real Coulomb friction at rest sticks, or slips once the force on it
    exceeds its breakaway)".

    ``law(s, reads)`` is the smoothed law (the part that jumps, e.g. Fc*tanh(v/v_w)) as a function of the
    signal s [SI] and ``reads``, the point's values of the block's ``regularised_reads`` by name; its slope
    (:meth:`slope`) is the one the linear model takes. ``width_text`` is how the width follows from the
    parameters ("3*v_w"); ``slope_text`` the slope through 0 as a formula ("Fc/v_w") [``slope_unit``];
    ``what`` names the smoothed law ("the Coulomb friction") and ``real`` what the machine does in the band
    instead; ``negligible`` [SI] a slope below which the law is as good as flat (a machine's friction with
    a millibar across it), not said."""

    signal: str
    width: float
    width_text: str
    law: Callable[[float, dict], float]
    slope_text: str
    slope_unit: str
    what: str
    real: str
    negligible: float = 0.0

    def slope(self, s: float, reads: dict) -> float:
        """d(law)/ds at s, by central differences over 1e-4 of the band (the laws are smooth there)."""
        h = 1e-4 * self.width
        return (self.law(s + h, reads) - self.law(s - h, reads)) / (2.0 * h)


def argument_names(function: Callable) -> list[str]:
    return list(inspect.signature(function).parameters)


@dataclass
class Declared:
    """Names an equation function may take, by category (used to validate a block at registration)."""

    names: dict[str, str] = field(default_factory=dict)

    def add(self, name: str, category: str, owner: str) -> None:
        if name in self.names:
            raise TypeError(f"{owner}: '{name}' is declared as both {self.names[name]} and {category}")
        self.names[name] = category


def check_declarations(cls: type[Block]) -> None:
    """Raise TypeError if a block's declarations and equation functions disagree."""
    owner = cls.__name__
    if not (cls.__doc__ and cls.__doc__.strip()):
        raise TypeError(f"{owner}: a block needs a docstring with its equation")
    declared = Declared()
    declared.add("t", "time", owner)
    for p in cls.ports:
        declared.add(p.name, f"{p.kind.value} port", owner)
    for p in cls.params:
        declared.add(p.name, "parameter", owner)
    for s in cls.states:
        declared.add(s.name, "state", owner)
        if s.size is not None:
            declared.add(f"der_{s.name}", "state derivative", owner)
    _check_signal_scale(cls, owner)
    for name in cls.prescribes:
        if name not in {p.name for p in cls.physical_ports()}:
            raise TypeError(f"{owner}: prescribes unknown physical port '{name}'")
    if cls.output_names() and cls.outputs is None:
        raise TypeError(f"{owner}: has outputs {cls.output_names()} but no outputs() function")
    if (cls.derivative_names() or len(cls.scalar_states()) < len(cls.states)) and cls.derivatives is None:
        raise TypeError(f"{owner}: has {cls.derivative_names()} to compute but no derivatives() function")
    for fn_name in ("outputs", "derivatives", "ratio"):
        fn = getattr(cls, fn_name)
        if fn is None:
            continue
        outputs = {p.name for p in cls.signal_outputs()}
        for arg in argument_names(fn):
            if arg not in declared.names:
                raise TypeError(f"{owner}.{fn_name}: argument '{arg}' is not a declared port, parameter or state")
            if arg in outputs:
                raise TypeError(f"{owner}.{fn_name}: argument '{arg}' is one of its own outputs; compute it from "
                                f"states and inputs instead")
    if cls.rigid_link is not None:
        if cls.ratio is None:
            raise TypeError(f"{owner}: a rigid link needs a ratio(...) function of parameters")
        if any(arg not in {p.name for p in cls.params} for arg in argument_names(cls.ratio)):
            raise TypeError(f"{owner}.ratio may take parameters only")
    through = {PortKind.HYDRAULIC: "flow", PortKind.ROTATIONAL: "torque", PortKind.TRANSLATIONAL: "force"}
    for what_kind, refs in (("checked", cls.checked), ("regularised", cls.regularised),
                            ("regularised_reads", tuple(r for r in cls.regularised_reads
                                                        if r not in {st.name for st in cls.states}))):
        for ref in refs:
            port_name, _, what = ref.partition(".")
            port = next((p for p in cls.ports if p.name == port_name), None)
            if port is None or (what and what != through.get(port.kind)):
                raise TypeError(f"{owner}: {what_kind} signal '{ref}' is neither a port of the block nor a "
                                f"physical port's flow, torque or force ('<port>.flow')")
    if cls.checked and cls.valid_ranges.__func__ is Block.valid_ranges.__func__:
        raise TypeError(f"{owner}: declares checked signals {list(cls.checked)} but no valid_ranges()")
    if cls.regularised and cls.regularisations.__func__ is Block.regularisations.__func__:
        raise TypeError(f"{owner}: declares regularised signals {list(cls.regularised)} but no regularisations()")
    names = {p.name for p in cls.params}
    for preset, values in cls.presets.items():
        unknown = set(values) - names
        if unknown:
            raise TypeError(f"{owner}: preset '{preset}' sets unknown parameters {sorted(unknown)}")
    for p in cls.params:
        if p.default is not None and p.fluid is None:
            problem = p.check(p.default)
            if problem:
                raise TypeError(f"{owner}: default out of bounds: {problem}")


def _check_signal_scale(cls: type[Block], owner: str) -> None:
    """A state's ``scale_of`` and the ports of ``same_quantity`` must be generic signal ports of the block."""
    generic = {p.name for p in cls.ports if p.kind is PortKind.SIGNAL and p.unit == "SI"}
    for s in cls.states:
        if s.scale_of is not None and (s.unit != "SI" or s.scale_of not in generic):
            raise TypeError(f"{owner}: state '{s.name}' takes the scale of '{s.scale_of}', which needs a generic "
                            f"(SI) state and a generic signal port of that name")
    for group in cls.same_quantity:
        unknown = [name for name in group if name not in generic]
        if len(group) < 2 or unknown:
            raise TypeError(f"{owner}: same_quantity group {group} needs two or more generic signal ports "
                            f"(not {unknown})")
