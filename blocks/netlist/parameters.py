"""The parameter table of a flat circuit: every named value, its source text and how to evaluate it.

Names are qualified: ``m_load`` (a netlist parameter), ``valve.A_max`` (a component parameter),
``left.valve.A_max`` (inside subsystem ``left``), ``A.volume``, ``A.initial``, ``valve.initial.x``,
``fluid.rho``. Each entry is a constant or an expression over other names of its scope. Evaluation walks
them in dependency order (networkx), so that an optimiser can override any name, ``m_load`` included, and
every value that depends on it follows, without rebuilding the circuit.

Dimensions: a value written with a unit ("7500 kg") carries its dimension; a bare number is free (it is
the SI value of whatever the place needs). Expressions propagate dimensions (products multiply them, sums
must agree, a free number adapts), so ``A_max: m_load`` or ``p: "100 bar + 5 m"`` is a wrong-unit error,
while ``J: "0.085 + m_load*r**2/n**2"`` with a free ``n`` and ``0.085`` is accepted.
"""

from __future__ import annotations

import ast
import math
import re
from dataclasses import dataclass, field

import networkx as nx
import numpy as np

from blocks.errors import NetlistError, VphsError
from blocks.expressions import Expression, ExpressionError, dotted_name, parse_expression
from blocks.netlist.yaml_source import Located
from blocks.units import (_QUANTITY, GENERIC, UNSPACED_QUANTITY, Unit, UnitError, UnknownUnitError, decimal_comma,
                          did_you_mean, nearest, parse_unit, quantity, quantity_name, si_name, split_quantity,
                          substitute_quantities)

FREE = None  # dimension of a bare number: adapts to its place


EVALUATED_ONCE = "an expression here is evaluated once, with the netlist's values; write it in the netlist"
"""Why an expression given from outside the netlist may not read what changes (:meth:`ParameterTable.given_values`)."""


class ParameterError(VphsError):
    """An override (from an optimiser, a job or --set) that the parameter does not accept."""


@dataclass
class Entry:
    """One named value. ``expression`` reads names through ``scope`` (local name -> qualified name);
    ``literals`` are the quantities written inside it ("5 m" -> a placeholder name with SI value and unit)."""

    name: str
    unit: str | None  # declared SI unit, None if free (netlist parameters)
    constant: float | tuple | None
    expression: Expression | None
    scope: dict[str, str]
    source: Located
    path: tuple
    bounds: object | None = None  # a blocks.block.Param to check bounds with
    elements: list | None = None  # an array of constants and expressions (array parameters)
    literals: dict[str, tuple[float, Unit, str]] = field(default_factory=dict)
    dims: Unit | None = FREE  # the written unit of a constant, or the declared unit (FREE for a bare number)
    raw: object = None  # the text as written (re-read when a net's kind fixes the unit of its initial value)
    lines: list[int] | None = None  # an array read from a data file ({csv:, column:}): each element's file line
    unknown_units: dict[str, UnknownUnitError] = field(default_factory=dict)
    """Names that failed as units where the value reads as "<number> <unit>" ("mn" in "10 l/mn"), which the
    expression then took as parameter names: if no such parameter exists, the misspelt unit is reported."""

    def element_place(self, i: int) -> str | None:
        """Where element ``i`` of an array read from a data file was written (``ref.csv:7``), else None."""
        if self.lines is None or not 0 <= i < len(self.lines):
            return None
        return f"{getattr(self.raw, 'csv', '?')}:{self.lines[i]}"

    def dependencies(self) -> set[str]:
        found = set(self.expression.names) if self.expression is not None else set()
        for item in self.elements or ():
            if isinstance(item, Expression):
                found |= item.names
        return found - set(self.literals)

    def error(self, message: str) -> NetlistError:
        return self.source.error(self.path, message)

    @property
    def written(self) -> str:
        """The value as the user wrote it (not the placeholder text of its unit literals)."""
        return self.raw if isinstance(self.raw, str) else (self.expression.text if self.expression else str(self.raw))


