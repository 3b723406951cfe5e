"""Units at the edges: parse "207 bar", "30 cm^3/rev", "m^3/(s*Pa)" into SI values with a dimension check.

Everything inside the engine is SI. Units are parsed only where values enter (netlists, data files, command
line) and where they leave (CSV headers, plots, reports).

Dimensions are exponent vectors over (length, mass, time, angle, temperature, current). Angle is kept as a
dimension of its own so that "30 cm^3/rev" converts correctly into a displacement in m^3/rad and "12 Hz"
into an angular frequency in rad/s (1 Hz = 1 rev/s = 2*pi rad/s). The price is strictness: a value in
"N*m*s" does not fit a parameter declared in "N*m*s/rad". Pressures are gauge pressures.

Grammar: products with ``*``, ``·`` or a space, quotients with ``/`` (left-associative, as in arithmetic:
``m^3/s/Pa`` = ``m^3/(s*Pa)``), powers with ``^`` or ``**`` (integer or fraction such as ``^0.5``),
parentheses, and the dimensionless ``1``. ``%`` is 0.01.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache

DIMENSION_NAMES = ("m", "kg", "s", "rad", "K", "A")


@dataclass(frozen=True)
class Unit:
    """A parsed unit: the factor to SI and the dimension exponents."""

    factor: float
    dims: tuple[float, ...]

    def __mul__(self, other: "Unit") -> "Unit":
        return Unit(self.factor * other.factor, tuple(a + b for a, b in zip(self.dims, other.dims)))

    def __truediv__(self, other: "Unit") -> "Unit":
        return Unit(self.factor / other.factor, tuple(a - b for a, b in zip(self.dims, other.dims)))

    def __pow__(self, n: float) -> "Unit":
        return Unit(self.factor**n, tuple(a * n for a in self.dims))

    def same_dimension(self, other: "Unit") -> bool:
        return all(abs(a - b) < 1e-12 for a, b in zip(self.dims, other.dims))

    def describe_dims(self) -> str:
        parts = [f"{n}^{_fmt_exp(e)}" if e != 1 else n for n, e in zip(DIMENSION_NAMES, self.dims) if e]
        return "*".join(parts) if parts else "1"


def _fmt_exp(e: float) -> str:
    return str(int(e)) if float(e).is_integer() else f"{e:g}"


def _base(index: int) -> tuple[float, ...]:
    return tuple(1.0 if i == index else 0.0 for i in range(len(DIMENSION_NAMES)))


_ONE = Unit(1.0, (0.0,) * len(DIMENSION_NAMES))
_M, _KG, _S, _RAD, _K, _A = (Unit(1.0, _base(i)) for i in range(6))
_N = _KG * _M / _S**2
_PA = _N / _M**2
_J = _N * _M
_W = _J / _S
_REV = Unit(2 * math.pi, _RAD.dims)

UNITS: dict[str, Unit] = {
    "1": _ONE, "unit": _ONE, "%": Unit(0.01, _ONE.dims),
    "SI": _ONE,  # declared by generic signal parameters: a value in SI of any dimension (not checked)
    # length, area, volume
    "m": _M, "mm": Unit(1e-3, _M.dims), "cm": Unit(1e-2, _M.dims), "um": Unit(1e-6, _M.dims),
    "km": Unit(1e3, _M.dims), "in": Unit(0.0254, _M.dims),
    "l": Unit(1e-3, (_M**3).dims), "L": Unit(1e-3, (_M**3).dims), "ml": Unit(1e-6, (_M**3).dims),
    "cc": Unit(1e-6, (_M**3).dims),
    # mass
    "kg": _KG, "g": Unit(1e-3, _KG.dims), "t": Unit(1e3, _KG.dims),
    # time
    "s": _S, "ms": Unit(1e-3, _S.dims), "us": Unit(1e-6, _S.dims), "min": Unit(60.0, _S.dims),
    "h": Unit(3600.0, _S.dims),
    # angle and rotation
    "rad": _RAD, "deg": Unit(math.pi / 180, _RAD.dims), "rev": _REV,
    "rpm": _REV / Unit(60.0, _S.dims), "Hz": _REV / _S,
    # force, pressure, energy, power
    "N": _N, "kN": Unit(1e3, _N.dims), "MN": Unit(1e6, _N.dims), "Nm": _N * _M,
    "Pa": _PA, "kPa": Unit(1e3, _PA.dims), "MPa": Unit(1e6, _PA.dims), "GPa": Unit(1e9, _PA.dims),
    "bar": Unit(1e5, _PA.dims), "mbar": Unit(100.0, _PA.dims), "psi": Unit(6894.757293168, _PA.dims),
    "J": _J, "kJ": Unit(1e3, _J.dims), "W": _W, "kW": Unit(1e3, _W.dims),
    # viscosity
    "cSt": Unit(1e-6, (_M**2 / _S).dims), "St": Unit(1e-4, (_M**2 / _S).dims),
    # temperature (differences), current
    "K": _K, "A": _A, "mA": Unit(1e-3, _A.dims),
}

_TOKEN = re.compile(r"\s*(?:(?P<num>\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)|(?P<name>[A-Za-z%]+)|(?P<op>\*\*|[*·/^()-]))")
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_QUANTITY = re.compile(rf"^\s*(?P<value>{_NUMBER})\s*(?P<unit>.*?)\s*$")


GENERIC = "SI"
"""The declared unit of a generic signal parameter (a gain, a limit, a table): any dimension, in SI."""


class UnitError(ValueError):
    """A unit or quantity that cannot be parsed, or has the wrong dimension."""


class UnknownUnitError(UnitError):
    """A name that is not a unit: ``name``, and the units ``near`` it for a 'did you mean' hint. Kept apart so
    that a value that is "<number> <unit>" but for a misspelt unit after an operator ("10 l/mn", which also
    reads as the expression 10 l divided by a parameter mn) can be reported as the misspelt unit it is."""

    def __init__(self, name: str, near: list[str]):
        super().__init__(f"unknown unit '{name}'{did_you_mean(near)}")
        self.name, self.near = name, near


@lru_cache(maxsize=512)
def parse_unit(text: str) -> Unit:
    """Parse a unit expression such as ``"m^3/(s*Pa)"`` into a :class:`Unit`."""
    text = text.strip()
    if not text:
        return _ONE
    tokens = _tokenize(text)
    try:
        unit, pos = _parse_product(tokens, 0, text)
    except OverflowError:
        raise UnitError(f"unit '{text}' is too large") from None
    if pos != len(tokens):
        raise UnitError(f"unexpected '{tokens[pos][1]}' in unit '{text}'")
    return unit


def _tokenize(text: str) -> list[tuple[str, str]]:
    tokens, pos = [], 0
    text = text.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise UnitError(f"cannot read '{text[pos:].strip()}' in unit '{text}'")
        kind = m.lastgroup
        tokens.append((kind, m.group(kind)))
        pos = m.end()
    return tokens


def _parse_product(tokens, pos, text):
    unit, pos = _parse_power(tokens, pos, text)
    while pos < len(tokens):
        kind, tok = tokens[pos]
        if tok in ("*", "·"):
            rhs, pos = _parse_power(tokens, pos + 1, text)
            unit = unit * rhs
        elif tok == "/":
            rhs, pos = _parse_power(tokens, pos + 1, text)
            unit = unit / rhs
        elif kind == "name" or tok == "(":
            rhs, pos = _parse_power(tokens, pos, text)  # juxtaposition: "N m"
            unit = unit * rhs
        else:
            break
    return unit, pos


def _parse_power(tokens, pos, text):
    unit, pos = _parse_atom(tokens, pos, text)
    if pos < len(tokens) and tokens[pos][1] in ("^", "**"):
        pos += 1
        sign = 1.0
        if pos < len(tokens) and tokens[pos][1] == "(":
            # exponent in parentheses, e.g. m^(1/2) is not supported beyond a plain number
            raise UnitError(f"write exponents as plain numbers in unit '{text}'")
        if pos < len(tokens) and tokens[pos][1] == "-":
            sign, pos = -1.0, pos + 1
        if pos >= len(tokens) or tokens[pos][0] != "num":
            raise UnitError(f"missing exponent in unit '{text}'")
        exponent = sign * float(tokens[pos][1])
        if abs(exponent) > 12:
            raise UnitError(f"exponent {exponent:g} in unit '{text}' is implausible")
        unit = unit ** exponent
        pos += 1
    return unit, pos


def _parse_atom(tokens, pos, text):
    if pos >= len(tokens):
        raise UnitError(f"unit '{text}' ends too early")
    kind, tok = tokens[pos]
    if tok == "(":
        unit, pos = _parse_product(tokens, pos + 1, text)
        if pos >= len(tokens) or tokens[pos][1] != ")":
            raise UnitError(f"unbalanced parenthesis in unit '{text}'")
        return unit, pos + 1
    if kind == "num":
        if float(tok) != 1.0:
            raise UnitError(f"a number ({tok}) inside unit '{text}' is not allowed")
        return _ONE, pos + 1
    if kind == "name":
        if tok not in UNITS:
            raise UnknownUnitError(tok, nearest(tok, UNITS))
        return UNITS[tok], pos + 1
    raise UnitError(f"unexpected '{tok}' in unit '{text}'")


_NAMED = (("m", "a length"), ("m/s", "a velocity"), ("Pa", "a pressure"), ("rad", "an angle"),
          ("rad/s", "an angular velocity"), ("N", "a force"), ("N*m", "a torque (or energy)"), ("m^3/s", "a flow"),
          ("s", "a time"), ("kg", "a mass"), ("m^3", "a volume"), ("m^2", "an area"), ("m^3/rad", "a displacement"),
          ("K", "a temperature"), ("A", "a current"), ("W", "a power"))


def si_name(dims: Unit) -> str:
    """'m', 'Pa', 'm^3/s'... for the SI unit of a dimension, or its base-unit description ("1": a plain number)."""
    for name, _ in _NAMED:
        unit = parse_unit(name)
        if unit.same_dimension(dims):
            return name
    return dims.describe_dims()


def quantity_name(dims: Unit) -> str:
    """What a dimension is, for messages: 'a pressure', 'a flow', 'a plain number', else 'a quantity in kg*m^-3'."""
    if dims.same_dimension(_ONE):
        return "a plain number"
    for name, what in _NAMED:
        if parse_unit(name).same_dimension(dims):
            return what
    return f"a quantity in {dims.describe_dims()}"


def nearest(name: str, choices, n: int = 3) -> list[str]:
    """The closest names to ``name`` among ``choices`` (for 'did you mean' hints), ignoring case first.

    A name without a dot is also compared with each dotted choice's last part, so that ``zeta2`` finds
    ``relief.zeta`` (whose whole name is too long to look alike) before ``ret.A`` (which looks alike by
    three letters in five). A tie goes to the whole name's likeness (``k_z``: ``k_s`` before ``relief.k_s``)."""
    import difflib

    choices = list(choices)
    same = [c for c in choices if c.lower() == name.lower()]
    wanted = name.lower()
    scored = {}  # as difflib.get_close_matches: the best first, then in reverse order of the lowered name
    for choice in choices:
        lowered = choice.lower()
        parts = [lowered] + ([lowered.rsplit(".", 1)[1]] if "." in lowered and "." not in wanted else [])
        scores = [difflib.SequenceMatcher(None, part, wanted).ratio() for part in parts]
        if scores[0] >= 0.6 or max(scores) >= 0.75:  # a short last part looks alike by chance more easily
            scored[lowered] = (max(scores), scores[0], lowered, choice)
    close = [entry[-1] for entry in sorted(scored.values(), reverse=True)[:n]]
    return list(dict.fromkeys(same + close))[:n]


