"""The parameter table of a flat circuit: every named value, its source text and how to evaluate it.

Names are qualified: ``m_load`` (a netlist parameter), ``valve.A_max`` (a component parameter),
``left.valve.A_max`` (inside subsystem ``left``), ``A.volume``, ``A.initial``, ``valve.initial.x``,
``fluid.rho``. Each entry is a constant or an expression over other names of its scope. Evaluation walks
them in dependency order (networkx), so that an optimiser can override any name, ``m_load`` included, and
every value that depends on it follows, without rebuilding the circuit.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import networkx as nx

from blocks.errors import NetlistError
from blocks.expressions import ExpressionError, parse_expression, Expression
from blocks.netlist.yaml_source import Located
from blocks.units import UnitError, parse_unit, quantity, split_quantity, substitute_quantities, _QUANTITY


@dataclass
class Entry:
    """One named value. ``expression`` reads names through ``scope`` (local name -> qualified name)."""

    name: str
    unit: str | None  # declared SI unit, None if free (netlist parameters)
    constant: float | tuple | None
    expression: Expression | None
    scope: dict[str, str]
    source: Located
    path: tuple
    bounds: object | None = None  # a blocks.block.Param to check bounds with
    elements: list | None = None  # an array of constants and expressions (array parameters)

    def dependencies(self) -> set[str]:
        found = set(self.expression.names) if self.expression is not None else set()
        for item in self.elements or ():
            if isinstance(item, Expression):
                found |= item.names
        return found

    def error(self, message: str) -> NetlistError:
        return self.source.error(self.path, message)


@dataclass
class ParameterTable:
    entries: dict[str, Entry] = field(default_factory=dict)
    _order: list[str] | None = None

    def add(self, entry: Entry) -> None:
        if entry.name in self.entries:
            raise entry.error(f"duplicate name '{entry.name}'")
        self.entries[entry.name] = entry
        self._order = None

    def order(self) -> list[str]:
        """Names in evaluation order; an error naming the names in a dependency cycle."""
        if self._order is None:
            graph = nx.DiGraph()
            graph.add_nodes_from(self.entries)
            for entry in self.entries.values():
                for local in entry.dependencies():
                    target = entry.scope.get(local)
                    if target is None or target not in self.entries:
                        near = [n for n in entry.scope if n in self.entries or entry.scope[n] in self.entries]
                        from blocks.units import nearest

                        hint = nearest(local, near)
                        raise entry.error(
                            f"unknown parameter '{local}' in {entry.name}"
                            + (f" (did you mean {', '.join(hint)}?)" if hint else "")
                        )
                    graph.add_edge(target, entry.name)
            try:
                cycle = nx.find_cycle(graph)
            except nx.NetworkXNoCycle:
                cycle = None
            if cycle:
                names = [edge[0] for edge in cycle]
                raise self.entries[names[0]].error(f"parameters depend on each other in a cycle: {' -> '.join(names + names[:1])}")
            self._order = list(nx.topological_sort(graph))
        return self._order

    def evaluate(self, overrides: dict[str, float] | None = None) -> dict[str, float | tuple]:
        """All values in SI; ``overrides`` replace named values (and so everything that depends on them)."""
        overrides = overrides or {}
        for name in overrides:
            if name not in self.entries:
                from blocks.units import nearest

                hint = nearest(name, self.entries)
                raise KeyError(f"unknown parameter '{name}'" + (f" (did you mean {', '.join(hint)}?)" if hint else ""))
        values: dict[str, float | tuple] = {}
        for name in self.order():
            entry = self.entries[name]
            if name in overrides:
                value = overrides[name]
            elif entry.expression is not None or entry.elements is not None:
                local = {n: values[q] for n, q in entry.scope.items() if n in entry.dependencies()}
                try:
                    if entry.elements is not None:
                        value = tuple(item.evaluate(local) if isinstance(item, Expression) else item
                                      for item in entry.elements)
                    else:
                        value = entry.expression.evaluate(local)
                except ExpressionError as exc:
                    raise entry.error(str(exc)) from None
            else:
                value = entry.constant
            if entry.bounds is not None:
                problem = entry.bounds.check(value)
                if problem:
                    raise entry.error(f"{entry.name.rsplit('.', 1)[0]}: {problem}")
            values[name] = value
        return values


def make_entry(name: str, raw, unit: str | None, scope: dict[str, str], source: Located, path: tuple,
               bounds=None) -> Entry:
    """Read a raw netlist value: a number (SI), '<number> <unit>' (checked against ``unit``) or an expression."""
    if isinstance(raw, bool) or raw is None:
        raise source.error(path, f"{name}: expected a number, a '<number> <unit>' string or an expression, got {raw!r}")
    if isinstance(raw, (int, float)):
        return Entry(name, unit, float(raw), None, scope, source, path, bounds)
    if isinstance(raw, str):
        unit_problem = None
        if _QUANTITY.match(raw):
            try:
                if unit is None:
                    number, unit_text = split_quantity(raw)
                    value = number * parse_unit(unit_text).factor
                else:
                    value = quantity(raw, unit)
                return Entry(name, unit, value, None, scope, source, path, bounds)
            except UnitError as exc:
                unit_problem = exc  # may still be an expression such as "0.085 + m_load*r**2"
        try:
            expression = parse_expression(substitute_quantities(raw))
        except ExpressionError as exc:
            raise source.error(path, f"{name}: {unit_problem or exc}") from None
        if unit_problem is not None and "wrong unit" in str(unit_problem):
            raise source.error(path, f"{name}: {unit_problem}")
        return Entry(name, unit, None, expression, scope, source, path, bounds)
    raise source.error(path, f"{name}: expected a single value, got {type(raw).__name__}")


def make_array_entry(name: str, raw: list, unit: str, scope: dict[str, str], source: Located, path: tuple,
                     bounds=None) -> Entry:
    """An array parameter: each element a number, '<number> <unit>' or an expression."""
    elements = []
    for i, item in enumerate(raw):
        single = make_entry(f"{name}[{i}]", item, unit, scope, source, path + (i,))
        elements.append(single.expression if single.expression is not None else single.constant)
    if all(not isinstance(e, Expression) for e in elements):
        return Entry(name, unit, tuple(elements), None, scope, source, path, bounds)
    return Entry(name, unit, None, None, scope, source, path, bounds, elements)
