"""Contract tests that walk the block registry: every registered type, generic or the crane's, is checked.

What a block promises (see :mod:`blocks.block`), checked here for all of them at once, so that a new block
cannot forget one of it:

- documentation: a class docstring with a one-line summary and the equation below it, a description for
  every port, parameter and state, a module docstring;
- units: every declared unit parses and is SI-coherent (factor 1: "Pa", not "bar"); bounds are ordered and
  defaults lie inside them;
- declarations: the equation functions are static, take declared names only, and return tuples of the
  declared lengths;
- finite values at a plausible default point (parameters at their defaults or inside their bounds,
  states at their start, signal inputs 0.5, pressures 50 and 20 bar, speeds 1);
- honest feedthrough: every input that ``outputs`` takes (its declared direct feedthrough) does change
  an output at some tried operating point; an input it does not take cannot, by construction;
- numba: both equation functions compile with ``numba.njit`` and agree with the Python call;
- tolerance scale: every generic ("SI") state names the signal port whose quantity it carries
  (``State.scale_of``, so that its absolute tolerance is that quantity's), or is listed with a reason;
- the registry: names are unique, and registering a block whose function takes an undeclared name fails.
"""

from __future__ import annotations

import inspect
import itertools
import math
import sys

import numba
import numpy as np
import pytest

from blocks import registry
from blocks.block import CAPACITY, Block, Param, State, argument_names, check_declarations, signal_in, signal_out
from blocks.netlist.spec import Fluid
from blocks.units import parse_unit, quantity

TYPES = registry.all_types()
NAMES = list(TYPES)

# The fluid a component reads when the netlist's `fluid:` section is left at its defaults.
FLUID = {key: quantity(getattr(Fluid(), key), unit) for key, unit in
         (("rho", "kg/m^3"), ("nu", "m^2/s"), ("beta", "Pa"), ("vapour_pressure", "Pa"))}
FLUID["cavitation_pressure"] = FLUID["vapour_pressure"]  # derived: with the cavitation law on (the default)

# Parameter values for blocks whose required parameters need more than "inside the bounds" to be a valid,
# non-degenerate operating point (their check_values asks for it, or the generic value makes the block
# constant). Everything else is found by `plausible_scalar` / DEFAULT_TABLE.
PLAUSIBLE: dict[str, dict[str, float | tuple]] = {
    "saturation": {"lower": -1.0, "upper": 1.0},  # lower = upper = 1 would be a constant
    "dead_band": {"lower": -0.2, "upper": 0.2},
    "lookup_2d": {"x_table": (0.0, 1.0, 2.0), "y_table": (0.0, 1.0),
                  "z_table": (0.0, 1.0, 2.0, 4.0, 3.0, 7.0)},  # 3 x 2 grid
    "transfer_function": {"num": (0.5, 1.0, 2.0), "den": (1.0, 3.0, 2.0)},  # biproper: b_0 != 0
    "transfer_function_strict": {"num": (1.0, 2.0), "den": (1.0, 3.0, 2.0)},
    # p_open > p_set is required (the bounds cannot say it): the generic 1 Pa, 1 Pa would be a bare step
    "relief_valve": {"p_set": 30e5, "p_open": 40e5},
    # the generic d1_0 = 1 m gives a cylinder shorter than the jib's angle range allows (2.2 ... 3.0 m): clamped,
    # the jib would not turn and its speed would move no output
    "lga_jib_load": {"d1_0": 2.1},
}
DEFAULT_TABLE = (0.0, 1.0, 2.0)  # an array parameter nobody chose a value for: strictly increasing

# Inputs a block reads in `outputs` although changing them changes no output at any tried point, each with
# the reason it is still right to declare it. Empty: every declared feedthrough was found to be real.
FEEDTHROUGH_EXCEPTIONS: dict[tuple[str, str], str] = {}

