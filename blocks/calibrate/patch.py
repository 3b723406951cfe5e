"""Editing a netlist as data: new parameters, components and nets, a port moved onto a new net; written as
a new file (atomically), the original never touched.

The new file keeps the original's text wherever the document did not change (its comments, quotes and
layout: :mod:`blocks.netlist.yaml_roundtrip`), so that ``diff original.yaml new.yaml`` shows the edits and
nothing else; a header of comments above a rule says what vphs wrote it for (a file written from one that
vphs wrote gets the new header in place of the old).

The document is the file's YAML mapping (read with :func:`blocks.netlist.yaml_source.read_yaml`, so the
same safe subset and bounds apply). Only the top level of the file is edited: components inside a
subsystem are not patched (their nets and ports are still reachable through the subsystem's exposed ports).
Relative paths inside the document (subsystem netlists, CSV columns of array parameters) are rewritten for
the new file's folder, so the patched file reads the same files as the original.
"""

from __future__ import annotations

import copy
import os
from pathlib import Path

import yaml

from blocks.netlist.yaml_roundtrip import dump_over
from blocks.netlist.yaml_source import read_yaml
from blocks.result import atomic_write_text
from blocks.units import display_factor


class NetlistDoc:
    """A netlist file's mapping, editable; remembers the folder its relative paths are relative to."""

    def __init__(self, data: dict, folder: Path, text: str | None = None):
        self.data = data
        self.folder = Path(folder)
        self.text = text  # the file's text, which the written file keeps where the document is unchanged
        self.sections = set(data)  # the file's own top-level keys: an empty section added to them is not written
        self.notes: list[str] = []
        self.origin: dict[str, str] = {}  # a node added by move_port -> the net whose oil it holds

    @classmethod
    def read(cls, file: str | Path) -> "NetlistDoc":
        located = read_yaml(file)
        return cls(copy.deepcopy(located.data), Path(file).resolve().parent, read_text(file))

    def copy(self) -> "NetlistDoc":
        doc = NetlistDoc(copy.deepcopy(self.data), self.folder, self.text)
        doc.sections = set(self.sections)
        doc.notes = list(self.notes)
        doc.origin = dict(self.origin)
        return doc

    # ---- sections ---------------------------------------------------------------------------------
    def section(self, key: str) -> dict:
        if self.data.get(key) is None:
            self.data[key] = {}
        return self.data[key]

    def unique(self, base: str) -> str:
        """A name not yet used by a parameter, component, subsystem or net."""
        used = set(self.section("parameters")) | set(self.section("components")) | set(self.section("nets")) \
            | set(self.section("subsystems"))
        name, k = base, 2
        while name in used:
            name, k = f"{base}_{k}", k + 1
        return name

    def add_parameter(self, name: str, value) -> None:
        self.section("parameters")[name] = value

    def add_component(self, name: str, type_name: str, params: dict) -> None:
        self.section("components")[name] = {"type": type_name, "params": dict(params)}

    def net_ports(self, net: str) -> list[str]:
        value = self.section("nets")[net]
        return value if isinstance(value, list) else value["ports"]

    def set_net_ports(self, net: str, ports: list[str]) -> None:
        nets = self.section("nets")
        if isinstance(nets[net], list):
            nets[net] = list(ports)
        else:
            nets[net]["ports"] = list(ports)

    def add_net(self, name: str, ports: list[str], volume=None) -> None:
        spec = {"ports": list(ports)}
        if volume is not None:
            spec["volume"] = volume
        self.section("nets")[name] = spec

    def net_of(self, port: str) -> str | None:
        for net in self.section("nets"):
            if port in self.net_ports(net):
                return net
        return None

    def move_port(self, port: str, new_net: str, new_port_on_old: str, new_port_on_new: str, volume=None,
                  initial=None) -> str:
        """Insert a two-port element in series at ``port``: the port leaves its net for ``new_net``, the
        element's ``new_port_on_old`` joins the old net and ``new_port_on_new`` the new one; the new net
        starts at ``initial`` (the old net's start pressure, so that nothing rushes through at t = 0), and
        its ``volume`` is taken from the old net's own volume where it has one (so the oil volume, and with it
        the dynamics, stay as they were). Returns the old net."""
        old = self.net_of(port)
        ports = [p for p in self.net_ports(old) if p != port] + [new_port_on_old]
        self.set_net_ports(old, ports)
        self.add_net(new_net, [port, new_port_on_new], volume)
        if initial is not None:
            self.section("nets")[new_net]["initial"] = initial  # start in equilibrium with the old net
        root = self.origin.get(old, old)
        self.origin[new_net] = root
        spec = self.section("nets")[root]
        if volume is not None and isinstance(spec, dict) and spec.get("volume") is not None \
                and not root.startswith("cal_"):
            spec["volume"] = f"({spec['volume']}) - {volume!r} m^3"  # the node's oil is taken from the net
        return old

    def set_param(self, component: str, param: str, value) -> None:
        comp = self.section("components")[component]
        if comp.get("params") is None:
            comp["params"] = {}
        comp["params"][param] = value

    def param_text(self, component: str, param: str):
        comp = self.section("components")[component]
        return (comp.get("params") or {}).get(param)

    # ---- writing ----------------------------------------------------------------------------------
    def write(self, path: str | Path, header: str = "") -> Path:
        path = Path(path).resolve()
        data = {key: value for key, value in self.data.items() if value != {} or key in self.sections}
        write_yaml(path, _rebase(copy.deepcopy(data), self.folder, path.parent), self.text, header)
        return path


