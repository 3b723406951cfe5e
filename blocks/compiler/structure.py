"""The structure of a flat circuit: its state vector, its parameter vector and its evaluation order.

- Hydraulic net -> one pressure state (dp/dt = beta/V * sum q), unless a source prescribes its pressure.
- Rotational and translational nets joined by rigid links (gears, rack and pinion) form one rigid body
  with one speed state w of its root net; net k moves at r_k * w, its inertia counts r_k^2 * J_k, its
  torques r_k * tau_k (virtual power). A speed source on any net of the body prescribes it instead.
- Each block's own states follow, with their declared nominal magnitudes; a generic signal block's state
  (a filter's, an integrator's) takes the nominal of the quantity its signal carries where the netlist fixes
  it (:mod:`blocks.compiler.signal_scale`: a filter on a flow 1e-4 m^3/s, not 1).
- The direct-feedthrough graph (networkx) has an edge from a block to every block whose outputs read
  what it produces (a signal, or a prescribed across value); a cycle is an algebraic loop, reported by
  the names of the blocks in it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import networkx as nx

from blocks.block import ACROSS, CAPACITY, Block, PortKind
from blocks.compiler.signal_scale import net_scales, state_nominal
from blocks.netlist.flatten import NET_BOUNDS, FlatCircuit, FlatComponent, FlatNet
from blocks.netlist.parameters import Entry, make_entry
from blocks.nominal import nominal_magnitude
from blocks.units import parse_unit

PHYSICAL_STATE_NOMINAL = {kind: nominal_magnitude(parse_unit(unit)) for kind, (_, unit) in ACROSS.items()}
"""A net's pressure 1e5 Pa, a body's speed 1 rad/s or 0.1 m/s (:data:`blocks.nominal.NOMINAL_MAGNITUDE`)."""


@dataclass
class StateSlot:
    """Where one state (or array state) lives in x, and who owns it."""

    name: str  # "A.p", "shaft.w", "valve.x"
    index: int
    size: int
    unit: str
    nominal: float
    owner: str  # the net or component name
    kind: str  # "pressure", "speed", "block"


@dataclass
class RigidBody:
    """Mechanical nets moving together. ``members``: net -> (parent net, link component, forward?)."""

    root: str
    kind: PortKind
    members: dict[str, tuple[str | None, str | None, bool]]
    prescribed_by: tuple[str, str] | None = None  # (component, port)
    state: StateSlot | None = None


@dataclass
class Structure:
    circuit: FlatCircuit
    states: list[StateSlot] = field(default_factory=list)
    net_state: dict[str, StateSlot] = field(default_factory=dict)  # hydraulic nets with a pressure state
    prescribed: dict[str, tuple[str, str]] = field(default_factory=dict)  # net -> (component, port)
    bodies: list[RigidBody] = field(default_factory=list)
    body_of: dict[str, RigidBody] = field(default_factory=dict)
    block_states: dict[str, dict[str, StateSlot]] = field(default_factory=dict)
    theta_index: dict[str, tuple[int, int]] = field(default_factory=dict)  # entry name -> (start, stop)
    theta_size: int = 0
    order: list[str] = field(default_factory=list)  # blocks with outputs, in evaluation order
    driver: dict[tuple[str, str], tuple[str, str]] = field(default_factory=dict)  # input -> driving output
    port_net: dict[tuple[str, str], str] = field(default_factory=dict)

    @property
    def n_states(self) -> int:
        return sum(s.size for s in self.states)


def analyse(circuit: FlatCircuit) -> Structure:
    """Lay out states and parameters and order the blocks; raise NetlistError on structural faults."""
    st = Structure(circuit)
    for net in circuit.nets.values():
        for comp, port in net.ports:
            st.port_net[(comp, port)] = net.name
    _find_prescribed(st)
    _signal_drivers(st)
    _rigid_bodies(st)
    _hydraulic_states(st)
    for body in st.bodies:
        given = [n for n in body.members if f"{n}.initial" in st.circuit.parameters.entries]
        if body.prescribed_by is not None and given:
            entry = st.circuit.parameters.entries[f"{given[0]}.initial"]
            raise entry.error(f"net '{given[0]}' moves with the source {body.prescribed_by[0]}: an initial speed "
                              f"would be ignored")
        if body.prescribed_by is None:
            if not given:
                _name_initial_value(st, st.circuit.nets[body.root], ACROSS[body.kind][1])
            _check_inertia(st, body)
            body.state = _add_state(st, f"{body.root}.{ACROSS[body.kind][0]}", 1, ACROSS[body.kind][1],
                                    PHYSICAL_STATE_NOMINAL[body.kind], body.root, "speed")
    for name, comp in circuit.components.items():
        slots = {}
        for state in comp.cls.states:
            size = 1 if state.size is None else int(state.size(comp.array_lengths))
            slots[state.name] = _add_state(st, f"{name}.{state.name}", size, state.unit, state.nominal, name, "block")
        st.block_states[name] = slots
    _theta_layout(st)
    st.order = _evaluation_order(st)
    _scale_signal_states(st)
    return st


def _scale_signal_states(st: Structure) -> None:
    """A generic block state that names its signal's port takes that signal's nominal magnitude, where known
    (after the parameters are evaluated and the order is found, so that their errors come first)."""
    scales = net_scales(st.circuit)
    for name, comp in st.circuit.components.items():
        for state in comp.cls.states:
            slot = st.block_states[name][state.name]
            slot.nominal = state_nominal(state, name, st.port_net, scales)


def _add_state(st: Structure, name, size, unit, nominal, owner, kind) -> StateSlot:
    slot = StateSlot(name, st.n_states, size, unit, nominal, owner, kind)
    st.states.append(slot)
    return slot


def _find_prescribed(st: Structure) -> None:
    for name, comp in st.circuit.components.items():
        for port in comp.cls.prescribes:
            net = st.port_net[(name, port)]
            if net in st.prescribed:
                other = st.prescribed[net][0]
                raise comp.source.error(comp.path, f"net '{net}' is prescribed by two sources: {other} and {name}")
            st.prescribed[net] = (name, port)
            # not its bulk modulus: a subsystem's fluid gives every net of it one, a held one too; nor a volume
            # written in another file: a reusable part's line volume on a port its user holds at a pressure
            volume = st.circuit.parameters.entries.get(f"{net}.volume")
            for what, given in (("an initial value", st.circuit.parameters.entries.get(f"{net}.initial")),
                               ("a volume", volume if volume is not None and volume.source.file == comp.source.file
                                else None)):
                if given is not None:
                    raise given.error(f"net '{net}' is held by the source {name}: {what} would be ignored")


def _signal_drivers(st: Structure) -> None:
    for net in st.circuit.nets.values():
        if net.kind is not PortKind.SIGNAL:
            continue
        outs = [(c, p) for c, p in net.ports if st.circuit.components[c].cls.port(p).direction == "out"]
        ins = [(c, p) for c, p in net.ports if st.circuit.components[c].cls.port(p).direction == "in"]
        if not outs:
            raise net.source.error(net.path, f"signal net '{net.name}' has no driving output "
                                   f"(it joins only inputs: {', '.join(f'{c}.{p}' for c, p in ins)})"
                                   + _exposed_hint(st, [net.name]))
        if len(outs) > 1:
            raise net.source.error(net.path, f"signal net '{net.name}' is driven by two outputs: "
                                   f"{outs[0][0]}.{outs[0][1]} and {outs[1][0]}.{outs[1][1]}")
        out_port = st.circuit.components[outs[0][0]].cls.port(outs[0][1])
        for target in ins:
            st.driver[target] = outs[0]
            in_port = st.circuit.components[target[0]].cls.port(target[1])
            if not _units_agree(out_port.unit, in_port.unit):
                raise net.source.error(net.path, f"signal net '{net.name}' joins {outs[0][0]}.{outs[0][1]} "
                                       f"[{out_port.unit}] to {target[0]}.{target[1]} [{in_port.unit}]: the units "
                                       f"differ (put a gain between them)")


def _units_agree(a: str, b: str) -> bool:
    """Two signal ports may be joined if either is generic ("SI") or their dimensions agree."""
    from blocks.units import GENERIC, parse_unit

    if GENERIC in (a, b):
        return True
    return parse_unit(a).same_dimension(parse_unit(b))


def _rigid_bodies(st: Structure) -> None:
    mech = [n for n in st.circuit.nets.values() if n.kind in (PortKind.ROTATIONAL, PortKind.TRANSLATIONAL)]
    links = nx.MultiGraph()
    links.add_nodes_from(n.name for n in mech)
    for name, comp in st.circuit.components.items():
        if comp.cls.rigid_link is not None:
            a, b = comp.cls.rigid_link
            links.add_edge(st.port_net[(name, a)], st.port_net[(name, b)], link=name)
    for nodes in nx.connected_components(links):
        sub = links.subgraph(nodes)
        if sub.number_of_edges() >= sub.number_of_nodes():
            names = sorted({d["link"] for _, _, d in sub.edges(data=True)})
            comp = st.circuit.components[names[0]]
            raise comp.source.error(comp.path, f"rigid links {', '.join(names)} form a closed loop "
                                    f"(over-constrained); break it with a compliant coupling")
        prescribing = [n for n in nodes if n in st.prescribed]
        if len(prescribing) > 1:
            comp = st.circuit.components[st.prescribed[prescribing[1]][0]]
            raise comp.source.error(comp.path, f"nets {', '.join(sorted(prescribing))} move rigidly together "
                                    f"but are prescribed by two sources")
        root = prescribing[0] if prescribing else sorted(nodes, key=lambda n: (n.count("."), n))[0]
        members: dict[str, tuple[str | None, str | None, bool]] = {root: (None, None, True)}
        for parent, child in nx.bfs_edges(sub, root):
            data = next(iter(sub.get_edge_data(parent, child).values()))
            comp = data["link"]
            a, _ = st.circuit.components[comp].cls.rigid_link
            forward = st.port_net[(comp, a)] == parent  # w_child = ratio * w_parent
            members[child] = (parent, comp, forward)
        kind = st.circuit.nets[root].kind
        body = RigidBody(root, kind, members, st.prescribed.get(root))
        st.bodies.append(body)
        for n in nodes:
            st.body_of[n] = body


def _exposed_hint(st: Structure, nets: list[str]) -> str:
    """For an error about an incomplete net: when the file exposes it under ``ports:`` (a subsystem part
    validated or run alone), the netlist that uses the part is what completes it (its volume, driver, mass)."""
    ports = st.circuit.netlist.ports
    if not any(ref in nets for ref in ports.values()):
        return ""
    return (f" (this file is a subsystem part: it exposes {', '.join(ports)} under ports:, which the netlist "
            f"using it connects; validate that netlist)")


def _check_inertia(st: Structure, body: RigidBody) -> None:
    for net in body.members:
        for comp, port in st.circuit.nets[net].ports:
            if st.circuit.components[comp].cls.port(port).stores:
                return
    net = st.circuit.nets[body.root]
    what = CAPACITY[body.kind][0]
    raise net.source.error(net.path, f"{body.kind.value} net '{body.root}' has no inertia: attach a block that "
                           f"stores {'inertia' if what == 'J' else 'mass'} (e.g. {'inertia' if what == 'J' else 'mass'})"
                           + _exposed_hint(st, list(body.members)))


def _hydraulic_states(st: Structure) -> None:
    circuit = st.circuit
    for net in circuit.nets.values():
        if net.kind is not PortKind.HYDRAULIC or net.name in st.prescribed:
            continue
        stores = any(circuit.components[c].cls.port(p).stores for c, p in net.ports)
        if not net.has_volume and not stores:
            if net.default_volume is None:
                raise net.source.error(net.path, f"hydraulic net '{net.name}' has no volume: give it volume:, "
                                       f"attach a volume component, or set defaults: volume: in the netlist "
                                       f"(a net held at a pressure, such as a return line, gets a tank or "
                                       f"pressure_source instead)" + _exposed_hint(st, [net.name]))
            raw, source, scope = net.default_volume
            circuit.parameters.add(make_entry(f"{net.name}.volume", raw, "m^3", scope, source, ("defaults", "volume"),
                                              NET_BOUNDS["volume"]))
            net.has_volume = True
        slot = _add_state(st, f"{net.name}.p", 1, "Pa", PHYSICAL_STATE_NOMINAL[PortKind.HYDRAULIC], net.name,
                          "pressure")
        st.net_state[net.name] = slot
        _name_initial_value(st, net, "Pa")


def _name_initial_value(st: Structure, net, unit: str) -> None:
    """A state net without initial: starts at 0, under the name '<net>.initial' (so --set can change it)."""
    name = f"{net.name}.initial"
    if name not in st.circuit.parameters.entries:
        st.circuit.parameters.add(Entry(name, unit, 0.0, None, {}, net.source, net.path, dims=None))


def _theta_layout(st: Structure) -> None:
    """Every parameter-table entry the equations read gets a slice of theta."""
    entries = st.circuit.parameters.entries
    values = st.circuit.parameters.evaluate()  # also checks every default once
    st.circuit.parameters.check_unread(values)  # and what no value reads (a defaults: volume: no net takes)
    names = ["fluid.beta"] + (["fluid.vapour_pressure"] if cavitation(st) or entrained_air(st) else [])
    names += ["fluid.air", "fluid.air_index"] if entrained_air(st) else []
    for name, comp in st.circuit.components.items():
        names += [f"{name}.{p.name}" for p in comp.cls.params]
    for net in st.net_state:
        names += [n for n in (f"{net}.volume", f"{net}.bulk_modulus") if n in entries]
    offset = 0
    for name in names:
        value = values[name]
        size = len(value) if isinstance(value, tuple) else 1
        st.theta_index[name] = (offset, offset + size)
        offset += size
    st.theta_size = offset


def cavitation(st: Structure) -> bool:
    """Whether the nets' pressure equation holds a vapour cavity (blocks.library.hydraulic.cavitation)."""
    return bool(st.circuit.netlist.fluid.cavitation)