@dataclass
class ParameterTable:
    entries: dict[str, Entry] = field(default_factory=dict)
    _order: list[str] | None = None
    _dims: dict[str, Unit | None] = field(default_factory=dict)  # each name's dimension (order(); FREE: a number)
    unread: list[Entry] = field(default_factory=list)
    """Values written that no other value reads and that are not parameters themselves (a file's ``defaults:
    volume:`` that no net takes): checked as entries are (:meth:`check_unread`), never evaluated for use."""
    derived: dict[str, str] = field(default_factory=dict)
    """Entries the netlist does not write but derives from others (name -> what to set instead): not set
    on their own (``--set``, an optimiser's or a calibration's free parameter)."""

    def add(self, entry: Entry) -> None:
        if entry.name in self.entries:
            raise entry.error(f"duplicate name '{entry.name}'")
        self.entries[entry.name] = entry
        self._order = None

    def order(self) -> list[str]:
        """Names in evaluation order; errors for unknown names, dependency cycles and wrong dimensions."""
        if self._order is None:
            graph = nx.DiGraph()
            graph.add_nodes_from(self.entries)
            for entry in self.entries.values():
                for target in self._read_by(entry):
                    graph.add_edge(target, entry.name)
            try:
                cycle = nx.find_cycle(graph)
            except nx.NetworkXNoCycle:
                cycle = None
            if cycle:
                names = [edge[0] for edge in cycle]
                raise self.entries[names[0]].error(
                    f"parameters depend on each other in a cycle: {' -> '.join(names + names[:1])}")
            order = list(nx.topological_sort(graph))
            self._check_dimensions(order)
            self._order = order
        return self._order

    def _read_by(self, entry: Entry) -> list[str]:
        """The names ``entry`` reads; errors for an unknown name and for a list read as one value."""
        found = []
        for local in entry.dependencies():
            target = entry.scope.get(local)
            if target is None or target not in self.entries:
                raise entry.error(self._unknown_name(entry, local))
            read = self.entries[target]
            if read.elements is not None or isinstance(read.constant, tuple):
                raise entry.error(f"{entry.name}: '{local}' is a list of values; an expression reads "
                                  f"one value")
            found.append(target)
        return found

    def _unknown_name(self, entry: Entry, local: str) -> str:
        """What is wrong with ``local``, a name ``entry`` reads that is no parameter: a misspelt parameter, or
        where the value reads as "<number> <unit>" but for this name ("10 l/mn"), a misspelt unit (or, if a
        parameter's name is near it too, either; the hints say which are near)."""
        near = nearest(local, [n for n in entry.scope if entry.scope[n] in self.entries])
        unit = entry.unknown_units.get(local)
        if unit is None:
            return f"unknown parameter '{local}' in {entry.name}{did_you_mean(near)}"
        if unit.near and not near:
            return f"{entry.name}: {unit}"
        hints = ([f"the unit {', '.join(unit.near)}"] if unit.near else []) + \
                ([f"the parameter {', '.join(near)}"] if near else [])
        either = did_you_mean([" or ".join(hints)] if hints else [])
        return f"{entry.name}: unknown unit or parameter '{local}'{either}"

    def _check_dimensions(self, order: list[str]) -> None:
        inferred: dict[str, Unit | None] = {}
        for name in order:
            inferred[name] = self._dimension_of(self.entries[name], inferred)
        self._dims = inferred

    def _dimension_of(self, entry: Entry, inferred: dict[str, Unit | None]) -> Unit | None:
        """The dimension of ``entry`` given those of the names it reads; an error if it does not fit its
        declared unit."""
        dims = entry.dims
        if entry.expression is not None:
            try:
                dims = _infer(entry.expression.tree, entry, inferred)
            except UnitError as exc:
                raise entry.error(f"{entry.name}: wrong unit: '{entry.written}' {exc}") from None
            if entry.unit is not None and entry.unit != GENERIC and dims is not FREE:
                declared = parse_unit(entry.unit)
                if not dims.same_dimension(declared):
                    raise entry.error(f"{entry.name}: wrong unit: '{entry.written}' is in "
                                      f"{dims.describe_dims()}, expected {entry.unit}"
                                      + self._written_elsewhere(entry))
                dims = declared
        generic = entry.unit is None or entry.unit == GENERIC
        return dims if generic else (parse_unit(entry.unit) if dims is not FREE else FREE)

    def check_unread(self, values: dict[str, float | tuple]) -> None:
        """Check each :attr:`unread` entry as if it were read: the names it reads, its dimension, its value
        and its bounds; ``values`` are the table's (:meth:`evaluate`)."""
        self.order()
        for entry in self.unread:
            self._read_by(entry)
            self._dimension_of(entry, self._dims)
            self._value(entry, values)

    def dimension(self, name: str) -> Unit | None:
        """The dimension the netlist gives ``name``, None where it does not say.

        In this order: the declared unit of a component parameter (``pump.q``: m^3/s); the unit its value is
        written in, or its expression's (``Q_in: "40 l/min"``, ``Q_in: "2*Q_nom"``); for a bare number (free:
        the SI value of whatever its place needs) the declared unit of the places it is put as it stands
        (``q: Q_in`` or ``q: -Q_in``, through other netlist parameters that are it under another name). None
        (not known) for a bare number in no place of declared unit: put only where any unit goes (a generic
        signal block's SI parameter, a profile's ``values``: there ``Q_in: 6.7e-4`` may be a flow, driving a
        constant block that drives a flow source, and ``u1: 0.1`` a plain number), read inside an expression
        (a free number adapts there, ``J: "0.085 + m*r**2/n**2"``, and its dimension would have to be solved
        for), or nowhere; and for one put in places of different dimensions."""
        entry = self.entries[name]
        if entry.unit not in (None, GENERIC):
            return parse_unit(entry.unit)
        self.order()
        dims = self._dims.get(name, FREE)
        return dims if dims is not FREE else self._dimension_from_places(name)

    def _written_elsewhere(self, entry: Entry) -> str:
        """The values with a unit that ``entry`` reads and that were written in another file (a subsystem's
        parameter set by the file that uses it), with where: the place to mend is often there."""
        found = []
        for local in sorted(entry.dependencies()):
            read = self.entries.get(entry.scope.get(local, ""))
            if read is None or read.dims is FREE or read.source.file == entry.source.file:
                continue
            line, _ = read.source.where(read.path)
            found.append(f"{read.name} = '{read.written}' at {read.source.file}:{line}")
        return f" (it reads {', '.join(found)})" if found else ""

    def value_si(self, name: str, raw) -> float:
        """A value given for ``name`` from outside the netlist (``--set``, a job, an experiment file) in SI: a
        number is SI; ``"<number> <unit>"`` is converted, its unit checked against the dimension the netlist
        gives ``name``: its declared unit, the unit its value is written in, or for a bare number the
        dimension its readers take it in (``n_gear`` in ``J: "0.085 + m*r**2/n_gear**2"`` must be a plain
        number for J to be a moment of inertia; ``"39 rpm"`` is refused, where it used to be read as 4.08).
        A unit no reader constrains (a bare number put only where any unit goes) is converted unchecked.
        An array (a table) takes no single value, and the value must be finite. Raises UnitError (no
        location: the caller names where the value was given)."""
        self.check_single(name)
        entry = self.entries[name]
        value = self._si(name, entry, raw)
        if not np.isfinite(value):
            raise UnitError(f"{raw!r} is not a finite number")
        return value

    def check_single(self, name: str) -> None:
        """Raise UnitError if ``name`` is an array (a table): no single value given from outside replaces it."""
        entry = self.entries[name]
        if entry.elements is not None or isinstance(entry.constant, tuple) or getattr(entry.bounds, "array", False):
            raise UnitError(f"{name} is an array (a table); change it in the netlist")

    def _si(self, name: str, entry: Entry, raw) -> float:
        if entry.unit not in (None, GENERIC):
            return quantity(raw, entry.unit)
        if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
            raise UnitError(f"expected a number or a '<number> <unit>' string, got {raw!r}")
        if not isinstance(raw, str):
            return float(raw)
        number, unit_text = split_quantity(raw)
        if not unit_text:
            return number
        given = parse_unit(unit_text)
        problem = self.dimension_problem(name, given)
        if problem:
            raise UnitError(f"wrong unit '{unit_text}': {problem}")
        return number * given.factor

    def dimension_problem(self, name: str, given: Unit) -> str | None:
        """Why a value given for ``name`` from outside the netlist in the dimension ``given`` cannot be one
        (None: it can): the dimension the netlist gives ``name`` (:meth:`dimension`: declared, written, or
        its places'), else what its readers say (:meth:`unit_conflict`)."""
        known = self.dimension(name)
        if known is not None:
            return None if given.same_dimension(known) else f"{name} is in {known.describe_dims()}"
        return self.unit_conflict(name, given)

    def given_expression(self, name: str, raw, source: Located, path: tuple, label: str) -> Entry | None:
        """A value given for ``name`` from outside the netlist (a job's ``set:``) as an expression over the
        netlist's parameters, written as the netlist writes one (``"2*w0 + 1 rad/s"``) and reading them by
        their qualified names: an entry named ``label`` (the place its messages name, ``set.sys.wn``), its
        names and its dimension checked (against ``name``'s: :meth:`dimension_problem`), errors located at
        ``path`` in ``source``. None for a number or ``"<number> <unit>"`` (:meth:`value_si` reads those).
        Evaluate it with :meth:`value_of`; :meth:`reads` says what its value depends on."""
        if not isinstance(raw, str):
            return None
        entry = make_entry(label, raw, None, {n: n for n in self.entries}, source, path)
        if entry.expression is None:
            return None
        self.order()
        self._read_by(entry)
        dims = self._dimension_of(entry, self._dims)
        problem = self.dimension_problem(name, dims) if dims is not FREE else None
        if problem:
            raise entry.error(f"{label}: wrong unit: '{raw}' is in {dims.describe_dims()}, but {problem}")
        return entry

    def reads(self, entry: Entry, held=()) -> set[str]:
        """The names ``entry``'s value depends on: those it reads, and through their expressions theirs, except
        through the names ``held`` at a value given for them (whose expressions in the netlist are not read)."""
        found, todo = set(), [entry]
        while todo:
            reader = todo.pop()
            for local in reader.dependencies():
                target = reader.scope[local]  # order() checked the scope
                if target not in found:
                    found.add(target)
                    if target not in held:
                        todo.append(self.entries[target])
        return found

    def value_of(self, entry: Entry, values: dict[str, float | tuple]) -> float | tuple:
        """The value of an entry not in the table (:meth:`given_expression`) from the table's ``values``."""
        return self._value(entry, values)

    def given_values(self, expressions: dict[str, Entry], values: dict[str, float | tuple], held,
                     changed: dict[str, str], section: str) -> dict[str, float | tuple]:
        """The values of the expressions a section given from outside the netlist holds (a job's ``set:``, an
        experiment's ``overrides:``, the ``--set`` options; each by the name it sets, from
        :meth:`given_expression`), from the table's ``values`` (:meth:`evaluate` with the names ``held`` at
        the section's plain values, and at those it is given on top of). Each is evaluated once, so one that
        reads, itself or through the netlist's expressions, a name in ``changed`` (-> what changes it: 'the job
        varies') or another expression of ``expressions`` would not follow it, and is refused, located where
        it was given. Its own name is no such read: there it reads the netlist's value (``p_set: "p_set + 10
        bar"``); nor is what the netlist's expression of a held name reads. Its own name read through another
        name is: that name follows the value given (``w0: "sys.wn/3"`` with ``sys.wn: "2*w0"``)."""
        found = {}
        for name, entry in expressions.items():
            for read in sorted(self.reads(entry, held)):
                why = changed.get(read) or (f"is given by an expression in {section} too"
                                            if read != name and read in expressions else None)
                if why:
                    raise entry.error(f"{entry.name}: '{entry.written}' reads {read}, which {why}: {EVALUATED_ONCE}")
            for read in sorted({entry.scope[local] for local in entry.dependencies()} - {name} - set(held)):
                if name in self.reads(self.entries[read], held):
                    raise entry.error(f"{entry.name}: '{entry.written}' reads {read}, which reads {name}, the name "
                                      f"it sets: {read} would follow the value given, not the one read")
            found[name] = self.value_of(entry, values)
        return found

    def unit_conflict(self, name: str, given: Unit) -> str | None:
        """Why a value of ``name`` in the dimension ``given`` cannot be one, where the netlist gives ``name`` no
        dimension (:meth:`dimension` None): for a bare number, what its readers' expressions make of it
        ('with n_gear in rpm, J: wrong unit ...'); None if nothing says against it (a bare number put only
        where any unit goes, or a value given by an expression). Shared by :meth:`value_si` and the values
        read from a data file's column (an experiment's group table), so that a unit is checked alike."""
        if self.entries[name].expression is not None:
            return None
        conflict = self._conflict(name, given)
        if conflict is None:
            return None
        what = "a plain number" if given.same_dimension(parse_unit("1")) else f"in {given.describe_dims()}"
        return f"with {name} {what}, {conflict}"

    def _conflict(self, name: str, dims: Unit) -> str | None:
        """What a bare number's readers say against it being in ``dims`` (None: nothing): the dimension check
        of the whole table, rerun with ``name`` written in ``dims``."""
        entry = self.entries[name]
        order, inferred = self.order(), self._dims
        entry.dims = dims
        try:
            self._check_dimensions(order)
        except NetlistError as exc:
            return f"{exc.message} (at {exc.file}:{exc.line})" if exc.line is not None else exc.message
        finally:  # as it was: the check of the table as written needs no rerun
            entry.dims, self._dims = FREE, inferred
        return None

    def readers(self, name: str) -> list[tuple[Entry, list[Expression]]]:
        """Every entry that reads ``name``, with its expressions that do (its own, or its array's elements)."""
        out = []
        for reader in self.entries.values():
            items = [reader.expression] if reader.expression is not None else \
                [item for item in reader.elements or () if isinstance(item, Expression)]
            items = [item for item in items if any(reader.scope.get(local) == name for local in item.names)]
            if items:
                out.append((reader, items))
        return out

    def _dimension_from_places(self, name: str) -> Unit | None:
        """The one dimension of the declared-unit places ``name`` is put as it stands (directly or through
        netlist parameters that are it under another name); None if there is none, or more than one. Places
        that say nothing (any unit, inside an expression) are no constraint."""
        fixed = []
        for reader, items in self.readers(name):
            for item in items:
                if reader.scope.get(_sole_name(item.tree, reader)) != name or reader.unit == GENERIC:
                    continue  # read inside an expression, or a place of any unit
                if reader.unit is not None:
                    fixed.append(parse_unit(reader.unit))
                else:  # a netlist parameter that is this one under another name
                    dims = self.dimension(reader.name)
                    fixed += [dims] if dims is not None else []
        return fixed[0] if fixed and all(f.same_dimension(fixed[0]) for f in fixed) else None

    def evaluate(self, overrides: dict[str, float] | None = None) -> dict[str, float | tuple]:
        """All values in SI; ``overrides`` replace named values (and so everything that depends on them)."""
        overrides = overrides or {}
        for name in overrides:
            if name not in self.entries:
                raise ParameterError(f"unknown parameter '{name}'{did_you_mean(nearest(name, self.entries))}")
        values: dict[str, float | tuple] = {}
        for name in self.order():
            entry = self.entries[name]
            if name in overrides:
                value = overrides[name]
                if entry.bounds is not None:
                    problem = entry.bounds.check(value)
                    if problem:
                        raise ParameterError(f"override {name}: {problem}")
                values[name] = value
                continue
            values[name] = self._value(entry, values)
        return values

    @staticmethod
    def _value(entry: Entry, values: dict[str, float | tuple]) -> float | tuple:
        """The value of ``entry`` in SI from the ``values`` of the names it reads, its bounds checked; one
        without bounds (a net's or a state's initial value, a netlist parameter) must be finite."""
        if entry.expression is not None or entry.elements is not None:
            local = {n: values[entry.scope[n]] for n in entry.dependencies()}  # order() checked the scope
            local.update({k: v for k, (v, _, _) in entry.literals.items()})
            try:
                if entry.elements is not None:
                    value = tuple(item.evaluate(local) if isinstance(item, Expression) else item
                                  for item in entry.elements)
                else:
                    value = entry.expression.evaluate(local)
            except ExpressionError as exc:
                raise entry.error(f"{entry.name}: {as_written(str(exc), entry.literals)}") from None
        else:
            value = entry.constant
        if entry.bounds is not None:
            problem = entry.bounds.check(value)
            if problem:
                raise entry.error(f"{entry.name.rsplit('.', 1)[0]}: {problem}")
        elif not all(math.isfinite(v) for v in (value if isinstance(value, tuple) else (value,))):
            written = f" ('{entry.raw}')" if isinstance(entry.raw, str) else ""
            raise entry.error(f"{entry.name} = {value}{written} is not finite")
        return value


