"""A generic signal's dimension, checked where the netlist gives it twice.

A generic ("SI") signal port carries any quantity in SI; some take their dimension from a parameter as
written (:attr:`blocks.block.Block.signal_dimensions`: a constant's ``value``, a lookup table's breakpoints).
When another port on the same signal net declares its unit (a flow source's ``q`` in m^3/s, a valve's ``x``
in 1), the two must agree: a constant of "6 bar" driving a flow source would otherwise be read as 6e5 m^3/s,
and a table whose breakpoints are in l/min would be read with a pressure. A parameter written as a bare
number, or whose dimension the netlist does not fix, is not checked (it is taken in SI).
"""

from __future__ import annotations

from blocks.block import PortKind
from blocks.units import GENERIC, parse_unit, quantity_name


def check_signal_dimensions(flat) -> None:
    """Raise the netlist's error, at the parameter, for the first dimension that disagrees."""
    table = flat.parameters
    for net in flat.nets.values():
        if net.kind is not PortKind.SIGNAL:
            continue
        ports = [(comp, flat.components[comp].cls.port(name)) for comp, name in net.ports]
        declared = [(comp, port) for comp, port in ports if port.unit not in ("", GENERIC)]
        if not declared:
            continue
        for comp, port in ports:
            for param in flat.components[comp].cls.signal_dimensions.get(port.name, ()):
                name = f"{comp}.{param}"
                dims = table.dimension(name)
                if dims is None:
                    continue
                for other_comp, other in declared:
                    unit = parse_unit(other.unit)
                    if not dims.same_dimension(unit):
                        entry = table.entries[name]
                        role = "reads" if other.direction == "in" else "drives"
                        written = (f"[{', '.join(str(v) for v in entry.raw)}]" if isinstance(entry.raw, list)
                                   else f"'{entry.written}'")
                        raise entry.error(
                            f"{name} = {written} is {quantity_name(dims)}, but the signal {comp}.{port.name} "
                            f"is {quantity_name(unit)}: {other_comp}.{other.name} {role} it in {other.unit}")