def did_you_mean(near: list[str]) -> str:
    """" (did you mean a, b?)" for the names ``near`` a misspelt one, "" if there are none."""
    return f" (did you mean {', '.join(near)}?)" if near else ""


def display_factor(unit: str) -> float:
    """The SI factor of a display unit ("bar" -> 1e5); 1 for a dimensionless or SI-marked one ("", "1", "SI")."""
    return 1.0 if unit in ("", "1", "SI") else parse_unit(unit).factor


def to_si(value: float, unit: str) -> float:
    """Convert ``value`` given in ``unit`` to SI."""
    return value * parse_unit(unit).factor


def from_si(value, unit: str):
    """Convert an SI value (or array) to ``unit``."""
    return value / parse_unit(unit).factor


def quantity(value, declared_unit: str) -> float:
    """Read a netlist value into SI for a parameter declared in ``declared_unit``.

    A number is taken as SI already. A string is "<number> <unit>"; its unit must have the dimension of
    ``declared_unit``; a bare number in a string ("0.7") is SI too.
    """
    if isinstance(value, bool):
        raise UnitError(f"expected a number, got {value!r}")
    if isinstance(value, (int, float)):
        return float(value)
    if not isinstance(value, str):
        raise UnitError(f"expected a number or a '<number> <unit>' string, got {value!r}")
    number, unit_text = split_quantity(value)
    if not unit_text:
        return number
    return convert(number, unit_text, declared_unit)


