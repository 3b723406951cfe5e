"""What a candidate effect is: a parametric patch of the netlist at a specific place (or of a compared
channel), whose parameter at its ``zero`` value is exactly the declared model.

A :class:`Candidate` lists the :class:`Place` s where it applies in a given netlist (:meth:`places`, from
the netlist's top-level nets, ports and block types, and the experiment's channels) and edits a
:class:`~blocks.calibrate.patch.NetlistDoc` to add itself there (:meth:`patch`) with its parameter as a new
netlist parameter. Channel candidates (sensor offset and gain) patch the compared signal in
post-processing (:mod:`blocks.calibrate.model`), not the netlist.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field


from blocks.block import PortKind

# blocks whose ports take no part in a series insertion (sensors, pure capacities, ideal pressure sources)
NO_SERIES = {"pressure_sensor", "volume", "tank", "pressure_source"}
CAL = "cal_"
"""Prefix of everything calibration adds to a netlist (never patched again)."""


@dataclass
class Place:
    candidate: str
    key: str  # unique: "<candidate>@<where>"
    where: str  # for people: "net V, at relief.a (between V and the relief)"
    param: str  # the new netlist parameter (netlist kind) or "offset:<channel>" / "gain:<channel>"
    unit: str  # SI unit of the parameter
    zero: float  # the value that is the declared model
    lower: float
    upper: float
    step: float  # first finite-difference step (screening adapts it)
    plausible: tuple[float, float]  # the physically plausible range
    kind: str = "netlist"  # "netlist" or "channel"
    target: dict = field(default_factory=dict)
    meaning: str = ""  # how to read the value, e.g. "dp at 100 l/min = k*(100 l/min)^2"
    plot_against: str = "t"  # a measured channel name, "a - b" (the difference of two such), or "t"
    one_sided: bool = True  # the parameter's sign is fixed (zero is a bound)


@dataclass
class Context:
    """What candidates need to know about the netlist and the experiment to find their places."""

    doc: object  # NetlistDoc of the current netlist
    flat: object  # its FlatCircuit
    structure: object
    values: dict  # the netlist's evaluated parameters (SI)
    exp: object
    data: object
    logged_nets: set
    q_ref: float  # reference flow [m^3/s]: the largest measured flow, else 1e-3
    p_ref: float  # reference pressure noise [Pa]: the smallest pressure sigma, else 1e4
    w_ref: float  # reference speed [rad/s]: the largest measured speed, else 10
    t_span: float
    v_ref: float = 0.1  # reference velocity [m/s]: the largest measured velocity, else 0.1 (a cylinder's)
    notes: list = field(default_factory=list)

    def top_components(self) -> dict:
        return {name: comp for name, comp in self.flat.components.items()
                if "." not in name and not name.startswith(CAL)}

    def net_kind(self, net: str):
        flat = self.flat.nets.get(net)
        return flat.kind if flat is not None else None

    def prescribed(self, net: str) -> bool:
        return net in self.structure.prescribed

    def has_state(self, net: str) -> bool:
        return net in self.structure.net_state

    def first_input_of_unit(self, dims: str) -> str:
        from blocks.units import parse_unit

        for ch in self.exp.channels:
            if ch.si_unit and ch.si_unit not in ("1", "SI") and parse_unit(ch.si_unit).same_dimension(parse_unit(dims)):
                if ch.role == "input":
                    return ch.name
        for ch in self.exp.channels:
            if ch.si_unit and ch.si_unit not in ("1", "SI") and parse_unit(ch.si_unit).same_dimension(parse_unit(dims)):
                return ch.name
        return "t" if self.data.kind == "time" else (self.exp.inputs[0].name if self.exp.inputs else "t")

    def pressure_channel(self, net: str) -> str | None:
        """The measured channel whose logged signal is the pressure of top-level net ``net`` (None: none)."""
        from blocks.units import parse_unit

        of = {o.name: o.of for o in self.flat.outputs}
        for ch in self.exp.channels:
            if ch.signal is not None and of.get(ch.signal) == net and ch.si_unit not in ("", "1", "SI") \
                    and parse_unit(ch.si_unit).same_dimension(parse_unit("Pa")):
                return ch.name
        return None

    def across(self, a: str, b: str, dims: str) -> str:
        """What a residual plot of an effect between nets ``a`` and ``b`` is drawn against: the pressure drop
        ``"pa - pb"`` where a channel measures each net, the pressure of the one measured, else the first
        channel of ``dims`` (:meth:`first_input_of_unit`). Only the plot's x-axis (blocks.calibrate.report)."""
        pa, pb = self.pressure_channel(a), self.pressure_channel(b)
        if pa and pb:
            return f"{pa} - {pb}"
        return pa or pb or self.first_input_of_unit(dims)