def entrained_air(st: Structure) -> bool:
    """Whether the nets' pressure equation has free air in the oil (blocks.library.hydraulic.entrained_air)."""
    return st.circuit.netlist.fluid.air is not None


def bulk_modulus_name(st: Structure, net: str) -> str:
    name = f"{net}.bulk_modulus"
    return name if name in st.theta_index else "fluid.beta"


def _per_output_pattern(st: Structure, name: str, cls, port_reads, net_states):
    """[(states written, states read)] for each value ``cls.derivatives`` returns, from what each one reads
    (:mod:`blocks.compiler.output_reads`); None where that is not known (the block is then taken whole: each
    state it writes reads everything it reads). A block with a capacity or an array state is taken whole."""
    from blocks.compiler.output_reads import derivative_reads

    if cls.storing_ports() or len(cls.scalar_states()) != len(cls.states):
        return None
    names = cls.derivative_names()
    reads = derivative_reads(cls.derivatives, len(names))
    if reads is None:
        return None
    own = st.block_states[name]

    def read(args) -> set[int]:
        found: set[int] = set()
        for arg in sorted(args):
            if arg in own:  # one of the block's own states: that state alone
                found |= set(range(own[arg].index, own[arg].index + own[arg].size))
            else:
                found |= port_reads(name, [arg])
        return found

    out = []
    k = 0
    for port in cls.through_ports():
        net = st.port_net[(name, port.name)]
        writes = net_states(net) if net not in st.prescribed else set()
        out.append((writes, read(reads[k])))
        k += 1
    for state in cls.scalar_states():
        slot = st.block_states[name][state.name]
        out.append((set(range(slot.index, slot.index + slot.size)), read(reads[k])))
        k += 1
    assert k == len(names)
    return out