def convert(number: float, unit_text: str, declared_unit: str) -> float:
    """Convert ``number`` in ``unit_text`` to SI, checking it has the dimension of ``declared_unit``.

    Declared units are SI-coherent (factor 1: "Pa", "m^3/rad", "rad/s"), so the SI value is the number times
    the factor of the given unit.
    """
    given = parse_unit(unit_text)
    declared = parse_unit(declared_unit)
    if declared_unit == GENERIC:
        return number * given.factor
    if not given.same_dimension(declared):
        raise UnitError(
            f"wrong unit '{unit_text}' ({given.describe_dims()}): expected a quantity in {declared_unit} "
            f"({declared.describe_dims()})"
        )
    return number * given.factor


def si_value(raw, dims: "Unit | None" = None) -> float:
    """A number (SI) or '<number> <unit>' in SI, its unit checked against ``dims`` where that is given."""
    if isinstance(raw, (int, float)) and not isinstance(raw, bool):
        return float(raw)
    number, unit_text = split_quantity(str(raw))
    unit = parse_unit(unit_text)
    if unit_text and dims is not None and not unit.same_dimension(dims):
        raise UnitError(f"wrong unit: '{raw}' is in {unit.describe_dims()}, expected {dims.describe_dims()}")
    return number * unit.factor


