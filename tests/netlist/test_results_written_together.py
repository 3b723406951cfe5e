"""`vphs run -o results.csv --plot results.png` replaces both files or neither (blocks.result.write_together).
Found by a usability review: Ctrl-C while the plot was drawn left the new run's CSV beside the last run's
plot, and the message said "nothing half-written was left behind"."""

from __future__ import annotations

from pathlib import Path

import pytest

import cli
from blocks.result import Result, write_together

ROOT = Path(__file__).resolve().parents[2]
DRIVE = ROOT / "netlists" / "examples" / "drive_line.yaml"


def test_an_interrupt_while_the_second_file_is_written_keeps_both_old_files(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.png"
    a.write_text("old a")
    b.write_text("old b")

    def interrupted(tmp):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_together((a, lambda tmp: tmp.write_text("new a")), (b, interrupted))
    assert (a.read_text(), b.read_text()) == ("old a", "old b")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.png"]  # no temporary file left
    write_together((a, lambda tmp: tmp.write_text("new a")), (b, lambda tmp: tmp.write_text("new b")))
    assert (a.read_text(), b.read_text()) == ("new a", "new b")


def test_vphs_run_interrupted_while_plotting_leaves_the_last_runs_csv_and_plot(tmp_path, monkeypatch, capsys):
    csv, png = tmp_path / "r.csv", tmp_path / "r.png"
    assert cli.main(["run", str(DRIVE), "-q", "--t-end", "0.2 s", "-o", str(csv), "--plot", str(png)]) == 0
    before = (csv.read_bytes(), png.read_bytes())

    def interrupted(self, path, title=None):
        raise KeyboardInterrupt

    monkeypatch.setattr(Result, "plot", interrupted)
    code = cli.main(["run", str(DRIVE), "-q", "--t-end", "0.3 s", "-o", str(csv), "--plot", str(png)])
    assert code == 130 and "interrupted" in capsys.readouterr().err
    assert (csv.read_bytes(), png.read_bytes()) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "r.png"]