def as_written(message: str, literals: dict) -> str:
    """``message`` with the placeholders of unit ``literals`` put back as written (``_q3`` -> ``50 mm``)."""
    if not literals:
        return message
    return re.sub(r"\b_q\d+\b", lambda m: literals[m.group(0)][2] if m.group(0) in literals else m.group(0),
                  message)


def _sole_name(node: ast.AST, entry: Entry) -> str | None:
    """The local name an expression is, as it stands or negated (``Q_in``, ``-Q_in``, ``supply.p``); else None."""
    while isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        node = node.operand
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return dotted_name(node, entry.written)
    return None


def _refuse_plain_number_beside_scaled_unit(node: ast.BinOp, number_left: bool, dims: Unit, entry: Entry) -> None:
    """A number written bare, added to (or subtracted from) a quantity with a dimension written in a scaled
    unit in the same expression, is refused: in ``"50 mm + 10"`` the 10 counts as SI (10 m) where the
    writer most likely meant 10 mm. A bare number added to parameters (``"0.085 + m*r**2/n**2"``) stays SI,
    as everywhere else, and a dimensionless sum (``"1 + 5 %"``, ``"1 + 50 mm/0.2 m"``) is no slip at all
    (the caller checks that). ``dims``: the sum's dimension, whose SI unit the number counts in."""
    number, other = (node.left, node.right) if number_left else (node.right, node.left)
    while isinstance(number, ast.UnaryOp):
        number = number.operand
    if not isinstance(number, ast.Constant):
        return
    scaled = [entry.literals[n.id] for n in ast.walk(other)
              if isinstance(n, ast.Name) and n.id in entry.literals and entry.literals[n.id][1].factor != 1.0]
    if scaled:
        raise UnitError(f"puts the plain number {number.value:g} in a sum with {scaled[0][2]}: a plain number "
                        f"counts in SI ({si_name(dims)}) there; write its unit")