# Generic ("SI") states that name no port for their tolerance scale (they keep their declared nominal 1),
# each with the reason no port's quantity is theirs.
UNSCALED_STATES: dict[tuple[str, str], str] = {
    ("transfer_function", "x"): "the canonical-form state x[k] is u filtered by s^(n-1-k)/den(s): its size "
                                "is u's times den's coefficients' units and values, not u's quantity",
    ("transfer_function_strict", "x"): "as transfer_function's",
}

HYDRAULIC_BASE = (50e5, 20e5, 35e5, 5e5)  # the k-th hydraulic port of a block (cycled)
SIGNAL_SPREAD = (0.5, -0.3, 1.7, 0.9, -1.1)  # the k-th signal input at the second operating point
PERTURB = {"signal": (-0.7, 2.0, 0.0, 10.0), "hydraulic": (50e5, 0.0, -0.5e5, 200e5, 21e5),
           "rotational": (-0.7, 2.0, 0.0), "translational": (-0.7, 2.0, 0.0)}
T = 0.25


# ---------------------------------------------------------------- building a default point
def plausible_scalar(p: Param) -> float:
    """A value inside the bounds: the geometric mean of two positive bounds, else 1.0 clipped into them."""
    lo, hi = p.lower, p.upper
    if lo is not None and hi is not None and lo > 0.0 and hi > 0.0:
        value = math.sqrt(lo * hi)
    else:
        value = min(max(1.0, -math.inf if lo is None else lo), math.inf if hi is None else hi)
    return float(round(value)) if p.integer else value


def default_params(cls: type[Block]) -> dict:
    """Every parameter's value at the default point (floats; float64 arrays for array parameters)."""
    chosen = PLAUSIBLE.get(cls.type_name, {})
    values = {}
    for p in cls.params:
        if p.name in chosen:
            value = chosen[p.name]
        elif p.fluid is not None:
            value = FLUID[p.fluid]
        elif p.default is not None:
            value = p.default
        elif p.array:
            value = DEFAULT_TABLE
        else:
            value = plausible_scalar(p)
        values[p.name] = np.asarray(value, dtype=float) if p.array else float(value)
    return values


def array_lengths(cls: type[Block], params: dict) -> dict[str, int]:
    return {p.name: len(params[p.name]) for p in cls.params if p.array}


def operating_points(cls: type[Block]) -> list[dict]:
    """Argument sets for the equation functions: a default point and one with every input different."""
    params = default_params(cls)
    lengths = array_lengths(cls, params)
    base = {"t": T, **params}
    for s in cls.states:
        if s.size is None:
            base[s.name] = float(s.start)
        else:
            n = s.size(lengths)
            base[s.name] = np.zeros(n)
            base[f"der_{s.name}"] = np.zeros(n)
    points = []
    for spread in (False, True):
        point = dict(base)
        k_signal = k_hyd = 0
        for port in cls.ports:
            if port.direction == "out":
                continue
            if port.direction == "in":
                point[port.name] = SIGNAL_SPREAD[k_signal % len(SIGNAL_SPREAD)] if spread else 0.5
                k_signal += 1
            elif port.kind.value == "hydraulic":
                point[port.name] = HYDRAULIC_BASE[k_hyd % len(HYDRAULIC_BASE)]
                if spread:
                    point[port.name] *= 1.0 + 0.13 * k_hyd
                k_hyd += 1
            else:
                point[port.name] = 1.0 if not spread else -0.4
        points.append(point)
    return points


def call(fn, values: dict):
    """Call an equation function as the compiler does: by argument name (array views copied)."""
    return fn(*[_fresh(values[name]) for name in argument_names(fn)])


def _fresh(value):
    return value.copy() if isinstance(value, np.ndarray) else value


def inputs_of(cls: type[Block]) -> list:
    return [p for p in cls.ports if p.direction != "out"]


def all_finite(values) -> bool:
    return all(math.isfinite(float(v)) for v in values)


