"""A channel mapped to a data column the CSV does not have (fault s23-3): the mistake is usually the
experiment's key (a misspelt or renamed column), so the error is placed at that key in the experiment file,
and still names the data file, its columns and the nearest one. It was placed at the CSV's header line.
"""

from __future__ import annotations

import re
from pathlib import Path

import cli

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "netlists" / "experiments" / "relief_rig_steady.yaml"
DATA = "setting,Q [l/min],p1 [bar],p2 [bar],p3 [bar]\n1,20,40,0.3,39\n1,40,50,0.5,48\n2,20,45,0.3,44\n"


def experiment(tmp_path: Path, change: tuple[str, str]) -> Path:
    """The shipped relief-rig experiment on a small data file in tmp_path, with ``change`` made to it."""
    text = SHIPPED.read_text().replace("netlist: circuits/", f"netlist: {SHIPPED.parent}/circuits/")
    text = text.replace("data: data/relief_rig_steady.csv", "data: data.csv")
    changed = text.replace(*change)
    assert changed != text
    (tmp_path / "data.csv").write_text(DATA)
    path = tmp_path / "exp.yaml"
    path.write_text(changed)
    return path


def line_of(text: str, needle: str) -> int:
    return text[:text.index(needle)].count("\n") + 1


def refused(tmp_path, capsys, path: Path) -> tuple[str, int, int, str]:
    """(file, line, column, message) of the one line ``vphs calibrate`` refuses ``path`` with (exit 2)."""
    code = cli.main(["calibrate", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    m = re.fullmatch(r"vphs: (.+?):(\d+):(\d+): (.*)", err)
    assert m, err
    return m[1], int(m[2]), int(m[3]), m[4]


def test_an_output_mapped_to_a_missing_column_is_placed_at_its_key(tmp_path, capsys):
    path = experiment(tmp_path, ('  p3: {signal: p3, noise: "0.2 bar"}', '  P3: {signal: p3, noise: "0.2 bar"}'))
    file, line, column, message = refused(tmp_path, capsys, path)
    assert (file, line, column) == (str(path), line_of(path.read_text(), "  P3:"), 3), message
    assert message == (f"outputs.P3: no column 'P3' in {tmp_path / 'data.csv'} (did you mean p3? its columns: "
                       f"setting, Q, p1, p2, p3)"), message


def test_an_input_mapped_to_a_missing_column_is_placed_at_its_key(tmp_path, capsys):
    path = experiment(tmp_path, ('  Q: {parameter: Q_in', '  q: {parameter: Q_in'))
    file, line, column, message = refused(tmp_path, capsys, path)
    assert (file, line, column) == (str(path), line_of(path.read_text(), "  q:"), 3), message
    assert message.startswith(f"inputs.q: no column 'q' in {tmp_path / 'data.csv'} (did you mean Q? "), message


def test_a_repeats_column_the_data_lacks_is_placed_at_repeats(tmp_path, capsys):
    path = experiment(tmp_path, ("group: setting\n", "group: setting\nrepeats: point\n"))
    file, line, column, message = refused(tmp_path, capsys, path)
    assert (file, line) == (str(path), line_of(path.read_text(), "repeats: point")), message
    assert message == (f"repeats: no column 'point' in {tmp_path / 'data.csv'} (its columns: setting, Q, p1, p2, "
                       f"p3)"), message