class Candidate:
    name: str = ""
    title: str = ""
    description: str = ""

    def places(self, ctx: Context) -> list[Place]:
        raise NotImplementedError

    def patch(self, doc, place: Place) -> None:
        """Add the effect at ``place`` to ``doc`` with its parameter ``place.param`` (a netlist parameter
        the caller adds with its value)."""
        raise NotImplementedError


_REGISTRY: dict[str, Candidate] = {}


def register(cls):
    """Class decorator: register one instance of a candidate under its ``name``."""
    if cls.name in _REGISTRY:
        raise TypeError(f"candidate '{cls.name}' registered twice")
    _REGISTRY[cls.name] = cls()
    return cls


def registered() -> dict[str, Candidate]:
    return dict(_REGISTRY)


def safe(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_]", "_", text)


def series_ports(ctx: Context) -> list[tuple[str, str, bool]]:
    """(net, port, logged) for every port where a series element can be inserted: top-level hydraulic
    nets, ports of top-level components other than sensors, capacities and pressure sources; for a net
    that is not measured and joins just two such ports, only the first (either place is the same)."""
    out = []
    comps = ctx.top_components()
    for net in ctx.doc.section("nets"):
        if ctx.net_kind(net) is not PortKind.HYDRAULIC:
            continue
        ports = []
        for port in ctx.doc.net_ports(net):
            comp, _, pname = port.partition(".")
            if comp not in comps or comps[comp].cls.type_name in NO_SERIES:
                continue
            ports.append(port)
        logged = net in ctx.logged_nets
        others = [p for p in ctx.doc.net_ports(net) if p not in ports]
        if not logged and len(ports) == 2 and not others:
            ports = ports[:1]
        out += [(net, p, logged) for p in ports]
    return out


def start_pressure(ctx: Context, net: str) -> str | float | None:
    """The pressure a net starts at, as a netlist reference for a new node's ``initial``: the net's own
    ``initial`` as written (``A.initial``; or a subsystem's net joined to it), the engine's default start
    where none is written (a number),
    or the setting of the pressure source holding it (tank, pressure_source: ``supply.p``), else None. A
    reference, not its value: a group, a run or an optimiser that sets ``supply.p`` moves the new node's
    start with it (frozen at 207 bar, a node beside a 150 bar supply starts 57 bar off, and the solver
    fails at t = 0 through a loss of zero resistance)."""
    written = ctx.flat.parameters.entries.get(f"{net}.initial")
    if written is not None and written.raw is not None:  # in the file, or in a subsystem's net joined to it
        return f"{net}.initial"
    if f"{net}.initial" in ctx.values:  # the engine's default start, which no parameter moves
        return float(ctx.values[f"{net}.initial"])
    for port in ctx.doc.net_ports(net):
        comp, _, pname = port.partition(".")
        flat = ctx.flat.components.get(comp)
        if flat is not None and pname in flat.cls.prescribes and f"{comp}.p" in ctx.values:
            return f"{comp}.p"
    return None


def hydraulic_pairs(ctx: Context) -> list[tuple[str, str, str]]:
    """(net_a, net_b, components) for each pair of top-level hydraulic nets joined by a top-level component,
    not both held by pressure sources (a leak between them would change nothing measured); components names
    every component that joins the pair ("valve, cyl": the leak may be in any of them)."""
    joined: dict[tuple[str, str], list[str]] = {}
    for name, comp in ctx.top_components().items():
        nets = []
        for p in comp.cls.physical_ports():
            if p.kind is PortKind.HYDRAULIC:
                net = ctx.doc.net_of(f"{name}.{p.name}")
                if net is not None and net not in nets:
                    nets.append(net)
        for i in range(len(nets)):
            for j in range(i + 1, len(nets)):
                a, b = sorted((nets[i], nets[j]))
                if not (ctx.prescribed(a) and ctx.prescribed(b)):
                    joined.setdefault((a, b), []).append(name)
    return [(a, b, ", ".join(names)) for (a, b), names in joined.items()]


def mechanical_nets(ctx: Context, kinds=(PortKind.ROTATIONAL, PortKind.TRANSLATIONAL)) -> list[tuple[str, object]]:
    """One top-level net per rigid body that moves (not held by a speed source), with its kind."""
    out, bodies = [], set()
    for net in ctx.doc.section("nets"):
        kind = ctx.net_kind(net)
        if kind not in kinds:
            continue
        body = ctx.structure.body_of.get(net) if hasattr(ctx.structure, "body_of") else None
        root = getattr(body, "root", net) if body is not None else net
        if root in bodies:
            continue
        if body is not None and getattr(body, "prescribed_by", None):
            continue
        bodies.add(root)
        out.append((net, kind))
    return out


def add_to_param(doc, component: str, param: str, name: str) -> None:
    """Make ``component.param`` its written value plus the netlist parameter ``name`` (just ``name`` when the
    netlist leaves it at 0 or unset): a block's own gain patched with a zero-parameter increment."""
    old = doc.param_text(component, param)
    doc.set_param(component, param, name if old in (None, 0, 0.0, "0") else f"({old}) + {name}")