def _infer(node: ast.AST, entry: Entry, known: dict[str, Unit | None]):
    """The dimension of an expression: a Unit, or FREE for a pure number."""
    if isinstance(node, ast.Constant):
        return FREE
    if isinstance(node, (ast.Name, ast.Attribute)):
        name = node.id if isinstance(node, ast.Name) else dotted_name(node, entry.written)
        if name in entry.literals:
            return entry.literals[name][1]
        target = entry.scope.get(name)
        return known.get(target, FREE) if target is not None else FREE
    if isinstance(node, ast.UnaryOp):
        return _infer(node.operand, entry, known)
    if isinstance(node, ast.BinOp):
        left, right = _infer(node.left, entry, known), _infer(node.right, entry, known)
        if isinstance(node.op, (ast.Add, ast.Sub, ast.Mod)):
            if left is not FREE and right is not FREE and not left.same_dimension(right):
                raise UnitError(f"adds {left.describe_dims()} to {right.describe_dims()}")
            if (left is FREE) != (right is FREE) and any((left if right is FREE else right).dims):
                _refuse_plain_number_beside_scaled_unit(node, left is FREE, left if right is FREE else right, entry)
            return left if left is not FREE else right
        if isinstance(node.op, ast.Mult):
            return left if right is FREE else right if left is FREE else left * right
        if isinstance(node.op, ast.Div):
            if right is FREE:
                return left
            inverse = right ** -1
            return inverse if left is FREE else left * right ** -1
        if isinstance(node.op, ast.Pow):
            if right is not FREE and any(right.dims):
                raise UnitError(f"an exponent in {right.describe_dims()}")
            if left is FREE:
                return FREE
            if isinstance(node.right, ast.Constant):
                return left ** float(node.right.value)
            if isinstance(node.right, ast.UnaryOp) and isinstance(node.right.operand, ast.Constant):
                sign = -1.0 if isinstance(node.right.op, ast.USub) else 1.0
                return left ** (sign * float(node.right.operand.value))
            return FREE  # a computed exponent: give up on the check rather than guess
    if isinstance(node, ast.Call):
        args = [_infer(a, entry, known) for a in node.args]
        name = node.func.id
        if name == "sqrt":
            return args[0] ** 0.5 if args and args[0] is not FREE else FREE
        if name in ("abs", "min", "max", "floor", "ceil", "hypot"):
            dims = [a for a in args if a is not FREE]
            for a in dims[1:]:
                if not a.same_dimension(dims[0]):
                    raise UnitError(f"{name}() of {dims[0].describe_dims()} and {a.describe_dims()}")
            return dims[0] if dims else FREE
        return FREE  # transcendental functions: a pure number (or an angle) out
    return FREE