# ---------------------------------------------------------------- documentation
@pytest.mark.parametrize("name", NAMES)
def test_documentation(name):
    cls = TYPES[name]
    doc = inspect.cleandoc(cls.__doc__ or "")  # the class's own docstring, not Block's
    lines = [line for line in doc.splitlines() if line.strip()]
    assert lines, f"{name}: no class docstring"
    assert lines[0].strip() and len(lines[0]) <= 140, f"{name}: the summary line should be one short line"
    assert len(lines) > 1, f"{name}: the docstring has only its summary; it needs the equation below it"
    assert cls.summary() == doc.splitlines()[0]
    for p in cls.ports:
        assert p.description.strip(), f"{name}: port '{p.name}' has no description"
    for p in cls.params:
        assert p.description.strip(), f"{name}: parameter '{p.name}' has no description"
    for s in cls.states:
        assert s.description.strip(), f"{name}: state '{s.name}' has no description"
    module = sys.modules[cls.__module__]
    assert (module.__doc__ or "").strip(), f"{name}: module {cls.__module__} has no docstring"


# ---------------------------------------------------------------- units and bounds
def _assert_si(name: str, what: str, unit: str) -> None:
    parsed = parse_unit(unit)  # raises UnitError if it does not parse
    assert math.isclose(parsed.factor, 1.0, rel_tol=1e-12), \
        f"{name}: {what} is declared in '{unit}' (factor {parsed.factor:g} to SI); declare it in SI"


@pytest.mark.parametrize("name", NAMES)
def test_units_are_si(name):
    cls = TYPES[name]
    for p in cls.params:
        _assert_si(name, f"parameter '{p.name}'", p.unit)
    for s in cls.states:
        _assert_si(name, f"state '{s.name}'", s.unit)
    for p in cls.ports:
        _assert_si(name, f"port '{p.name}'", p.unit_of_value)
        if p.physical:
            assert p.unit == "SI", f"{name}: physical port '{p.name}' declares unit '{p.unit}', which is unused " \
                                  f"(it carries {p.unit_of_value})"


@pytest.mark.parametrize("name", NAMES)
def test_bounds_and_defaults(name):
    cls = TYPES[name]
    for p in cls.params:
        if p.lower is not None and p.upper is not None:
            assert p.lower <= p.upper, f"{name}: parameter '{p.name}' has lower {p.lower:g} > upper {p.upper:g}"
        for bound in (p.lower, p.upper):
            assert bound is None or not math.isnan(bound), f"{name}: parameter '{p.name}' has a NaN bound"
        if p.default is not None:
            assert isinstance(p.default, tuple) == p.array, \
                f"{name}: parameter '{p.name}': an array parameter's default is a tuple, a scalar's a number"
            assert p.check(p.default) is None, f"{name}: {p.check(p.default)}"
        if p.fluid is not None:
            assert p.fluid in FLUID, f"{name}: parameter '{p.name}' names an unknown fluid property '{p.fluid}'"
            assert p.check(FLUID[p.fluid]) is None, f"{name}: the default fluid's {p.fluid} is out of bounds"
    for s in cls.states:
        assert math.isfinite(s.start), f"{name}: state '{s.name}' starts at {s.start}"
        assert math.isfinite(s.nominal) and s.nominal > 0, \
            f"{name}: state '{s.name}' has nominal {s.nominal} (must be finite and > 0: it scales atol)"