def block_reads(st: Structure, name: str, function: str) -> list[str]:
    from blocks.block import argument_names

    fn = getattr(st.circuit.components[name].cls, function)
    return [] if fn is None else argument_names(fn)


def _evaluation_order(st: Structure) -> list[str]:
    """Blocks that have outputs, ordered so that every output is computed before it is read."""
    graph = nx.DiGraph()
    producers = {}
    for name, comp in st.circuit.components.items():
        if comp.cls.outputs is not None:
            graph.add_node(name)
    for net, (comp, _) in st.prescribed.items():
        producers[net] = comp
    for name, comp in st.circuit.components.items():
        if comp.cls.outputs is None:
            continue
        for arg in comp.cls.feedthrough():
            port = comp.cls.port(arg)
            if port.kind is PortKind.SIGNAL:
                src = st.driver.get((name, arg))
                if src is not None:
                    graph.add_edge(src[0], name)
            else:
                net = st.port_net[(name, arg)]
                body = st.body_of.get(net)
                source_net = body.root if body is not None else net
                if source_net in producers:
                    graph.add_edge(producers[source_net], name)
    try:
        cycle = nx.find_cycle(graph)
    except nx.NetworkXNoCycle:
        return list(nx.lexicographical_topological_sort(graph))
    blocks_in_loop = [edge[0] for edge in cycle]
    comp = st.circuit.components[blocks_in_loop[0]]
    raise comp.source.error(comp.path, "algebraic loop through blocks " + " -> ".join(blocks_in_loop + blocks_in_loop[:1])
                            + " (each reads the other's output directly; put a dynamic block in the loop)")