def _names_a_parameter(raw: str, scope: dict[str, str]) -> bool:
    """True for "1000 kg * g" with a parameter g: an operator written with spaces after a unit, followed by a
    name in scope, makes the text an expression (units themselves are written without spaced operators)."""
    unit_text = split_quantity(raw)[1]
    spaced = re.search(r"\s[*/·]|[*/·]\s", unit_text)
    return bool(spaced) and bool(set(re.findall(r"[A-Za-z_]\w*", unit_text[spaced.start():])) & set(scope))


def _misspelt_unit(text: str, inline: dict, scope: dict[str, str]) -> UnknownUnitError | None:
    """For an expression that does not parse: the misspelt unit of a "<number> <unit>" in it (``inline``, from
    :func:`~blocks.units.substitute_quantities`) if that is all that is wrong, else None. It is, when the unit
    is near known ones, no parameter has its name ("10 p_c" is a '*' left out) and the text parses with each
    such quantity taken as a value ("p_c + 10 barr"; not "7500 k\\ng", a line break inside "7500 kg")."""
    misspelt = [(unit, written) for local, (unit, written) in inline.items() if unit.near and local not in scope]
    if not misspelt:
        return None
    for _, written in misspelt:
        text = text.replace(written, " 1.0 ")
    try:
        parse_expression(text)
    except ExpressionError:
        return None
    return misspelt[0][0]