# ---------------------------------------------------------------- declarations
@pytest.mark.parametrize("name", NAMES)
def test_declarations(name):
    cls = TYPES[name]
    assert cls.type_name == name
    declared = {"t"} | {p.name for p in cls.ports} | {p.name for p in cls.params} | {s.name for s in cls.states}
    declared |= {f"der_{s.name}" for s in cls.states if s.size is not None}
    for fn_name in ("outputs", "derivatives", "ratio"):
        if getattr(cls, fn_name) is None:
            continue
        assert isinstance(inspect.getattr_static(cls, fn_name), staticmethod), \
            f"{name}.{fn_name} must be a @staticmethod (the generated code calls it on the class)"
        undeclared = set(argument_names(getattr(cls, fn_name))) - declared
        assert not undeclared, f"{name}.{fn_name} takes undeclared names {sorted(undeclared)}"
    if cls.outputs is not None:
        # outputs never read what they compute: a signal output, or a port whose across value they prescribe
        computed = {p.name for p in cls.signal_outputs()} | set(cls.prescribes)
        assert not computed & set(argument_names(cls.outputs)), \
            f"{name}.outputs reads what it computes: {sorted(computed & set(argument_names(cls.outputs)))}"
    ports = [p.name for p in cls.ports]
    assert len(ports) == len(set(ports)), f"{name}: duplicate port names"
    for port, given_by in cls.signal_dimensions.items():
        # a generic signal port whose dimension generic parameters give (blocks/netlist/signal_dimensions.py)
        assert port in ports and cls.port(port).kind.value == "signal" and cls.port(port).unit == "SI", \
            f"{name}.signal_dimensions: '{port}' is not a generic signal port"
        for param in given_by:
            assert cls.param(param).unit == "SI", f"{name}.signal_dimensions: '{param}' is not a generic parameter"

    params = default_params(cls)
    for p in cls.params:
        assert p.check(tuple(params[p.name]) if p.array else params[p.name]) is None, \
            f"{name}: the test's default point is out of bounds: {p.check(params[p.name])}"
    problem = cls.check_values(params)
    assert problem is None, f"{name}: the test's default point fails check_values ({problem}); add it to PLAUSIBLE"
    point = operating_points(cls)[0]
    if cls.outputs is not None:
        out = call(cls.outputs, point)
        assert isinstance(out, tuple) and len(out) == len(cls.output_names()), \
            f"{name}.outputs returned {out!r}, expected a tuple of {cls.output_names()}"
    else:
        assert not cls.output_names()
    if cls.derivatives is not None:
        der = call(cls.derivatives, point)
        assert isinstance(der, tuple) and len(der) == len(cls.derivative_names()), \
            f"{name}.derivatives returned {der!r}, expected a tuple of {cls.derivative_names()}"
    if cls.rigid_link is not None:
        ratio = call(cls.ratio, point)
        assert math.isfinite(ratio) and ratio != 0.0, f"{name}.ratio = {ratio} at the default point"


# ---------------------------------------------------------------- breakpoints of inputs in time
SMOOTH_IN_TIME = {"clock": "y = t, smooth"}  # blocks reading t with no jump or kink to declare


@pytest.mark.parametrize("name", NAMES)
def test_a_block_that_reads_time_declares_where_it_jumps_or_kinks(name):
    # the solver lands a step on each breakpoint (blocks/solve/rosenbrock.py); a time block that declared
    # none would let a step jump over its pulse (a 5 ms pulse in a 5 s run gave 0 bar instead of 6.5)
    cls = TYPES[name]
    reads_t = any("t" in argument_names(fn) for fn in (cls.outputs, cls.derivatives) if fn is not None)
    declares = cls.breakpoints.__func__ is not Block.breakpoints.__func__
    if reads_t and name not in SMOOTH_IN_TIME:
        assert declares, f"{name} reads t: declare the times its outputs jump or kink (Block.breakpoints)"
    if declares:
        times = cls.breakpoints(default_params(cls))
        assert all(isinstance(t, float) and math.isfinite(t) for t in times), times