def jacobian_pattern(st: Structure, per_output: bool = True):
    """Which state derivatives may depend on which states, from the netlist graph and, per value a block's
    ``derivatives`` returns, the arguments that value reads (:mod:`blocks.compiler.output_reads`; a block
    it cannot read is taken whole: each state it writes reads everything it reads). The finite-difference
    Jacobian groups the columns no row shares, so a finer pattern means fewer right-hand-side calls (the
    valve's flows and its spool's own equation apart: 13018 -> 9161 calls in netlists/opt/bridge_travel.yaml)
    and the same Jacobian, entry for entry: a value that does not read a state does not move with it.
    ``per_output`` False takes every block whole (bench/jacobian_pattern.py compares the two)."""
    import numpy as np

    n = st.n_states
    pattern = np.zeros((n, n), dtype=np.bool_)
    reads_cache: dict[str, set[int]] = {}

    def net_states(net: str) -> set[int]:
        """States the across value of ``net`` depends on (through a source, a rigid body's source...)."""
        if net in st.net_state:
            return {st.net_state[net].index}
        body = st.body_of.get(net)
        if body is not None and body.state is not None:
            return {body.state.index}
        if body is not None and body.prescribed_by is not None:
            return output_reads(body.prescribed_by[0])
        if net in st.prescribed:
            return output_reads(st.prescribed[net][0])
        return set()

    def own_states(name: str) -> set[int]:
        return {i for slot in st.block_states[name].values() for i in range(slot.index, slot.index + slot.size)}

    def port_reads(name: str, args) -> set[int]:
        comp = st.circuit.components[name]
        found: set[int] = set()
        for arg in args:
            if arg in st.block_states[name]:
                found |= own_states(name)
                continue
            try:
                port = comp.cls.port(arg)
            except KeyError:
                continue
            if port.kind is PortKind.SIGNAL:
                src = st.driver.get((name, arg))
                if src is not None:
                    found |= output_reads(src[0])
            else:
                found |= net_states(st.port_net[(name, arg)])
        return found

    def output_reads(name: str) -> set[int]:
        if name not in reads_cache:
            reads_cache[name] = set()  # guards recursion; the order is acyclic anyway
            reads_cache[name] = port_reads(name, block_reads(st, name, "outputs"))
        return reads_cache[name]

    for name, comp in st.circuit.components.items():
        if comp.cls.derivatives is None:
            continue
        by_value = _per_output_pattern(st, name, comp.cls, port_reads, net_states) if per_output else None
        if by_value is not None:
            for writes, reads in by_value:
                for w in writes:
                    for r in reads:
                        pattern[w, r] = True
            continue
        reads = port_reads(name, block_reads(st, name, "derivatives"))
        writes = own_states(name)
        for port in comp.cls.through_ports() + comp.cls.storing_ports():
            writes |= net_states(st.port_net[(name, port.name)]) if st.port_net[(name, port.name)] not in st.prescribed else set()
        if comp.cls.storing_ports():
            # a capacity divides the whole net balance: the net's derivative reads everything on the net
            for port in comp.cls.storing_ports():
                net = st.port_net[(name, port.name)]
                for c, _ in st.circuit.nets[net].ports:
                    reads |= port_reads(c, block_reads(st, c, "derivatives"))
        for w in writes:
            for r in reads:
                pattern[w, r] = True
    for body in st.bodies:
        if body.state is not None:
            i = body.state.index
            pattern[i, i] = True
    for slot in st.net_state.values():
        pattern[slot.index, slot.index] = True
    return pattern