def _unspaced_unit(raw: str, scope: dict[str, str]) -> str | None:
    """For an expression that does not parse: what is wrong with a number written against its unit ("p_c+10bar",
    "p_c+10barr"), if that is all that is wrong: inside an expression a unit follows its number after a space.
    It is, when the text with a space put after each such number parses with each quantity taken as a value,
    its unit a known one or a misspelt one (:func:`_misspelt_unit`, said first as it is said for "p_c + 10
    barr"); else None ("10k_unknown", "0x1F": nothing said about a unit)."""
    unspaced = UNSPACED_QUANTITY.search(raw)
    if unspaced is None:
        return None
    inline = {}
    try:
        text, _ = substitute_quantities(UNSPACED_QUANTITY.sub(r"\g<value> \g<unit>", raw), inline)
    except UnitError:
        return None
    misspelt = _misspelt_unit(text, inline, scope)
    if misspelt is None:
        try:
            parse_expression(text)
        except ExpressionError:
            return None
    space = (f"inside an expression a unit follows its number after a space ('{unspaced['value']} "
             f"{unspaced['unit']}', not '{unspaced[0]}')")
    return f"{misspelt}; and {space}" if misspelt is not None else space


def make_entry(name: str, raw, unit: str | None, scope: dict[str, str], source: Located, path: tuple,
               bounds=None) -> Entry:
    """Read a raw netlist value: a number (SI), '<number> <unit>' (checked against ``unit``) or an expression."""
    if isinstance(raw, bool) or raw is None:
        raise source.error(path, f"{name}: expected a number, a '<number> <unit>' string or an expression, got {raw!r}")
    if isinstance(raw, (int, float)):
        dims = parse_unit(unit) if unit and unit != GENERIC else FREE
        return Entry(name, unit, float(raw), None, scope, source, path, bounds, dims=dims, raw=raw)
    if not isinstance(raw, str):
        raise source.error(path, f"{name}: expected a single value, got {type(raw).__name__}")
    comma = decimal_comma(raw)  # "150,5 bar": as an expression, a pair of values
    if comma:
        raise source.error(path, f"{name}: {comma}")
    unit_problem = None
    if _QUANTITY.match(raw) and not _names_a_parameter(raw, scope):
        try:
            number, unit_text = split_quantity(raw)
            if unit is None:
                written = parse_unit(unit_text)
                value = number * written.factor
                dims = written if unit_text else FREE
            else:
                value = quantity(raw, unit)
                dims = parse_unit(unit) if unit != GENERIC else (parse_unit(unit_text) if unit_text else FREE)
            return Entry(name, unit, value, None, scope, source, path, bounds, dims=dims, raw=raw)
        except UnitError as exc:
            unit_problem = exc  # may still be an expression such as "0.085 + m_load*r**2"
    text, literals, inline = raw, {}, {}
    try:
        text, literals = substitute_quantities(raw, inline)
        expression = parse_expression(text)
    except (ExpressionError, UnitError) as exc:
        meant_an_expression = unit_problem is not None and not re.match(r"[A-Za-z%]", split_quantity(raw)[1])
        problem = as_written(str(exc), literals) if meant_an_expression or unit_problem is None else unit_problem
        # "10 barr + p_c" is no quantity ('+ p_c' in its unit) but an expression whose unit is misspelt
        if problem is not unit_problem or not isinstance(unit_problem, UnknownUnitError):
            problem = _misspelt_unit(text, inline, scope) or _unspaced_unit(raw, scope) or problem
        raise source.error(path, f"{name}: {problem}") from None
    if unit_problem is not None and "wrong unit" in str(unit_problem):
        raise source.error(path, f"{name}: {unit_problem}")
    unknown = {local: unit for local, (unit, _) in inline.items()}
    unknown.update({unit_problem.name: unit_problem} if isinstance(unit_problem, UnknownUnitError) else {})
    return Entry(name, unit, None, expression, scope, source, path, bounds, literals=literals,
                 dims=parse_unit(unit) if unit and unit != GENERIC else FREE, raw=raw, unknown_units=unknown)


