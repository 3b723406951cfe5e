"""Generate the circuit's right-hand side as Python source that numba compiles once and caches on disk.

The generated module holds two functions over the flat vectors (x: states, th: parameters):

- ``rhs(t, x, th, dx)``: across variables from the states, then every block's ``outputs`` in the
  evaluation order (signals, prescribed pressures and speeds), then every block's ``derivatives``,
  summed per node: dp/dt = beta/(V_net + sum V_port) * sum q for a hydraulic node (below the vapour
  pressure, a vapour cavity's: blocks.library.hydraulic.cavitation), and
  dw/dt = sum(r_k*tau_k) / sum(r_k^2*J_k) for a rigid body.
- ``observe(t, x, th, y)``: the same first two steps, then the logged signals.
- ``prescribed(t, x, th, a)`` (only when a source's torque or force is logged): the prescribed speeds.

What a speed (velocity) source delivers to its rigid body is not part of the right-hand side (the body has
no speed state to balance); ``observe`` computes it where it is logged: tau = M*dw/dt - F, with M the
body's inertia and F its generalised torque as above (the source's net is the body's root, r = 1), and
dw/dt the rate of the prescribed speed along the solution, d/dt w(t, x(t)), a central difference
(w(t + h, x + h*dx) - w(t - h, x - h*dx))/(2h), h = 1e-6*max(1, |t|) s, dx = rhs(t, x). Likewise what a
pressure source (a tank) delivers to its net: q = -sum(q_k), the flows the other blocks deliver to it (the
net has no pressure state, so no volume on it is compressed).

Block equations are called as numba functions with scalar arguments and inline into straight-line code,
so a step costs what a hand-written compiled function would, not a Python loop over blocks.
"""

from __future__ import annotations

import hashlib
import inspect
from dataclasses import dataclass
from pathlib import Path

import blocks.library.hydraulic.cavitation  # noqa: F401  (in the library digest: the node law)
import blocks.library.hydraulic.entrained_air  # noqa: F401  (in the library digest: the node law)
from blocks.block import ACROSS, THROUGH, PortKind
from blocks.compiler.structure import Structure, bulk_modulus_name, cavitation, entrained_air


@dataclass
class OutputExpr:
    name: str
    expr: str
    unit: str  # SI unit of the value


_LIBRARY_DIGEST: str | None = None


def library_digest() -> str:
    """A hash of every module of the block libraries (blocks.block, blocks.library.*, vphs_blocks.*), so that
    an edit anywhere a block's equations may reach, helpers called through other helpers included, gives a
    new generated module and never a stale compiled one."""
    global _LIBRARY_DIGEST
    if _LIBRARY_DIGEST is None:
        import sys

        from blocks import registry

        registry.load_all()
        digest = hashlib.sha256()
        names = sorted(n for n in sys.modules if n == "blocks.block" or n.startswith(("blocks.library", "vphs_blocks")))
        for name in names:
            file = getattr(sys.modules[name], "__file__", None)
            if file:
                digest.update(name.encode())
                digest.update(Path(file).read_bytes())
        _LIBRARY_DIGEST = digest.hexdigest()[:16]
    return _LIBRARY_DIGEST


