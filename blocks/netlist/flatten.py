"""From a netlist file to a flat circuit: subsystems expanded, names qualified, nets resolved into nodes.

Checks made here (each error names the file, line and column): unknown block type (with the nearest
names), unknown or missing parameter, wrong unit, value out of bounds (when evaluated), unknown port,
a port left unconnected or connected twice, ports of different kinds on one net, a signal net with no
driver or two, duplicate names, a hydraulic node without a volume, a mechanical node without inertia,
two sources prescribing one net, and subsystem files that include themselves.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from blocks import registry
from blocks.block import ACROSS, Block, Param, PortKind
from blocks.errors import NetlistError
from blocks.netlist import spec
from blocks.netlist.parameters import Entry, ParameterTable, make_array_entry, make_entry
from blocks.netlist.shape import load_spec
from blocks.netlist.yaml_source import Located, read_yaml
from blocks.solve.settings import settings_of
from blocks.units import GENERIC, nearest, parse_unit

MAX_SUBSYSTEM_DEPTH = 8
RESERVED = {"fluid", "pi", "e"} | {
    "sqrt", "exp", "log", "log10", "abs", "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "tanh", "hypot",
    "min", "max", "floor", "ceil", "radians", "degrees"}
FLUID_BOUNDS = {
    "rho": Param("rho", "kg/m^3", None, 1.0, 5000.0, "fluid density"),
    "nu": Param("nu", "m^2/s", None, 1e-8, 1e-2, "kinematic viscosity"),
    "beta": Param("beta", "Pa", None, 1e6, 1e11, "bulk modulus"),
    "vapour_pressure": Param("vapour_pressure", "Pa", None, -1.01325e5, 1e6, "vapour pressure (gauge)"),
    "air": Param("air", "1", None, 0.0, 0.5, "entrained air, volume fraction at atmospheric pressure"),
    "air_index": Param("air_index", "1", None, 1.0, 1.4, "polytropic index of the entrained air"),
}
# Derived from the top-level fluid, not written: the pressure below which the model turns oil into vapour
# (a displacement machine's chambers fill with vapour below it: blocks.library.hydraulic.displacement). It is
# the vapour pressure with the cavitation law on, and never (NO_VAPOUR) with `cavitation: false`, where the
# oil is the liquid at every pressure, as in the thesis's Simulink model.
CAVITATION_PRESSURE = Param("cavitation_pressure", "Pa", None, None, 1e6,
                            "below it oil turns to vapour: the vapour pressure, or never with cavitation: false")
NO_VAPOUR = -1e30  # Pa: a pressure no circuit reaches
TOP_LEVEL_FLUID = (("vapour_pressure", "the vapour pressure"), ("cavitation", "fluid cavitation"),
                   ("air", "the entrained air"), ("air_index", "the entrained air's index"))
NET_BOUNDS = {
    "volume": Param("volume", "m^3", None, 0.0, 1e3, "volume of a hydraulic net", positive=True),
    "bulk_modulus": Param("bulk_modulus", "Pa", None, 0.0, 1e12, "bulk modulus of a hydraulic net", positive=True),
}


@dataclass
class FlatComponent:
    name: str
    cls: type[Block]
    source: Located
    path: tuple
    array_lengths: dict[str, int] = field(default_factory=dict)


@dataclass
class FlatNet:
    name: str
    kind: PortKind | None
    ports: list[tuple[str, str]]  # (component, port)
    source: Located
    path: tuple
    has_volume: bool = False  # a volume entry "<net>.volume" exists
    default_volume: tuple | None = None  # (raw, file, scope) of the defaults: volume: that applies here


@dataclass
class FlatOutput:
    name: str
    of: str
    unit: str | None
    source: Located
    path: tuple


@dataclass
class FlatCircuit:
    """Everything the compiler needs; names are qualified (``left.valve``)."""

    file: str
    netlist: spec.Netlist
    source: Located
    components: dict[str, FlatComponent]
    nets: dict[str, FlatNet]
    parameters: ParameterTable
    outputs: list[FlatOutput]
    aliases: dict[str, str] = field(default_factory=dict)
    """Other names of things: a subsystem's exposed port ("bridge.x_ref") -> its inner net or port, and a
    net merged into another through a subsystem port ("bridge.P") -> the net it became ("P")."""
    files: list[str] = field(default_factory=list)
    """Every file the circuit was built from, resolved, each once in the order read: the netlist, its
    subsystem files, the data files of its ``{csv:, column:}`` parameters (what a result depends on)."""

    def resolve_alias(self, name: str) -> str:
        return follow_aliases(self.aliases, name)


def follow_aliases(aliases: dict[str, str], name: str) -> str:
    """What ``name`` is under its other names (an exposed port through nested subsystems), at most 50 deep."""
    seen = 0
    while name in aliases and seen < 50:
        name, seen = aliases[name], seen + 1
    return name


def flatten(file: str | Path) -> FlatCircuit:
    """Read ``file`` and everything it includes into one :class:`FlatCircuit`."""
    located = read_yaml(file)
    netlist = load_spec(located)
    builder = _Builder()
    builder.read(file)
    fluid = builder.add_fluid(netlist, located)
    builder.add_netlist(netlist, located, prefix="", overrides={},
                        stack=(str(Path(file).resolve()),), fluid=fluid, default_volume=None)
    if not builder.components:
        raise _no_components(located)
    nets = builder.resolve_nets()
    outputs = [
        FlatOutput(name, out if isinstance(out, str) else out.of, None if isinstance(out, str) else out.unit,
                   located, ("outputs", name))
        for name, out in netlist.outputs.items()
    ]
    for exposed, ref in netlist.ports.items():  # a file's own exposed ports must name something real
        if ref not in builder.net_names:
            builder._resolve_ref(ref, ref, located, ("ports", exposed))
    aliases = {k: v for k, v in {**builder.aliases, **builder.merged_into}.items() if k != v}
    circuit = FlatCircuit(str(file), netlist, located, builder.components, nets, builder.table, outputs, aliases,
                          list(builder.files))
    builder.table.order()  # unknown names and cycles are reported now, not at the first evaluation
    return circuit


def _no_components(located: Located) -> NetlistError:
    """A netlist whose circuit has no block (an empty file, only a description, ``components: {}``): there is
    nothing to simulate, and running it would write a CSV of time alone as if it were a result. Placed at
    ``components:`` if written, else at the document's start (line 1 of an empty file)."""
    line, column = located.where(("components",))
    return NetlistError(located.file, "the netlist has no components: a circuit needs at least one block "
                        "(components: {<name>: {type: <block type>, params: {...}}})", line or 1, column or 1)


