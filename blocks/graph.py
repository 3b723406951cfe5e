"""A picture of a flat circuit: components as boxes, nets as dots, a line for every connected port.

``vphs graph NETLIST [-o out.png]`` draws it. The drawing is a bipartite graph (networkx): a box per
component, labelled with its name and block type, and a dot per net, labelled with the net's name and
coloured by its kind (hydraulic blue, rotational and translational green, signal grey). A line joins a net
to every component whose port it connects, labelled with the port's name just outside the component's box;
a signal line is dashed, with an arrow from the output that drives the net to each input reading it.
Hydraulic nets with a declared volume get a larger dot. Components of one subsystem (``left.valve``)
share a box edge colour.

Layout: Kamada-Kawai (graph distances become drawing distances) per connected piece, scaled so that
neighbours sit about an inch apart, then the boxes and net labels are pushed apart until none overlap.
It is deterministic and stays readable up to some sixty components. The geometry is worked out in
points, so the text keeps its size whatever the circuit's: a larger circuit makes a larger picture.
Rendering uses matplotlib's Agg canvas only (no display, no graphviz); the PNG is written atomically.
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path

import networkx as nx
import numpy as np

from blocks.block import PortKind
from blocks.netlist.flatten import FlatCircuit
from blocks.result import atomic_write_figure

KIND_COLOURS = {
    PortKind.HYDRAULIC: "#1f6fb4",
    PortKind.ROTATIONAL: "#2e9a3a",
    PortKind.TRANSLATIONAL: "#2e9a3a",
    PortKind.SIGNAL: "#6f6f6f",
}
SUBSYSTEM_COLOURS = ("#b04a2f", "#7b4fb0", "#c08a00", "#178f8f", "#b0307a", "#5a6f1f", "#3f5fbf")
FONT = 8.0  # points
PAD = 0.35 * FONT  # box padding
NEIGHBOUR = 80.0  # target distance between a node and its nearest neighbour [points]
GAP = 6.0  # least clearance between two boxes [points]
MARGIN = 24.0
MAX_SIDE = 40 * 72.0  # the largest picture side [points]


@lru_cache(maxsize=4096)
def _text_size(text: str) -> tuple[float, float]:
    """Width and height in points of ``text`` (one or more lines) at FONT."""
    from matplotlib.textpath import TextPath

    lines = text.split("\n")
    width = max(TextPath((0, 0), line or " ", size=FONT).get_extents().width for line in lines)
    return width, len(lines) * FONT * 1.2


def circuit_graph(flat: FlatCircuit) -> nx.Graph:
    """The bipartite graph: nodes ("c", name) for components and ("n", name) for nets, an edge per port."""
    graph = nx.Graph()
    for name, comp in flat.components.items():
        graph.add_node(("c", name), label=f"{name}\n{comp.cls.type_name}")
    for name, net in flat.nets.items():
        graph.add_node(("n", name), label=name, kind=net.kind, volume=net.has_volume)
        for comp, port in net.ports:
            key = (("c", comp), ("n", name))
            if graph.has_edge(*key):  # one component on one net through two ports: one line, both names
                graph.edges[key]["ports"].append(port)
            else:
                graph.add_edge(*key, ports=[port], kind=net.kind)
    return graph


def layout(graph: nx.Graph) -> dict:
    """Positions with unit median neighbour distance: Kamada-Kawai per connected piece, side by side."""
    pieces = sorted((sorted(c, key=str) for c in nx.connected_components(graph)), key=lambda c: (-len(c), str(c[0])))
    pos: dict = {}
    x_offset = 0.0
    for nodes in pieces:
        piece = graph.subgraph(nodes)
        if len(nodes) == 1:
            local = {nodes[0]: np.zeros(2)}
        else:
            # a net joining many ports gets longer lines: its ports' boxes need the room around it
            lengths = {(a, b): 1.0 + 0.25 * max(0, graph.degree(a if a[0] == "n" else b) - 2)
                       for a, b in piece.edges}
            piece = nx.Graph(piece)
            nx.set_edge_attributes(piece, lengths, "length")
            local = nx.kamada_kawai_layout(piece, pos=nx.circular_layout(nodes), weight="length")
            local = {n: np.asarray(xy, dtype=float) for n, xy in local.items()}
            # graph distance 1 (a component to its net) -> drawing distance 1
            drawn = [np.linalg.norm(local[a] - local[b]) / piece.edges[a, b]["length"] for a, b in piece.edges]
            scale = 1.0 / max(float(np.median(drawn)), 1e-9)
            local = {n: xy * scale for n, xy in local.items()}
        coords = np.array(list(local.values()))
        lo = coords.min(axis=0)
        for node, xy in local.items():
            pos[node] = xy - lo + np.array([x_offset, 0.0])
        x_offset += float(np.ptp(coords[:, 0])) + 1.5
    return pos


def _half_sizes(graph: nx.Graph, nodes: list) -> np.ndarray:
    """Half width and height [points] of what is drawn at each node: a box, or a dot and its label."""
    sizes = []
    for node in nodes:
        w, h = _text_size(graph.nodes[node]["label"])
        if node[0] == "c":
            sizes.append((w / 2 + PAD + 1, h / 2 + PAD + 1))
        else:
            # the label sits above the dot; a net joining many ports keeps clear room for its lines
            room = 5.0 * max(0, graph.degree(node) - 2)
            sizes.append((max(w / 2 + 2, 6.0 + room), FONT + 6 + room))
    return np.array(sizes)


def remove_overlaps(xy: np.ndarray, half: np.ndarray, iterations: int = 400, gap: float = GAP) -> np.ndarray:
    """Push apart, along the axis of least overlap, every pair of boxes closer than ``gap`` [points]."""
    xy = xy.copy()
    n = len(xy)
    if n < 2:
        return xy
    for _ in range(iterations):
        d = xy[:, None, :] - xy[None, :, :]  # d[i, j] = xy[i] - xy[j]
        need = half[:, None, :] + half[None, :, :] + gap
        overlap = need - np.abs(d)
        hit = (overlap[..., 0] > 0) & (overlap[..., 1] > 0)
        hit[np.tril_indices(n)] = False
        if not hit.any():
            break
        push = np.zeros_like(xy)
        for i, j in zip(*np.nonzero(hit)):
            axis = 0 if overlap[i, j, 0] * 0.6 < overlap[i, j, 1] else 1  # prefer sideways: boxes are wide
            sign = math.copysign(1.0, d[i, j, axis]) if d[i, j, axis] != 0 else (1.0 if i < j else -1.0)
            step = 0.5 * overlap[i, j, axis] + 0.5
            push[i, axis] += sign * step
            push[j, axis] -= sign * step
        xy += push
    return xy


def _border(half: np.ndarray, direction: np.ndarray) -> float:
    """Distance from a box's centre to its edge along the unit vector ``direction``."""
    ux, uy = abs(direction[0]), abs(direction[1])
    return min(half[0] / ux if ux > 1e-9 else math.inf, half[1] / uy if uy > 1e-9 else math.inf)


