"""The nominal magnitude of a generic signal block's states: that of the quantity its signal carries.

A generic block (a filter, an integrator, a PID controller) declares its states in "SI" with nominal 1,
whatever its signal carries; the solver's absolute tolerance is ``atol`` times the nominal
(:mod:`blocks.solve.run`), so a filter on a flow of 1e-5 m^3/s got an absolute tolerance of 1e-6 "m^3/s",
a tenth of the signal, and was off by about 1 % at the default tolerances, silently. Here each signal net whose
quantity the netlist fixes gets that quantity's nominal magnitude (:func:`blocks.nominal.nominal_magnitude`):

1. a port on the net that declares a unit other than generic "SI" (a flow sensor's ``q`` in m^3/s, a
   valve's ``x`` in 1) fixes it;
2. a parameter that gives a generic port on the net its dimension (:attr:`Block.signal_dimensions`: a
   profile's ``values`` written in l/min, a saturation's limits in bar) and whose dimension the netlist
   fixes (:meth:`ParameterTable.dimension`); a bare number fixes nothing;
3. nets joined through a block that passes the same quantity through (:attr:`Block.same_quantity`: a
   filter's input and output, a sum's inputs and output) form one group, which takes the scale found by 1
   or 2 on its nets; where they find several (a sum whose gain converts, u = Kv*v_ref + u_pi with Kv in
   s/m, joins a velocity to a valve command), the smallest, so that no state's tolerance is looser than
   its own quantity's (a tighter one only costs steps).

A generic state whose declaration names a port (``State.scale_of``) takes the scale of that port's group;
where no scale is known, or the state names no port, it keeps its declared nominal.
"""

from __future__ import annotations

import networkx as nx

from blocks.block import PortKind, State
from blocks.netlist.flatten import FlatCircuit
from blocks.nominal import nominal_magnitude
from blocks.units import GENERIC, parse_unit


def net_scales(circuit: FlatCircuit) -> dict[str, float]:
    """The nominal magnitude [SI] of each signal net whose quantity the netlist fixes, by net name."""
    signal = [net for net in circuit.nets.values() if net.kind is PortKind.SIGNAL]
    net_of = {(comp, port): net.name for net in signal for comp, port in net.ports}
    groups = nx.Graph()
    groups.add_nodes_from(net.name for net in signal)
    for name, comp in circuit.components.items():
        for ports in comp.cls.same_quantity:
            nets = [net_of[(name, port)] for port in ports if (name, port) in net_of]
            groups.add_edges_from(zip(nets, nets[1:]))
    known = {net.name: _known_scales(circuit, net) for net in signal}
    scales = {}
    for members in nx.connected_components(groups):
        found = [scale for net in members for scale in known[net]]
        if found:
            scales.update((net, min(found)) for net in members)
    return scales


def _known_scales(circuit: FlatCircuit, net) -> list[float]:
    """The nominal magnitudes that the net's ports' declared units (1) and dimension parameters (2) give."""
    found = []
    for comp, name in net.ports:
        cls = circuit.components[comp].cls
        unit = cls.port(name).unit
        if unit not in ("", GENERIC):
            found.append(nominal_magnitude(parse_unit(unit)))
        for param in cls.signal_dimensions.get(name, ()):
            dims = circuit.parameters.dimension(f"{comp}.{param}")
            if dims is not None:
                found.append(nominal_magnitude(dims))
    return found


def state_nominal(state: State, component: str, port_net: dict[tuple[str, str], str],
                  scales: dict[str, float]) -> float:
    """The nominal magnitude of ``component``'s ``state``: its signal's scale where ``state.scale_of`` names a
    port on a net of known scale, else the declared ``state.nominal``."""
    if state.scale_of is None or state.unit != GENERIC:
        return state.nominal
    net = port_net.get((component, state.scale_of))
    return scales.get(net, state.nominal)