# ---------------------------------------------------------------- finite at the default point
@pytest.mark.parametrize("name", NAMES)
def test_finite_at_defaults(name):
    cls = TYPES[name]
    for point in operating_points(cls):
        if cls.outputs is not None:
            out = call(cls.outputs, point)
            assert all_finite(out), f"{name}.outputs = {out} at {point}"
        if cls.derivatives is not None:
            args = {k: _fresh(v) for k, v in point.items()}
            der = cls.derivatives(*[args[a] for a in argument_names(cls.derivatives)])
            assert all_finite(der), f"{name}.derivatives = {der} at {point}"
            for s in cls.states:
                if s.size is not None:
                    filled = args[f"der_{s.name}"]
                    assert np.all(np.isfinite(filled)), f"{name}: der_{s.name} = {filled}"
            returned = dict(zip(cls.derivative_names(), der))
            for p in cls.storing_ports():
                key = f"{CAPACITY[p.kind][0]}_{p.name}"
                assert returned[key] >= 0.0, f"{name}: negative capacity {key} = {returned[key]}"


# ---------------------------------------------------------------- honest feedthrough
@pytest.mark.parametrize("name", NAMES)
def test_feedthrough_is_honest(name):
    cls = TYPES[name]
    feed = cls.feedthrough()
    read = set(argument_names(cls.outputs)) if cls.outputs is not None else set()
    for port in inputs_of(cls):
        # inputs outside the signature cannot affect the outputs: they are never passed to them
        assert (port.name in feed) == (port.name in read), f"{name}: feedthrough() disagrees with the signature"
    for input_name in feed:
        port = cls.port(input_name)
        changed = False
        for point in operating_points(cls):
            reference = call(cls.outputs, point)
            for value in PERTURB[port.kind.value]:
                moved = call(cls.outputs, {**point, input_name: value})
                if any(not math.isclose(a, b, rel_tol=1e-12, abs_tol=0.0) for a, b in zip(reference, moved)):
                    changed = True
                    break
            if changed:
                break
        if not changed:
            assert (name, input_name) in FEEDTHROUGH_EXCEPTIONS, (
                f"{name}: outputs() takes '{input_name}' (declared direct feedthrough) but no output changed "
                f"when it was moved at any tried point: a false feedthrough creates false algebraic loops; "
                f"drop it from the signature or list it in FEEDTHROUGH_EXCEPTIONS with the reason")


def test_feedthrough_exceptions_are_current():
    for (name, input_name), reason in FEEDTHROUGH_EXCEPTIONS.items():
        assert name in TYPES and input_name in TYPES[name].feedthrough() and reason


# ---------------------------------------------------------------- tolerance scale
@pytest.mark.parametrize("name", NAMES)
def test_a_generic_state_names_the_port_whose_scale_it_has(name):
    cls = TYPES[name]
    generic_signals = {p.name for p in cls.ports if p.direction is not None and p.unit == "SI"}
    for s in cls.states:
        if s.unit != "SI":
            assert s.scale_of is None, f"{name}.{s.name} is declared in {s.unit}: its nominal is its own"
        elif (name, s.name) in UNSCALED_STATES:
            assert s.scale_of is None, f"{name}.{s.name} names a port: drop it from UNSCALED_STATES"
        else:
            assert s.scale_of in generic_signals, (
                f"{name}.{s.name} is a generic (SI) state: name the generic signal port whose quantity it "
                f"carries (State(..., scale_of=...)) so that its tolerance is that quantity's, or list it in "
                f"UNSCALED_STATES with the reason")
    for group in cls.same_quantity:
        assert len(group) >= 2 and set(group) <= generic_signals, f"{name}: same_quantity {group}"


@pytest.mark.parametrize("states, same_quantity, message", [
    ((State("x", "SI", 0.0, 1.0, "state", scale_of="v"),), (), "takes the scale of 'v'"),
    ((State("x", "m", 0.0, 0.1, "state", scale_of="u"),), (), "needs a generic"),
    ((), (("u", "w"),), "same_quantity"),
    ((), (("u",),), "same_quantity"),
])
def test_a_scale_must_name_generic_signal_ports(states, same_quantity, message):
    class Scaled(Block):
        """Throwaway block for the scale declarations: y = u.

        y = u
        """

        ports = (signal_in("u", "input"), signal_out("y", "output"))

        @staticmethod
        def outputs(u):
            return (u,)

    Scaled.states, Scaled.same_quantity = states, same_quantity
    if states:
        Scaled.derivatives = staticmethod(lambda u: (u,))
    with pytest.raises(TypeError, match=message):
        check_declarations(Scaled)


