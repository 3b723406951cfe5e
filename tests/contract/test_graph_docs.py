"""The circuit picture (``vphs graph``) and the generated netlist reference (``vphs docs``).

The reference in ``docs/`` is committed; it must equal what the code generates now, so the documentation
cannot drift from the blocks and the schema.
"""

from __future__ import annotations

import re
import shutil
import struct
import subprocess
import sys
import typing
from pathlib import Path

import pytest

import cli
from blocks import docs, registry
from blocks.graph import circuit_graph, draw_circuit, remove_overlaps
from blocks.netlist.flatten import flatten
from blocks.netlist.spec import Simulation

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "netlists" / "examples"
REFERENCE = ROOT / "docs" / "netlist-reference.md"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE, f"{path} is not a PNG"
    assert data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def vphs_command() -> list[str]:
    exe = shutil.which("vphs")
    return [exe] if exe else [sys.executable, "-c", "import sys, cli; sys.exit(cli.main())"]


# ---------------------------------------------------------------- vphs graph
def test_vphs_graph_writes_a_png(tmp_path):
    out = tmp_path / "tmp.png"
    done = subprocess.run(vphs_command() + ["graph", str(EXAMPLES / "drive_line.yaml"), "-o", str(out)],
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "wrote" in done.stderr
    width, height = png_size(out)
    assert 500 <= width <= 6000 and 500 <= height <= 6000, (width, height)
    assert out.stat().st_size > 20_000  # a drawing, not an empty canvas
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")], "a temporary file was left behind"


def test_graph_of_subsystems_and_default_name(tmp_path):
    source = EXAMPLES / "three_axes.yaml"
    if not source.exists():
        pytest.skip("no subsystem example")
    # default output: the netlist's name with .png, next to it -> use a copy in tmp_path
    shutil.copytree(EXAMPLES, tmp_path / "examples")
    netlist = tmp_path / "examples" / "three_axes.yaml"
    assert cli.main(["graph", str(netlist)]) == 0
    width, height = png_size(netlist.with_suffix(".png"))
    assert width > 800 and height > 800


def test_graph_bad_input_is_exit_2(tmp_path, capsys):
    assert cli.main(["graph", str(tmp_path / "missing.yaml"), "-o", str(tmp_path / "x.png")]) == 2
    assert not (tmp_path / "x.png").exists()
    assert "vphs:" in capsys.readouterr().err


def test_graph_bad_output_names_the_option_given(tmp_path, capsys):
    """Review: "-o out/g.txt" was refused as "--plot 'out/g.txt': ...", an option graph does not have."""
    out = tmp_path / "g.txt"
    assert cli.main(["graph", str(EXAMPLES / "drive_line.yaml"), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == f"vphs: -o '{out}': give a file ending in .png, .pdf, .svg\n", err
    assert not out.exists()


def test_circuit_graph_is_the_netlist():
    flat = flatten(EXAMPLES / "drive_line.yaml")
    graph = circuit_graph(flat)
    assert sum(1 for n in graph.nodes if n[0] == "c") == len(flat.components)
    assert sum(1 for n in graph.nodes if n[0] == "n") == len(flat.nets)
    ports = sum(len(data["ports"]) for _, _, data in graph.edges(data=True))
    assert ports == sum(len(net.ports) for net in flat.nets.values())
    assert graph.edges[("c", "valve"), ("n", "A")]["ports"] == ["A"]


def test_remove_overlaps_separates_boxes():
    import numpy as np

    xy = np.array([[0.0, 0.0], [1.0, 0.5], [0.5, -0.2]])
    half = np.full((3, 2), 10.0)
    moved = remove_overlaps(xy, half)
    for i in range(3):
        for j in range(i + 1, 3):
            gap = np.abs(moved[i] - moved[j]) - 2 * half[0]
            assert gap.max() >= 0, "boxes still overlap"


def test_graph_is_deterministic(tmp_path):
    flat = flatten(EXAMPLES / "drive_line.yaml")
    draw_circuit(flat, str(tmp_path / "a.png"))
    draw_circuit(flat, str(tmp_path / "b.png"))
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()


# ---------------------------------------------------------------- vphs docs
def test_committed_reference_is_current():
    expected = docs.reference_text()
    assert REFERENCE.exists(), "docs/netlist-reference.md is missing: run `vphs docs`"
    assert REFERENCE.read_text(encoding="utf-8") == expected, \
        "docs/netlist-reference.md is out of date with the code: run `vphs docs` and commit the result"


def test_vphs_docs_writes_the_reference(tmp_path):
    out = tmp_path / "ref.md"
    assert cli.main(["docs", "-o", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == docs.reference_text()


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs /proc, a folder that takes no new files")
def test_docs_into_a_folder_that_takes_no_files_is_exit_2(capsys):
    """/proc passes a permission check (as root) but refuses new files. Review: "internal error:
    FileNotFoundError", exit 1, after the reference was generated."""
    assert cli.main(["docs", "-o", "/proc/x.md"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("vphs: cannot write '/proc/x.md': /proc ") and len(err.splitlines()) == 1, err
    assert "internal error" not in err


def test_reference_covers_every_block_and_key():
    text = docs.reference_text()
    for name in registry.all_types():
        assert f"#### `{name}`" in text, f"block {name} missing from the reference"
    assert docs.undocumented_fields() == [], "schema keys without a meaning in blocks.docs.FIELD_TEXT"
    solvers = typing.get_args(Simulation.model_fields["solver"].annotation)
    assert set(solvers) == set(docs.SOLVER_TEXT), "every solver choice needs a line in blocks.docs.SOLVER_TEXT"


def test_reference_links_resolve():
    text = docs.reference_text()
    anchors = {docs.anchor(h) for h in re.findall(r"^#{1,6} (.+)$", text, re.M)}
    links = set(re.findall(r"\]\(#([^)]+)\)", text))
    assert links and not links - anchors, f"links to missing headings: {sorted(links - anchors)}"
    headings = re.findall(r"^#{1,6} (.+)$", text, re.M)
    assert len(headings) == len({docs.anchor(h) for h in headings}), "two headings share an anchor"