def draw_circuit(flat: FlatCircuit, output_path: str) -> None:
    """Draw ``flat`` and write the picture to ``output_path`` (PNG, written atomically)."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import FancyArrowPatch

    graph = circuit_graph(flat)
    nodes = sorted(graph.nodes, key=str)
    components = [n for n in nodes if n[0] == "c"]
    nets = [n for n in nodes if n[0] == "n"]
    index = {node: k for k, node in enumerate(nodes)}

    # ---- geometry in points ------------------------------------------------------------------------
    if nodes:
        pos = layout(graph)
        half = _half_sizes(graph, nodes)
        xy = np.array([pos[n] for n in nodes]) * NEIGHBOUR
        xy = remove_overlaps(xy, half)
        lo = (xy - half).min(axis=0) - MARGIN
        hi = (xy + half).max(axis=0) + MARGIN
    else:
        half = np.zeros((0, 2))
        xy = np.zeros((0, 2))
        lo, hi = np.zeros(2), np.array([300.0, 200.0])
    header = 58.0  # title and legend
    width, height = hi - lo
    width = max(width, 420.0)
    shrink = min(1.0, MAX_SIDE / max(width, height + header))  # a huge circuit: smaller, not clipped
    fig = Figure(figsize=(width * shrink / 72, (height + header) * shrink / 72))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    ax.set_xlim(lo[0], lo[0] + width)
    ax.set_ylim(lo[1], lo[1] + height + header)
    font = FONT * shrink

    subsystems = sorted({n[1].rsplit(".", 1)[0] for n in components if "." in n[1]})
    sub_colour = {s: SUBSYSTEM_COLOURS[i % len(SUBSYSTEM_COLOURS)] for i, s in enumerate(subsystems)}

    # ---- lines, arrows and port names ----------------------------------------------------------------
    port_labels: dict = {}
    for (a, b), data in graph.edges.items():
        comp, net = (a, b) if a[0] == "c" else (b, a)
        kind = data["kind"]
        colour = KIND_COLOURS.get(kind, "black")
        p_comp, p_net = xy[index[comp]], xy[index[net]]
        vector = p_net - p_comp
        length = float(np.hypot(*vector))
        u = vector / length if length > 1e-9 else np.array([0.0, -1.0])
        edge = _border(half[index[comp]], u)
        if kind is PortKind.SIGNAL:
            cls = flat.components[comp[1]].cls
            drives = any(cls.port(p).direction == "out" for p in data["ports"])
            start, end, shrink_a, shrink_b = ((p_comp, p_net, edge, 3.0) if drives else (p_net, p_comp, 3.0, edge + 1))
            ax.add_patch(FancyArrowPatch(tuple(start), tuple(end), arrowstyle="-|>", mutation_scale=9 * shrink,
                                         color=colour, lw=0.9 * shrink, linestyle=(0, (4, 2)),
                                         shrinkA=shrink_a * shrink, shrinkB=shrink_b * shrink, zorder=1))
        else:
            ax.plot(*zip(p_comp, p_net), color=colour, lw=1.8 * shrink, zorder=1, solid_capstyle="round")
        text = ",".join(data["ports"])
        tw, _ = _text_size(text)
        # beside the line (not on it, where an arrowhead may be), just outside the box
        normal = np.array([u[1], -u[0]]) if u[1] <= 0 else np.array([-u[1], u[0]])
        side = 0.5 * tw * abs(normal[0]) + 0.5 * FONT * abs(normal[1]) + 1.5
        at = p_comp + u * (edge + 6 + 0.5 * tw * abs(u[0]) + 0.5 * FONT * abs(u[1])) + normal * side
        port_labels.setdefault(comp, []).append((text, colour, at, (0.5 * tw + 1, 0.5 * FONT)))
    for labels in port_labels.values():  # two lines leaving a box side by side: keep both names legible
        where = remove_overlaps(np.array([at for _, _, at, _ in labels]),
                                np.array([size for _, _, _, size in labels]), iterations=50, gap=1.5)
        for (text, colour, _, _), at in zip(labels, where):
            ax.text(*at, text, fontsize=font - 1, color=colour, ha="center", va="center", zorder=4,
                    bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.85))

    # ---- nets ----------------------------------------------------------------------------------------
    for node in nets:
        kind = graph.nodes[node]["kind"]
        colour = KIND_COLOURS.get(kind, "black")
        p = xy[index[node]]
        ax.scatter(*p, s=(80 if graph.nodes[node]["volume"] else 34) * shrink**2, color=colour,
                   edgecolors="white", linewidths=0.8, zorder=3)
        ax.text(p[0], p[1] + 5, node[1], fontsize=font, color=colour, ha="center", va="bottom", zorder=5,
                fontweight="bold", bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.75))

    # ---- components ----------------------------------------------------------------------------------
    for node in components:
        name = node[1]
        sub = name.rsplit(".", 1)[0] if "." in name else None
        ax.text(*xy[index[node]], graph.nodes[node]["label"], fontsize=font, ha="center", va="center", zorder=6,
                linespacing=1.2, bbox=dict(boxstyle=f"round,pad={PAD / FONT:.2f}", fc="#fbfbf2",
                                           ec=sub_colour.get(sub, "#333333"), lw=(1.4 if sub else 1.0) * shrink))

    # ---- title and legend ------------------------------------------------------------------------------
    kinds = {graph.nodes[n]["kind"] for n in nets}
    handles = []
    for label, members, style in (("hydraulic", {PortKind.HYDRAULIC}, "-"),
                                  ("rotational / translational", {PortKind.ROTATIONAL, PortKind.TRANSLATIONAL}, "-"),
                                  ("signal (arrow: driver to reader)", {PortKind.SIGNAL}, "--")):
        if kinds & members:
            colour = KIND_COLOURS[next(iter(members))]
            handles.append(Line2D([], [], color=colour, marker="o", lw=1.6, linestyle=style, label=label))
    handles += [Line2D([], [], color="white", marker="s", markerfacecolor="#fbfbf2", markeredgecolor=c,
                       markersize=9, lw=0, label=f"subsystem {s}") for s, c in sub_colour.items()]
    top = 1.0 - 6.0 / (height + header)
    fig.text(0.5, top, f"{Path(flat.file).name}: {len(components)} components, {len(nets)} nets",
             fontsize=font + 3, ha="center", va="top")
    if handles:
        fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, top - 20.0 / (height + header)),
                   ncol=min(len(handles), 4), fontsize=font, frameon=False, handlelength=2.2)
    if not nodes:
        ax.text(0.5, 0.4, "empty circuit", ha="center", va="center", transform=ax.transAxes)
    atomic_write_figure(fig, Path(output_path))