def test_unscaled_states_are_current():
    for (name, state), reason in UNSCALED_STATES.items():
        assert name in TYPES and reason
        assert any(s.name == state and s.unit == "SI" for s in TYPES[name].states), (name, state)


# ---------------------------------------------------------------- numba
_NUMBA_CACHE: dict = {}


def _jit(fn):
    if fn not in _NUMBA_CACHE:
        _NUMBA_CACHE[fn] = numba.njit(fn)
    return _NUMBA_CACHE[fn]


@pytest.mark.parametrize("name", NAMES)
def test_numba_compiles_and_agrees(name):
    cls = TYPES[name]
    for point, fn_name in itertools.product(operating_points(cls), ("outputs", "derivatives", "ratio")):
        fn = getattr(cls, fn_name)
        if fn is None:
            continue
        args = [_fresh(point[a]) for a in argument_names(fn)]
        compiled_args = [_fresh(a) for a in args]
        expected = fn(*args)
        got = _jit(fn)(*compiled_args)
        if fn_name == "ratio":
            expected, got = (expected,), (got,)
        assert len(got) == len(expected), f"{name}.{fn_name}: numba returned {got!r}, Python {expected!r}"
        np.testing.assert_allclose(np.asarray(got, dtype=float), np.asarray(expected, dtype=float),
                                   rtol=1e-12, atol=0.0, err_msg=f"{name}.{fn_name}: numba disagrees with Python")
        for a, b in zip(args, compiled_args):  # der_x arrays filled in place must agree too
            if isinstance(a, np.ndarray):
                np.testing.assert_allclose(b, a, rtol=1e-12, atol=0.0, err_msg=f"{name}.{fn_name}: array argument")


# ---------------------------------------------------------------- the registry itself
def test_registry_names_unique():
    classes = list(TYPES.values())
    assert len(set(classes)) == len(classes), "a block class is registered under two names"
    assert all(cls.type_name == name for name, cls in TYPES.items())
    assert len({name.lower() for name in TYPES}) == len(TYPES), "type names differ only by case"
    for name in TYPES:
        assert name.isidentifier() and name == name.lower(), f"type name '{name}' is not a lower-case identifier"


def _throwaway(bad: bool):
    class Throwaway(Block):
        """Throwaway block for the registry test: y = k*u.

        y = k*u
        """

        ports = (signal_in("u", "input"), signal_out("y", "output"))
        params = (Param("k", "1", 1.0, None, None, "gain"),)

        if bad:
            @staticmethod
            def outputs(u, k, gain):  # 'gain' is not declared
                return (k * u * gain,)
        else:
            @staticmethod
            def outputs(u, k):
                return (k * u,)

    return Throwaway


def test_register_rejects_undeclared_argument():
    type_name = "__contract_test_undeclared__"
    try:
        with pytest.raises(TypeError, match="gain"):
            registry.register(type_name)(_throwaway(bad=True))
        assert type_name not in registry._REGISTRY, "a rejected block must not stay registered"
    finally:
        registry._REGISTRY.pop(type_name, None)


def test_register_rejects_a_taken_name_and_accepts_a_good_block():
    type_name = "__contract_test_good__"
    taken = NAMES[0]
    try:
        with pytest.raises(TypeError, match="registered twice"):
            registry.register(taken)(_throwaway(bad=False))
        assert registry._REGISTRY[taken] is TYPES[taken]
        cls = registry.register(type_name)(_throwaway(bad=False))
        assert registry.get(type_name) is cls and cls.feedthrough() == ["u"]
    finally:
        registry._REGISTRY.pop(type_name, None)
    assert type_name not in registry.all_types()