HEADER_RULE = "# ---- written by vphs above this line ----"


def read_text(file: str | Path) -> str:
    """A YAML file's text (already read once by :func:`read_yaml`, which refuses what is not UTF-8), the
    header vphs wrote above :data:`HEADER_RULE` left out."""
    text = Path(file).read_bytes().decode("utf-8-sig")
    lines = text.splitlines(keepends=True)
    for k, line in enumerate(lines):
        if not line.startswith("#"):
            break
        if line.rstrip("\r\n") == HEADER_RULE:
            return "".join(lines[k + 1:])
    return text


def write_yaml(path: Path, data: dict, original: str | None, header: str = "") -> None:
    """``data`` to ``path`` atomically: over the text ``original`` where that can be done faithfully, else
    afresh; ``header`` (lines) above the rule."""
    text = dump_over(original, data) if original is not None else None
    newline = "\r\n" if original is not None and text is not None and "\r\n" in original else "\n"
    if text is None:
        text = yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=110)
    if header:
        text = "".join(f"# {line}{newline}" if line else f"#{newline}" for line in header.splitlines()) \
            + HEADER_RULE + newline + text
    atomic_write_text(path, text)


def _rebase(data: dict, old: Path, new: Path) -> dict:
    """Rewrite relative file references (subsystem netlists, csv columns) from folder ``old`` to ``new``."""

    def move(rel: str) -> str:
        if os.path.isabs(rel):
            return rel
        return os.path.relpath((old / rel).resolve(), new)

    for sub in (data.get("subsystems") or {}).values():
        if isinstance(sub, dict) and isinstance(sub.get("netlist"), str):
            sub["netlist"] = move(sub["netlist"])
    for comp in (data.get("components") or {}).values():
        for value in ((comp or {}).get("params") or {}).values():
            if isinstance(value, dict) and isinstance(value.get("csv"), str):
                value["csv"] = move(value["csv"])
    return data


def written(value: float, unit: str):
    """An SI value as a written file gives it: in its display unit ('59.118... bar'), or bare without one."""
    return value if unit in ("", "1", "SI") else f"{value / display_factor(unit)!r} {unit}"


MIN_DIGITS = 4  # significant digits of a fitted value for people, at the least


def digits_for(value: float, se: float) -> int | None:
    """Significant digits of ``value`` down to two places past the leading digit of its standard error (the
    digits it warrants, plus 2: 0.0049869 for 0.004987 +- 0.000041), at least MIN_DIGITS; None (all digits) for
    a value of 0 or an SE that is not a number."""
    import math

    if not (math.isfinite(value) and value != 0.0) or math.isnan(se):
        return None
    if not (math.isfinite(se) and se > 0.0):  # not fixed by the data: the least
        return MIN_DIGITS
    return max(MIN_DIGITS, min(17, math.floor(math.log10(abs(value))) - math.floor(math.log10(se)) + 3))


def rounded(value: float, se: float, unit: str = ""):
    """A fitted SI value as :func:`written` gives it, rounded in its display unit to :func:`digits_for`
    digits (for people: calibrated.yaml; a netlist a calibration reads again keeps every digit)."""
    factor = 1.0 if unit in ("", "1", "SI") else display_factor(unit)
    digits = digits_for(value / factor, se / factor)
    if digits is None:
        return written(value, unit)
    shown = f"{value / factor:.{digits}g}"
    return float(shown) if unit in ("", "1", "SI") else f"{shown} {unit}"