class _Builder:
    def __init__(self) -> None:
        self.components: dict[str, FlatComponent] = {}
        self.table = ParameterTable()
        self.raw_nets: list[tuple[str, spec.Net, Located, tuple]] = []
        self.aliases: dict[str, str] = {}  # exposed subsystem port "left.P" -> internal ref
        self.net_names: set[str] = set()
        self.port_refs: list[tuple[str, str, Located, tuple]] = []
        self.merged_into: dict[str, str] = {}
        self.default_volume: dict[str, tuple | None] = {}
        self.auto_bulk: set[str] = set()
        self.subsystem_names: set[str] = set()
        self.subsystem_where: dict[str, tuple[Located, tuple, str]] = {}  # name -> where declared, its file
        # each file's scope, prefix and nets, for the dotted names of its nets' initial values (A.initial),
        # known once the nets are merged: a net joined to another through a subsystem port has one start
        self.net_scopes: list[tuple[dict[str, str], str, list[str]]] = []
        self.files: dict[str, None] = {}  # FlatCircuit.files (a dict keeps the order and each file once)

    def read(self, file) -> None:
        """Note a file the circuit is built from (:attr:`FlatCircuit.files`)."""
        self.files.setdefault(str(Path(file).resolve()), None)

    # ---- parameters ---------------------------------------------------------------------------------
    def add_fluid(self, netlist: spec.Netlist, located: Located, prefix: str = "",
                  parent: dict[str, str] | None = None) -> dict[str, str]:
        """The fluid entries of a file; returns its scope's names for them (fluid_rho -> 'fluid.rho').

        The top-level file defines fluid.*; a subsystem file that sets fluid properties itself gets its own
        (``left.fluid.beta``) for its components and nets, and inherits the others from the file using it."""
        if parent is None:
            keys = [k for k in FLUID_BOUNDS if getattr(netlist.fluid, k) is not None]
        else:
            keys = [k for k in netlist.fluid.model_fields_set if k in FLUID_BOUNDS]
            for key, what in TOP_LEVEL_FLUID:
                if key in netlist.fluid.model_fields_set:
                    raise located.error(("fluid", key), f"{what} is set by the top-level netlist only (it "
                                        f"decides the law of every net's pressure)")
        names = dict(parent or {})
        for key in keys:
            name = f"{prefix}fluid.{key}"
            self.table.add(make_entry(name, getattr(netlist.fluid, key), FLUID_BOUNDS[key].unit, {}, located,
                                      ("fluid", key), FLUID_BOUNDS[key]))
            names[f"fluid_{key}"] = name
        if parent is None:
            raw = "fluid_vapour_pressure" if netlist.fluid.cavitation else NO_VAPOUR
            self.table.add(make_entry("fluid.cavitation_pressure", raw, "Pa", names, located,
                                      ("fluid", "cavitation"), CAVITATION_PRESSURE))
            names["fluid_cavitation_pressure"] = "fluid.cavitation_pressure"
            self.table.derived["fluid.cavitation_pressure"] = ("fluid.vapour_pressure (and the netlist's fluid: "
                                                               "{cavitation:})")
        return names

    def add_netlist(self, netlist: spec.Netlist, located: Located, prefix: str, overrides: dict,
                    stack: tuple, fluid: dict[str, str], default_volume) -> None:
        """Add one file's parameters, components, subsystems and nets under ``prefix``.

        ``overrides`` are what the file using this one (as a subsystem) sets, by name: each
        ``(raw, source, path, scope)``, read in the scope of the file that wrote it. A name is one of this
        file's parameters, ``<component>.<parameter>`` of a component in it (as ``--set`` takes it), or
        ``<subsystem>.<name>``, passed on to a subsystem of this file."""
        for name in netlist.parameters:
            if not name.isidentifier() or name in RESERVED or name.startswith("_"):
                raise located.error(("parameters", name), f"'{name}' cannot be a parameter name (a name is letters, "
                                    f"digits and '_', starts with a letter, and is not one of {', '.join(sorted(RESERVED))})")
        scope = {name: prefix + name for name in netlist.parameters}
        scope.update(fluid)
        if netlist.defaults.volume is not None:  # this file's default, for its own nets (and its subsystems')
            default_volume = (netlist.defaults.volume, located, scope)
            # checked as written even where no net takes it (ParameterTable.check_unread)
            self.table.unread.append(make_entry(f"{prefix}defaults.volume", netlist.defaults.volume, "m^3", scope,
                                                located, ("defaults", "volume"), NET_BOUNDS["volume"]))
        for name, raw in netlist.parameters.items():
            if name in overrides:
                raw_value, over_source, over_path, over_scope = overrides[name]
                self.table.add(make_entry(prefix + name, raw_value, None, over_scope, over_source, over_path))
            else:
                self.table.add(make_entry(prefix + name, raw, None, scope, located, ("parameters", name)))
        inner: dict[str, dict] = {}  # component or subsystem name -> its overrides
        for name, override in overrides.items():
            head, dot, rest = name.partition(".")
            if name in netlist.parameters:
                continue
            if dot and (head in netlist.subsystems or (head in netlist.components and "." not in rest)):
                inner.setdefault(head, {})[rest] = override
                continue
            _, over_source, over_path, _ = override
            known = registry.all_types()
            hint = nearest(name, list(netlist.parameters) + [f"{c}.{p.name}" for c, comp in netlist.components.items()
                                                             if comp.type in known for p in known[comp.type].params])
            raise over_source.error(over_path, f"'{name}' is not a parameter of {located.file} (nor "
                                    f"'<component>.<parameter>' of a component in it)"
                                    + (f"; did you mean {', '.join(hint)}?" if hint else ""))
        for name, comp in netlist.components.items():
            self._add_component(prefix, name, comp, located, scope, inner.get(name, {}))
        for name, sub in netlist.subsystems.items():
            self._add_subsystem(prefix, name, sub, located, scope, stack, fluid, default_volume, inner.get(name, {}))
        for name, net in netlist.nets.items():
            qualified = prefix + name
            if qualified in self.components or qualified in self.net_names or qualified in self.subsystem_names:
                raise located.error(("nets", name), f"duplicate name '{name}' (a component, subsystem or net "
                                                    f"already has it)")
            if name == "fluid":
                raise located.error(("nets", name), "'fluid' is a reserved name")
            self.net_names.add(qualified)
            net_spec = netlist.net(name)
            self.raw_nets.append((qualified, net_spec, located, ("nets", name)))
            self.default_volume[qualified] = default_volume
            for key, unit in (("volume", "m^3"), ("bulk_modulus", "Pa"), ("initial", None)):
                raw = getattr(net_spec, key)
                if raw is None and key == "bulk_modulus" and fluid.get("fluid_beta", "fluid.beta") != "fluid.beta":
                    raw = "fluid_beta"  # a subsystem's own fluid (not carried onto an outer net it joins)
                    self.auto_bulk.add(f"{qualified}.bulk_modulus")
                if raw is not None:
                    self.table.add(make_entry(f"{qualified}.{key}", raw, unit, scope, located, ("nets", name, key),
                                              NET_BOUNDS.get(key)))
        # this file's component parameters, readable by their dotted names (supply.p) in its own expressions:
        # the entries of this file hold this same scope dict (a subsystem's parameter overrides are read in
        # the parent's scope, with the parent's names); its nets' initial values (A.initial) join it once the
        # nets are merged (:meth:`_merge_net_entries`)
        components = tuple(prefix + name + "." for name in netlist.components)
        for qualified in self.table.entries:
            local = qualified[len(prefix):]
            if qualified.startswith(components) and local.count(".") == 1:
                scope[local] = qualified
        self.net_scopes.append((scope, prefix, list(netlist.nets)))
        for exposed, ref in netlist.ports.items():
            self.aliases[prefix + exposed] = prefix + ref

    def _add_component(self, prefix: str, name: str, comp: spec.Component, located: Located, scope: dict,
                       overrides: dict) -> None:
        qualified = prefix + name
        path = ("components", name)
        if qualified in self.components:
            raise located.error(path, f"duplicate component name '{name}'")
        if "." in name:
            raise located.error(path, f"component name '{name}' may not contain '.'")
        if name == "fluid":
            raise located.error(path, "'fluid' is a reserved name")
        try:
            cls = registry.get(comp.type)
        except KeyError as exc:
            raise located.error(path + ("type",), f"{name}: {exc.args[0]}") from None
        flat = FlatComponent(qualified, cls, located, path)
        declared = {p.name: p for p in cls.params}
        def not_declared(key: str) -> str:
            hint = nearest(key, declared)
            return (f"'{key}' is not a parameter of {comp.type}" + (f" (did you mean {', '.join(hint)}?)" if hint else
                                                                    f" (its parameters: {', '.join(declared) or 'none'})"))

        for key in comp.params:
            if key not in declared:
                raise located.error(path + ("params", key), f"{name}: {not_declared(key)}")
        for key, (_, over_source, over_path, _) in overrides.items():
            if key not in declared:
                raise over_source.error(over_path, f"'{name}.{key}': {not_declared(key)}")
        # each value given: (raw, path, file, scope), the file and scope it is read in
        given = {key: (raw, path + ("params", key), located, scope) for key, raw in comp.params.items()}
        if comp.preset is not None:
            if comp.preset not in cls.presets:
                choices = ", ".join(cls.presets) or "none"
                raise located.error(path + ("preset",), f"{name}: {comp.type} has no preset '{comp.preset}' "
                                    f"(its presets: {choices})")
            for key, raw in cls.presets[comp.preset].items():
                given.setdefault(key, (raw, path + ("preset",), located, scope))
        given.update({key: (raw, over_path, over_source, over_scope)  # the using file's word is the last
                      for key, (raw, over_source, over_path, over_scope) in overrides.items()})
        for param in cls.params:
            entry_name = f"{qualified}.{param.name}"
            if param.name in given:
                raw, ppath, source, read_scope = given[param.name]
                if param.array:
                    entry = self._array_entry(entry_name, raw, param, source, ppath, name, read_scope)
                    flat.array_lengths[param.name] = len(entry.elements or entry.constant)
                    self.table.add(entry)
                    continue
                if isinstance(raw, (list, spec.CsvColumn)):
                    raise source.error(ppath, f"{name}: {param.name} takes a single value, not a list")
                self.table.add(make_entry(entry_name, raw, param.unit, read_scope, source, ppath, param))
            elif param.fluid is not None:
                self.table.add(make_entry(entry_name, f"fluid_{param.fluid}", param.unit, scope, located, path, param))
            elif param.default is not None:
                if param.array:
                    flat.array_lengths[param.name] = len(param.default)
                    self.table.add(Entry(entry_name, param.unit, tuple(param.default), None, scope, located, path, param))
                else:
                    self.table.add(Entry(entry_name, param.unit, float(param.default), None, scope, located, path, param))
            else:
                raise located.error(path + ("params",), f"{name}: missing parameter '{param.name}' "
                                    f"[{param.unit}] of {comp.type} ({param.description})")
        states = {s.name: s for s in cls.states}
        for key, raw in comp.initial.items():
            if key not in states:
                raise located.error(path + ("initial", key), f"{name}: '{key}' is not a state of {comp.type}"
                                    f" (its states: {', '.join(states) or 'none'})")
            if states[key].size is not None:
                raise located.error(path + ("initial", key), f"{name}: the array state '{key}' starts at its default")
            self.table.add(make_entry(f"{qualified}.initial.{key}", raw, states[key].unit, scope, located,
                                      path + ("initial", key)))
        for state in cls.states:  # every scalar start value has a name, so an optimiser or --set can set it
            if state.size is None and state.name not in comp.initial:
                self.table.add(Entry(f"{qualified}.initial.{state.name}", state.unit, float(state.start), None,
                                     scope, located, path, dims=None))
        self.components[qualified] = flat

    def _array_entry(self, entry_name, raw, param, located: Located, path: tuple, name: str, scope) -> Entry:
        if isinstance(raw, spec.CsvColumn):
            values, lines = read_csv_column(Path(located.file).parent / raw.csv, raw.column, param.unit, located, path)
            self.read(Path(located.file).parent / raw.csv)
            return Entry(entry_name, param.unit, values, None, scope, located, path, param, raw=raw, lines=lines)
        if not isinstance(raw, list) or not raw:
            raise located.error(path, f"{name}: {param.name} takes a non-empty list of values or {{csv:, column:}}")
        return make_array_entry(entry_name, raw, param.unit, scope, located, path, param)

    def _unconnected_exposed(self, port: str, kind: str) -> str:
        """An inner port left unconnected because the file using its subsystem does not connect the port
        the subsystem exposes it as: raised at that subsystem, in that file (the one to mend). A port the
        top file itself exposes (a subsystem part validated alone) gets a hint to add; else ''."""
        exposed = sorted((name for name in self.aliases if follow_aliases(self.aliases, name) == port),
                         key=lambda name: name.count("."))
        if not exposed:
            return ""
        if "." not in exposed[0]:
            return (f" (this file is a subsystem part: it exposes it as {exposed[0]} under ports:, which the "
                    f"netlist using it connects; validate that netlist)")
        sub, _, local = exposed[0].rpartition(".")
        located, path, file = self.subsystem_where[sub]
        raise located.error(path, f"subsystem '{sub.rsplit('.', 1)[-1]}': its port {local} ({kind}) is not "
                                  f"connected (it is {port[len(sub) + 1:]} inside {file})")

    def _add_subsystem(self, prefix: str, name: str, sub: spec.Subsystem, located: Located, scope: dict,
                       stack: tuple, fluid: dict[str, str], default_volume, passed: dict) -> None:
        """Expand a subsystem; its ``parameters:`` (read in this file's ``scope``) and what the file using
        this one ``passed`` on to it set values inside it (:meth:`add_netlist`)."""
        path = ("subsystems", name)
        qualified = prefix + name
        if qualified in self.components:
            raise located.error(path, f"duplicate name '{name}' (a component already has it)")
        file = (Path(located.file).parent / sub.netlist)
        resolved = str(file.resolve())
        if resolved in stack:
            raise located.error(path + ("netlist",), f"subsystem '{name}' includes {sub.netlist}, which includes itself")
        if len(stack) > MAX_SUBSYSTEM_DEPTH:
            raise located.error(path, f"subsystems nested deeper than {MAX_SUBSYSTEM_DEPTH}")
        try:
            inner_located = read_yaml(file)
        except NetlistError as exc:
            if exc.line is None:  # the file itself is unreadable: say where it is named
                raise located.error(path + ("netlist",), f"subsystem '{name}': {sub.netlist}: {exc.message}") from None
            raise
        self.read(file)
        inner = load_spec(inner_located)
        if "simulation" in inner_located.data:  # unused here, but the file's own when it is run alone
            settings_of(inner.simulation, inner_located)
        overrides = {k: (v, located, path + ("parameters", k), scope) for k, v in sub.parameters.items()}
        overrides.update(passed)  # the outer file's word is the last
        self.components[qualified] = None  # reserve the name
        inner_fluid = self.add_fluid(inner, inner_located, qualified + ".", fluid)
        self.add_netlist(inner, inner_located, qualified + ".", overrides, stack + (resolved,), inner_fluid,
                         default_volume)
        del self.components[qualified]
        self.subsystem_names.add(qualified)
        self.subsystem_where[qualified] = (located, path, sub.netlist)

    # ---- nets ---------------------------------------------------------------------------------------
    def resolve_nets(self) -> dict[str, FlatNet]:
        """Join the nets (subsystem ports merge inner and outer nets) and check every port once."""
        parent: dict[str, str] = {}

        def find(a: str) -> str:
            while parent.get(a, a) != a:
                a = parent[a]
            return a

        def union(a: str, b: str) -> None:
            ra, rb = find(a), find(b)
            if ra != rb:
                # keep the outer (shorter) name as the representative
                keep, drop = (ra, rb) if (ra.count("."), ra) <= (rb.count("."), rb) else (rb, ra)
                parent[drop] = keep

        ports_of: dict[str, list[tuple[str, str, Located, tuple]]] = {}
        owner: dict[tuple[str, str], str] = {}
        exposed_owner: dict[str, str] = {}  # an exposed subsystem port naming an inner net -> the net it is in
        for net_name, net, located, path in self.raw_nets:
            parent.setdefault(net_name, net_name)
            prefix = net_name.rsplit(".", 1)[0] + "." if "." in net_name else ""
            for i, ref in enumerate(net.ports):
                ppath = path + ("ports", i) if isinstance(located.data, dict) else path
                if not isinstance(located.data.get("nets", {}).get(path[-1]), dict):
                    ppath = path + (i,)
                target = self._resolve_ref(prefix + ref, ref, located, ppath)
                key = prefix + ref if isinstance(target, str) else target
                known = exposed_owner if isinstance(target, str) else owner
                if key in known and known[key] != net_name:  # two nets would silently become one
                    raise located.error(ppath, f"port {ref} is connected twice (nets '{known[key]}' and "
                                               f"'{net_name}')")
                if key in known:
                    raise located.error(ppath, f"port {ref} is listed twice in net '{net_name}'")
                known[key] = net_name
                if isinstance(target, str):  # an exposed subsystem port naming an inner net
                    parent.setdefault(target, target)
                    union(net_name, target)
                    continue
                comp, port = target
                ports_of.setdefault(net_name, []).append((comp, port, located, ppath))
        merged: dict[str, FlatNet] = {}
        for net_name, *_ in self.raw_nets:
            if find(net_name) != net_name:
                self.merged_into[net_name] = find(net_name)
        for net_name, net, located, path in self.raw_nets:
            root = find(net_name)
            flat = merged.setdefault(root, FlatNet(root, None, [], located, path))
            if root == net_name:
                flat.source, flat.path = located, path
            for comp, port, src, ppath in ports_of.get(net_name, []):
                kind = self.components[comp].cls.port(port).kind
                if flat.kind is None:
                    flat.kind = kind
                elif flat.kind is not kind:
                    first = flat.ports[0]
                    raise src.error(ppath, f"net '{root}' joins ports of different kinds: "
                                    f"{first[0]}.{first[1]} is {flat.kind.value}, {comp}.{port} is {kind.value}")
                flat.ports.append((comp, port))
        self._merge_net_entries(merged, find)
        self._check_net_entries(merged)
        for comp_name, comp in self.components.items():
            for port in comp.cls.ports:
                if (comp_name, port.name) not in owner and not port.optional and port.direction != "out":
                    hint = self._unconnected_exposed(f"{comp_name}.{port.name}", port.kind.value)
                    raise comp.source.error(comp.path, f"port {comp_name}.{port.name} ({port.kind.value}) is not "
                                                       f"connected" + hint)
        for flat in merged.values():
            if not flat.ports:
                raise flat.source.error(flat.path, f"net '{flat.name}' connects no ports")
        return merged

    def _merge_net_entries(self, merged: dict[str, FlatNet], find) -> None:
        """Nets merged through subsystem ports: their volumes add up (each evaluated in its own file's scope,
        so overriding one still works); an outer initial value or bulk modulus wins."""
        volumes: dict[str, list[str]] = {}
        for net_name, *_ in self.raw_nets:
            if f"{net_name}.volume" in self.table.entries:
                volumes.setdefault(find(net_name), []).append(f"{net_name}.volume")
        for root, names in volumes.items():
            if names == [f"{root}.volume"]:
                continue
            first = self.table.entries[names[0]]
            if f"{root}.volume" in self.table.entries:  # the root's own volume keeps its value under a new name
                own = self.table.entries.pop(f"{root}.volume")
                own.name = f"{root}.volume_own"
                self.table.entries[own.name] = own
                names = [own.name if n == f"{root}.volume" else n for n in names]
            scope = {f"_v{i}": name for i, name in enumerate(names)}
            total = make_entry(f"{root}.volume", " + ".join(scope), "m^3", scope, first.source, first.path,
                               NET_BOUNDS["volume"])
            self.table.entries[total.name] = total
        for net_name, _, located, path in self.raw_nets:
            root = find(net_name)
            if root == net_name:
                continue
            if self.default_volume.get(root) is None and self.default_volume.get(net_name) is not None:
                self.default_volume[root] = self.default_volume[net_name]
            for key in ("initial", "bulk_modulus"):
                entry = self.table.entries.pop(f"{net_name}.{key}", None)
                if entry is not None and entry.name in self.auto_bulk:
                    continue  # a merged net is in the outer file's fluid unless a bulk modulus is written
                if entry is not None and f"{root}.{key}" not in self.table.entries:
                    entry.name = f"{root}.{key}"
                    self.table.entries[entry.name] = entry
        for flat in merged.values():
            flat.has_volume = f"{flat.name}.volume" in self.table.entries
            flat.default_volume = self.default_volume.get(flat.name)
        for scope, prefix, nets in self.net_scopes:  # a merged net starts at its root's one initial value
            for name in nets:
                start = f"{find(prefix + name)}.initial"
                if start in self.table.entries:
                    scope[f"{name}.initial"] = start
        self.table._order = None

    def _check_net_entries(self, merged: dict[str, FlatNet]) -> None:
        """Volumes and bulk moduli belong to hydraulic nets; an initial value is in the net's across unit."""
        for net in merged.values():
            for key in ("volume", "bulk_modulus"):
                entry = self.table.entries.get(f"{net.name}.{key}")
                if entry is not None and net.kind is not PortKind.HYDRAULIC:
                    raise entry.error(f"net '{net.name}' is {net.kind.value if net.kind else 'empty'}: "
                                      f"only a hydraulic net has a {key.replace('_', ' ')}")
            entry = self.table.entries.get(f"{net.name}.initial")
            if entry is None:
                continue
            if net.kind not in ACROSS:
                raise entry.error(f"net '{net.name}' is a signal net: it has no initial value "
                                  f"(set the initial state of the block that drives it)")
            unit = ACROSS[net.kind][1]
            fixed = make_entry(entry.name, entry.raw, unit, entry.scope, entry.source, entry.path)
            self.table.entries[entry.name] = fixed
        self.table._order = None

    def _resolve_ref(self, qualified: str, ref: str, located: Located, path: tuple):
        """'valve.A' -> (component, port); an exposed subsystem port -> its inner net or port."""
        seen = 0
        while qualified in self.aliases and seen < 20:
            target = self.aliases[qualified]
            seen += 1
            if target in self.net_names:
                return target
            qualified = target
        if "." not in qualified:
            raise located.error(path, f"'{ref}' is not '<component>.<port>'")
        comp_name, port_name = qualified.rsplit(".", 1)
        comp = self.components.get(comp_name)
        if comp is None:
            if comp_name in self.subsystem_names:
                raise located.error(path, f"'{ref}': subsystem '{comp_name.rsplit('.', 1)[-1]}' exposes no port "
                                    f"'{port_name}'")
            hint = nearest(comp_name, self.components)
            raise located.error(path, f"'{ref}': unknown component '{comp_name}'"
                                + (f" (did you mean {', '.join(hint)}?)" if hint else ""))
        names = [p.name for p in comp.cls.ports]
        if port_name not in names:
            raise located.error(path, f"'{ref}': {comp.cls.type_name} has no port '{port_name}' "
                                f"(its ports: {', '.join(names)})")
        return comp_name, port_name