def split_quantity(text: str) -> tuple[float, str]:
    """Split "207 bar" into (207.0, "bar"); a bare number gives unit ""."""
    comma = decimal_comma(text)
    if comma:
        raise UnitError(comma)
    m = _QUANTITY.match(text)
    if not m:
        raise UnitError(f"'{text}' is not '<number> <unit>'")
    return float(m.group("value")), m.group("unit")


def decimal_comma(text: str) -> str | None:
    """What is wrong with a number written with a decimal comma ("150,5 bar"), else None.

    Only a comma between digits outside any parentheses counts: there it can be nothing else (a value is
    one number), while in ``max(1,2)`` it separates arguments. Said in words, as the expression parser
    would only see a tuple of two numbers."""
    for m in re.finditer(r"(?<![\w.])(\d+),(\d+)", text):
        if text.count("(", 0, m.start(2)) == text.count(")", 0, m.start(2)):
            whole, decimals = m.groups()
            thousands = f", or {whole}{decimals} without a thousands separator" if len(decimals) == 3 else ""
            return f"',' is not a decimal point in '{text}' (write {whole}.{decimals}{thousands})"
    return None


_INLINE_NUMBER = r"(?<![\w.])(?P<value>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
_INLINE_UNIT = (r"(?P<unit>[A-Za-z%][A-Za-z0-9%]*(?:(?:\^|\*\*)-?\d+(?:\.\d+)?)?"
                r"(?:[*/·][A-Za-z%][A-Za-z0-9%]*(?:(?:\^|\*\*)-?\d+(?:\.\d+)?)?)*)")
_INLINE_QUANTITY = re.compile(
    # a number, a space, then a unit written without spaces ("30 cm^3/rev", "1e-12 m^3/(s*Pa)" is not
    # supported inside expressions): "1000 kg * g" keeps g a parameter name, not a gram, and "1 bar/A.initial"
    # reads the dotted name A.initial, not a unit bar/A
    _INLINE_NUMBER + r"\s+" + _INLINE_UNIT + r"(?![\w(.])"
)
UNSPACED_QUANTITY = re.compile(_INLINE_NUMBER + r"(?![eE][-+]?\d)" + _INLINE_UNIT)
"""A number written against what may be its unit ("10bar" in "p_c+10bar"): not a quantity inside an expression,
where the unit follows its number after a space; looked for only to say so (an exponent, "1e5", is no unit)."""


_LITERAL_NAMES = __import__("itertools").count()


def substitute_quantities(text: str, unknown: dict | None = None) -> tuple[str, dict[str, tuple[float, Unit, str]]]:
    """Replace each "<number> <unit>" inside an expression by a placeholder name; return the new text and
    the placeholders' SI values, units and written text (so the dimension of the expression can be checked,
    and messages can show what was written, not the placeholder).

    ``"23000 kg + m_payload"`` -> ``("_q7 + m_payload", {"_q7": (23000.0, kg, "23000 kg")})``. A unit must
    follow its number after a space; text that is not a known unit is left alone ("3 bar * k": the unit is
    "bar"). ``unknown``, if given, receives each name written as a unit that is none, with its
    :class:`UnknownUnitError` and the quantity as written ("barr": (..., "10 barr") in "p_c + 10 barr"; "mn":
    (..., "10 l/mn") in "2*10 l/mn"), so that a message can say the misspelt unit.
    """
    literals: dict[str, tuple[float, Unit, str]] = {}
    unknown = {} if unknown is None else unknown

    def replace(match: re.Match) -> str:
        unit_text = match.group("unit")
        cuts = [m.start() for m in re.finditer(r"\s*[*/·]", unit_text)] + [len(unit_text)]
        for cut in reversed(cuts):
            try:
                unit = parse_unit(unit_text[:cut])
            except UnknownUnitError as exc:
                unknown.setdefault(exc.name, (exc, match.group(0)))
                continue
            except UnitError:
                continue
            name = f"_q{next(_LITERAL_NAMES)}"
            literals[name] = (float(match.group("value")) * unit.factor, unit,
                              f"{match.group('value')} {unit_text[:cut]}")
            return f"{name}{unit_text[cut:]}"
        return match.group(0)

    return _INLINE_QUANTITY.sub(replace, text), literals