class Generator:
    def __init__(self, st: Structure):
        self.st = st
        self.comp_index = {name: i for i, name in enumerate(st.circuit.components)}
        self.net_index = {name: j for j, name in enumerate(st.circuit.nets)}
        self.classes: dict[type, int] = {}
        self.reactions: list[tuple[str, str]] = []  # (source, port) whose torque or force observe computes
        for comp in st.circuit.components.values():
            self.classes.setdefault(comp.cls, len(self.classes))

    # ---- names of generated variables ------------------------------------------------------------------
    def across(self, net: str) -> str:
        return f"v_n{self.net_index[net]}"

    def ratio(self, net: str) -> str:
        return f"r_n{self.net_index[net]}"

    def out_var(self, comp: str, port: str) -> str:
        names = self.st.circuit.components[comp].cls.output_names()
        return f"y{self.comp_index[comp]}_{names.index(port)}"

    def theta(self, name: str) -> str:
        a, b = self.st.theta_index[name]
        return f"th[{a}]" if b == a + 1 and not self._is_array(name) else f"th[{a}:{b}]"

    def _is_array(self, name: str) -> bool:
        comp, _, pname = name.rpartition(".")
        if comp in self.st.circuit.components:
            try:
                return self.st.circuit.components[comp].cls.param(pname).array
            except KeyError:
                return False
        return False

    def signal_value(self, comp: str, port: str) -> str:
        src = self.st.driver.get((comp, port))
        return "0.0" if src is None else self.out_var(*src)

    def arg(self, comp: str, name: str) -> str:
        cls = self.st.circuit.components[comp].cls
        if name == "t":
            return "t"
        slots = self.st.block_states[comp]
        if name in slots:
            slot = slots[name]
            return f"x[{slot.index}]" if cls_state_scalar(cls, name) else f"x[{slot.index}:{slot.index + slot.size}]"
        if name.startswith("der_") and name[4:] in slots:
            slot = slots[name[4:]]
            return f"dx[{slot.index}:{slot.index + slot.size}]"
        try:
            port = cls.port(name)
        except KeyError:
            return self.theta(f"{comp}.{name}")
        if port.kind is PortKind.SIGNAL:
            return self.signal_value(comp, name)
        return self.across(self.st.port_net[(comp, name)])

    def call(self, comp: str, function: str) -> str:
        cls = self.st.circuit.components[comp].cls
        from blocks.block import argument_names

        args = ", ".join(self.arg(comp, a) for a in argument_names(getattr(cls, function)))
        prefix = {"outputs": "_o", "derivatives": "_d", "ratio": "_r"}[function]
        return f"{prefix}{self.classes[cls]}({args})"

    # ---- code ------------------------------------------------------------------------------------------
    def header(self) -> list[str]:
        lines = [f"# block library version {library_digest()} (any edit of a block or helper module changes "
                 f"this file's name, and so numba's cache)"]
        if entrained_air(self.st):
            lines.append("from blocks.library.hydraulic.entrained_air import aerated_pressure_rate as "
                         "_aerated_pressure_rate")
        elif cavitation(self.st):
            lines.append("from blocks.library.hydraulic.cavitation import cavitating_pressure_rate as "
                         "_cavitating_pressure_rate")
        for cls, k in self.classes.items():
            module = inspect.getmodule(cls)
            lines.append(f"from {module.__name__} import {cls.__name__} as _K{k}")
            for fn, prefix in (("outputs", "_o"), ("derivatives", "_d"), ("ratio", "_r")):
                if getattr(cls, fn) is not None:
                    lines.append(f"{prefix}{k} = njit(_K{k}.{fn}, error_model='numpy')")
        return lines

    def prelude(self) -> list[str]:
        """Across variables and phase-1 outputs, shared by rhs and observe."""
        st = self.st
        lines = []
        for net, slot in st.net_state.items():
            lines.append(f"{self.across(net)} = x[{slot.index}]")
        for body in st.bodies:
            lines.append(f"{self.ratio(body.root)} = 1.0")
            for net, (parent, link, forward) in body.members.items():
                if parent is None:
                    continue
                op = "*" if forward else "/"
                lines.append(f"{self.ratio(net)} = {self.ratio(parent)} {op} {self.call(link, 'ratio')}")
            if body.state is not None:
                for net in body.members:
                    lines.append(f"{self.across(net)} = {self.ratio(net)} * x[{body.state.index}]")
        for comp in st.order:
            cls = st.circuit.components[comp].cls
            names = [self.out_var(comp, n) for n in cls.output_names()]
            lines.append(f"{', '.join(names)}, = {self.call(comp, 'outputs')}")
            for port in cls.prescribes:
                net = st.port_net[(comp, port)]
                body = st.body_of.get(net)
                if body is None:
                    lines.append(f"{self.across(net)} = {self.out_var(comp, port)}")
                else:  # a speed source drives the whole rigid body
                    root_speed = f"({self.out_var(comp, port)} / {self.ratio(net)})"
                    for member in body.members:
                        lines.append(f"{self.across(member)} = {self.ratio(member)} * {root_speed}")
        return lines

    def rhs(self) -> list[str]:
        st = self.st
        lines = self.prelude()
        for net in st.net_state:
            j = self.net_index[net]
            volume = self.theta(f"{net}.volume") if f"{net}.volume" in st.theta_index else "0.0"
            lines += [f"q_n{j} = 0.0", f"V_n{j} = {volume}"]
        for k, body in enumerate(st.bodies):
            if body.state is not None:
                lines += [f"F_b{k} = 0.0", f"M_b{k} = 0.0"]
        body_index = {id(b): k for k, b in enumerate(st.bodies)}
        for comp, flat in st.circuit.components.items():
            cls = flat.cls
            if cls.derivatives is None:
                continue
            i = self.comp_index[comp]
            names = cls.derivative_names()
            temps = [f"d{i}_{k}" for k in range(len(names))]
            call = self.call(comp, "derivatives")
            if not names:
                lines.append(call)
                continue
            lines.append(f"{', '.join(temps)}, = {call}")
            k = 0
            for port in cls.through_ports():
                lines += self._deliver(comp, port, temps[k], capacity=False, body_index=body_index)
                k += 1
            for port in cls.storing_ports():
                lines += self._deliver(comp, port, temps[k], capacity=True, body_index=body_index)
                k += 1
            for state in cls.scalar_states():
                lines.append(f"dx[{st.block_states[comp][state.name].index}] = {temps[k]}")
                k += 1
        for net, slot in st.net_state.items():
            j = self.net_index[net]
            beta = self.theta(bulk_modulus_name(st, net))
            if entrained_air(st):
                lines.append(f"dx[{slot.index}] = _aerated_pressure_rate(x[{slot.index}], {beta}, V_n{j}, q_n{j}, "
                             f"{self.theta('fluid.vapour_pressure')}, {self.theta('fluid.air')}, "
                             f"{self.theta('fluid.air_index')}, {cavitation(st)})")
            elif cavitation(st):
                lines.append(f"dx[{slot.index}] = _cavitating_pressure_rate(x[{slot.index}], {beta}, V_n{j}, q_n{j}, "
                             f"{self.theta('fluid.vapour_pressure')})")
            else:
                lines.append(f"dx[{slot.index}] = {beta} / V_n{j} * q_n{j}")
        for k, body in enumerate(st.bodies):
            if body.state is not None:
                lines.append(f"dx[{body.state.index}] = F_b{k} / M_b{k}")
        return lines

    def _deliver(self, comp, port, temp, capacity, body_index) -> list[str]:
        st = self.st
        net = st.port_net[(comp, port.name)]
        if port.kind is PortKind.HYDRAULIC:
            if net not in st.net_state:
                return []  # a prescribed pressure takes whatever flows
            j = self.net_index[net]
            return [f"{'V' if capacity else 'q'}_n{j} += {temp}"]
        body = st.body_of[net]
        if body.state is None:
            return []
        k = body_index[id(body)]
        return self._add_to_body(net, temp, capacity, f"F_b{k}", f"M_b{k}")

    def _add_to_body(self, net: str, temp: str, capacity: bool, force: str, mass: str) -> list[str]:
        """A port's torque (force) or inertia (mass) on ``net``, added to its rigid body's sums: r*tau to the
        generalised torque, r^2*J to the inertia."""
        r = self.ratio(net)
        return [f"{mass} += {r} * {r} * {temp}"] if capacity else [f"{force} += {r} * {temp}"]

    # ---- what a speed or velocity source delivers ------------------------------------------------------
    def _reaction(self, comp: str, port: str) -> str:
        """The variable that ``observe`` computes the source's torque (force) into."""
        if (comp, port) not in self.reactions:
            self.reactions.append((comp, port))
        return f"R{self.reactions.index((comp, port))}"

    def _source_ports(self, source: tuple[str, str]) -> list[tuple[str, int, object, bool]]:
        """(component, index of its derivatives' value, port, capacity?) of each port that delivers a flow,
        torque or force to the source's net (a hydraulic one) or rigid body (a mechanical one), or stores
        an inertia (mass) on that body. A volume on a held pressure is not read: no flow compresses it."""
        st, found = self.st, []
        net = st.port_net[source]
        body = st.body_of.get(net)
        for comp, flat in st.circuit.components.items():
            cls = flat.cls
            if cls.derivatives is None:
                continue
            delivered = [(p, False) for p in cls.through_ports()] + [(p, True) for p in cls.storing_ports()]
            for k, (port, capacity) in enumerate(delivered):
                at = st.port_net[(comp, port.name)]
                if (st.body_of.get(at) is body) if body is not None else (at == net and not capacity):
                    found.append((comp, k, port, capacity))
        return found

    def _reaction_ports(self) -> list[list[tuple[str, int, object, bool]]]:
        return [self._source_ports(source) for source in self.reactions]

    @staticmethod
    def _needs_rates(ports) -> bool:
        """Whether a logged source's body stores an inertia (mass), so that its torque (force) reads the rate
        of its prescribed speed (``prescribed``); a pressure source's flow does not."""
        return any(capacity for found in ports for *_, capacity in found)

    def reaction_lines(self) -> list[str]:
        """``observe``'s lines computing what each logged source delivers: tau = M*dw/dt - F for a speed or
        velocity source, q = -sum(q_k) for a pressure source (module docstring)."""
        if not self.reactions:
            return []
        st = self.st
        ports = self._reaction_ports()
        lines = ["dx = np.zeros(x.shape[0])"]  # also what a block's array state derivative is written into
        if self._needs_rates(ports):
            n = len(self.reactions)
            lines += ["rhs(t, x, th, dx)", "h_r = 1e-6 * max(1.0, abs(t))",
                      f"a_p = np.empty({n})", f"a_m = np.empty({n})", "prescribed(t + h_r, x + h_r * dx, th, a_p)",
                      "prescribed(t - h_r, x - h_r * dx, th, a_m)"]
        called = set()
        for found in ports:
            for comp, *_ in found:
                if comp not in called:
                    called.add(comp)
                    i = self.comp_index[comp]
                    temps = [f"d{i}_{k}" for k in range(len(st.circuit.components[comp].cls.derivative_names()))]
                    lines.append(f"{', '.join(temps)}, = {self.call(comp, 'derivatives')}")
        for m, found in enumerate(ports):
            lines += [f"F_r{m} = 0.0", f"M_r{m} = 0.0"]
            for comp, k, port, capacity in found:
                temp = f"d{self.comp_index[comp]}_{k}"
                lines += [f"F_r{m} += {temp}"] if port.kind is PortKind.HYDRAULIC else \
                    self._add_to_body(st.port_net[(comp, port.name)], temp, capacity, f"F_r{m}", f"M_r{m}")
            rate = f"(a_p[{m}] - a_m[{m}]) / (2.0 * h_r)" if any(c for *_, c in found) else "0.0"
            lines.append(f"R{m} = M_r{m} * {rate} - F_r{m}")
        return lines

    def prescribed(self) -> list[str]:
        """The body of ``prescribed(t, x, th, a)``: the speed each logged source prescribes, into a."""
        return self.prelude() + [f"a[{m}] = {self.out_var(*source)}" for m, source in enumerate(self.reactions)]

    def source(self, outputs: list[OutputExpr]) -> str:
        body = "\n".join("    " + line for line in self.rhs()) or "    pass"
        obs = self.prelude() + self.reaction_lines() + [f"y[{m}] = {o.expr}" for m, o in enumerate(outputs)]
        obs_body = "\n".join("    " + line for line in obs) or "    pass"
        prescribed = "\n".join("    " + line for line in self.prescribed())
        prescribed = f"""


@njit(cache=True, error_model="numpy")
def prescribed(t, x, th, a):
{prescribed}""" if self._needs_rates(self._reaction_ports()) else ""
        return "\n".join(self.header()) + f"""


@njit(cache=True, error_model="numpy")
def rhs(t, x, th, dx):
{body}{prescribed}


@njit(cache=True, error_model="numpy")
def observe(t, x, th, y):
{obs_body}
"""

    # ---- logged signals --------------------------------------------------------------------------------
    def resolve_output(self, ref: str) -> tuple[str, str]:
        """'A' (a net), 'sensor.y' (a port), 'valve.x' (a state) or 'motor.a.flow' (what a block delivers
        to the net at a physical port: flow, torque or force, positive into the net; for a speed or velocity
        source's port, what the source delivers: :meth:`reaction_lines`) -> (expression, SI unit)."""
        st = self.st
        ref = st.circuit.resolve_alias(ref)
        through = self._resolve_through(ref)
        if through is not None:
            return through
        if ref in st.circuit.nets:
            net = st.circuit.nets[ref]
            if net.kind is PortKind.SIGNAL:
                comp, port = next((c, p) for c, p in net.ports
                                  if st.circuit.components[c].cls.port(p).direction == "out")
                return self.out_var(comp, port), st.circuit.components[comp].cls.port(port).unit
            return self.across(ref), ACROSS[net.kind][1]
        comp, _, name = ref.rpartition(".")
        if comp not in st.circuit.components:
            raise KeyError(f"'{ref}' is neither a net nor <component>.<port or state>")
        cls = st.circuit.components[comp].cls
        if name in st.block_states[comp]:
            slot = st.block_states[comp][name]
            if slot.size != 1:
                raise KeyError(f"'{ref}' is an array state; log one of its elements through a block output")
            return f"x[{slot.index}]", slot.unit
        try:
            port = cls.port(name)
        except KeyError:
            choices = [p.name for p in cls.ports] + [s.name for s in cls.states]
            raise KeyError(f"'{ref}': {cls.type_name} has no port or state '{name}' (has: {', '.join(choices)})") from None
        if port.kind is PortKind.SIGNAL:
            if port.direction == "out":
                return self.out_var(comp, name), port.unit
            return self.signal_value(comp, name), port.unit
        return self.across(st.port_net[(comp, name)]), ACROSS[port.kind][1]


    def _resolve_through(self, ref: str):
        parts = ref.rsplit(".", 2)
        if len(parts) != 3 or parts[2] not in THROUGH_SUFFIX:
            return None
        comp, port_name, what = parts
        if comp not in self.st.circuit.components:
            return None
        cls = self.st.circuit.components[comp].cls
        sources = [p.name for p in cls.physical_ports() if p.name in cls.prescribes]
        ports = [p.name for p in cls.through_ports()] + sources
        if port_name not in ports:
            raise KeyError(f"'{ref}': {cls.type_name} delivers no {what} at '{port_name}' "
                           f"(ports with a through value: {', '.join(ports) or 'none'})")
        port = cls.port(port_name)
        if THROUGH_SUFFIX[what] is not port.kind:
            raise KeyError(f"'{ref}': port {port_name} is {port.kind.value}; ask for its "
                           f"{next(k for k, v in THROUGH_SUFFIX.items() if v is port.kind)}")
        if port_name in sources:
            return self._reaction(comp, port_name), THROUGH[port.kind][1]
        if len(cls.scalar_states()) < len(cls.states):
            raise KeyError(f"'{ref}': through values of blocks with array states cannot be logged")
        index = cls.derivative_names().index(f"{THROUGH[port.kind][0]}_{port_name}")
        return f"{self.call(comp, 'derivatives')}[{index}]", THROUGH[port.kind][1]


THROUGH_SUFFIX = {"flow": PortKind.HYDRAULIC, "torque": PortKind.ROTATIONAL, "force": PortKind.TRANSLATIONAL}


def cls_state_scalar(cls, name: str) -> bool:
    return any(s.name == name and s.size is None for s in cls.states)
