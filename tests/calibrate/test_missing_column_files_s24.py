"""With several data files, a column missing from one of them (fault s24-4) is said at the experiment's key
(outputs.p2) and names the file that lacks it, not the first or the one that has it: the message says where
to look. It did already (blocks.calibrate.data._missing_column names the table's file); this shows it.
"""

from __future__ import annotations

import re
from pathlib import Path

import cli

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "netlists" / "experiments" / "relief_rig_steady.yaml"
GOOD = "setting,Q [l/min],p1 [bar],p2 [bar],p3 [bar]\n1,20,40,0.3,39\n2,40,50,0.5,48\n"
RENAMED = "setting,Q [l/min],p1 [bar],p_2 [bar],p3 [bar]\n3,20,45,0.3,44\n3,40,55,0.5,53\n"


def experiment(tmp_path: Path, files: dict[str, str]) -> Path:
    """The shipped relief-rig experiment on the data ``files`` (name -> text), in that order."""
    text = SHIPPED.read_text().replace("netlist: circuits/", f"netlist: {SHIPPED.parent}/circuits/")
    text = text.replace("data: data/relief_rig_steady.csv", f"data: [{', '.join(files)}]")
    for name, data in files.items():
        (tmp_path / name).write_text(data)
    path = tmp_path / "exp.yaml"
    path.write_text(text)
    return path


def test_the_file_that_lacks_a_column_is_named(tmp_path, capsys):
    for files, lacking in (({"a.csv": GOOD, "b.csv": RENAMED}, "b.csv"), ({"b.csv": RENAMED, "a.csv": GOOD}, "b.csv"),
                           ({"a.csv": GOOD, "c.csv": GOOD, "d.csv": RENAMED}, "d.csv")):
        path = experiment(tmp_path, files)
        code = cli.main(["calibrate", str(path), "-q", "-o", str(tmp_path / "out")])
        err = capsys.readouterr().err.strip()
        assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
        text = path.read_text()
        line = text[:text.index("  p2:")].count("\n") + 1
        assert re.fullmatch(rf"vphs: {re.escape(str(path))}:{line}:3: outputs\.p2: no column 'p2' in "
                            rf"{re.escape(str(tmp_path / lacking))} \(did you mean p_2\? its columns: setting, Q, p1, "
                            r"p_2, p3\)", err), err
        assert not (tmp_path / "out").exists()