def make_array_entry(name: str, raw: list, unit: str, scope: dict[str, str], source: Located, path: tuple,
                     bounds=None) -> Entry:
    """An array parameter: each element a number, '<number> <unit>' or an expression."""
    elements, literals, written, bare, unknown = [], {}, [], [], {}
    for i, item in enumerate(raw):
        single = make_entry(f"{name}[{i}]", item, unit, scope, source, path + (i,))
        elements.append(single.expression if single.expression is not None else single.constant)
        literals.update(single.literals)
        unknown.update(single.unknown_units)
        if single.expression is None:
            if single.dims is not FREE:
                written.append((i, item, single.dims))
            elif single.constant != 0.0:
                bare.append((i, item))
    # a list holds one quantity: "0.3 bar" beside "0.3 m" is a slip, and so is 5 beside "0 bar" (5 Pa)
    for i, item, dims in written[1:]:
        first, first_item, first_dims = written[0]
        if not dims.same_dimension(first_dims):
            raise source.error(path + (i,), f"{name}[{i}] = '{item}' is {quantity_name(dims)}, but {name}[{first}] "
                                            f"= '{first_item}' is {quantity_name(first_dims)}: one list holds one "
                                            f"quantity")
    scaled = [(i, item, dims) for i, item, dims in written  # (a number written as one is in SI: .nan too)
              if isinstance(item, str) and parse_unit(split_quantity(item)[1]).factor != 1.0]
    if scaled and bare:
        (i, item), (first, first_item, dims) = bare[0], scaled[0]
        raise source.error(path + (i,), f"{name}[{i}] = {item} is a plain number beside {name}[{first}] = "
                                        f"'{first_item}': a plain number counts in SI ({si_name(dims)}) there; "
                                        f"write its unit")
    # the list's dimension, as its elements with a unit write it (the declared one, or a generic list's)
    dims = written[0][2] if written else (parse_unit(unit) if unit and unit != GENERIC else FREE)
    if all(not isinstance(e, Expression) for e in elements):
        return Entry(name, unit, tuple(elements), None, scope, source, path, bounds, dims=dims, raw=raw)
    return Entry(name, unit, None, None, scope, source, path, bounds, elements, literals, dims=dims, raw=raw,
                 unknown_units=unknown)