def read_csv_column(file: Path, column: str, unit: str, located: Located, path: tuple) -> tuple[tuple, list[int]]:
    """One column of a data file (:func:`blocks.datafile.read_table`: header cells ``name [unit]``), in SI,
    its unit checked against the parameter's declared unit; and the file line of each value."""
    from blocks.datafile import read_table

    try:
        table = read_table(file)
    except NetlistError as exc:
        raise located.error(path, f"CSV {exc}") from None
    name = column.split("[")[0].strip()
    if name == table.group:
        example = f"{name} [{unit}]" if unit != GENERIC else f"{name} [<unit>]"
        raise located.error(path, f"{file}: column '{name}' has no unit in its header (a column without one "
                                  f"only labels groups of rows): write it as '{example}'")
    if name not in table.columns:
        raise located.error(path, f"{file}: no column '{column}' (columns: {', '.join(table.columns)})")
    written = table.units[name]
    if unit != GENERIC and not parse_unit(written).same_dimension(parse_unit(unit)):
        raise located.error(path, f"{file}: column '{column}' is in {written}, expected a quantity in {unit}")
    values = table.columns[name]
    if not np.all(np.isfinite(values)):
        row = int(np.argmin(np.isfinite(values)))
        raise located.error(path, f"{file}:{table.lines[row]}: column '{column}' has an empty cell")
    if values.size == 0:
        raise located.error(path, f"{file}: column '{column}' has no values")
    return tuple(float(v) for v in values), list(table.lines)
