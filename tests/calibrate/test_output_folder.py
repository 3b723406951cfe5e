"""A calibration's output folder: its files replace the previous run's whole, or not at all
(blocks/calibrate/output.py), and `vphs calibrate` keeps the previous output when a run fails or is
interrupted."""

from __future__ import annotations

from pathlib import Path

import pytest

import cli
from blocks.calibrate import output
from blocks.calibrate.output import PREVIOUS, replacing
from blocks.errors import VphsError

ROOT = Path(__file__).resolve().parents[2]
EXPERIMENT = ROOT / "netlists" / "experiments" / "relief_rig_steady.yaml"


def _previous_run(folder: Path) -> dict[str, str]:
    """A folder as an earlier calibration with two rounds left it, plus a user's note."""
    files = {"report.md": "old report", "report.json": "{}", "round1/augmented.yaml": "round 1",
             "round2/candidates/a.yaml": "round 2", "experiment_augmented.yaml": "old experiment",
             "notes.txt": "the user's"}
    for name, text in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text)
    return files


def _contents(folder: Path) -> dict[str, str]:
    return {str(p.relative_to(folder)): p.read_text() for p in folder.rglob("*") if p.is_file()}


def test_a_finished_run_leaves_none_of_the_previous_runs_files(tmp_path):
    _previous_run(tmp_path)
    with replacing(tmp_path):
        assert sorted(p.name for p in tmp_path.iterdir()) == [PREVIOUS, "notes.txt"]  # the old run's aside
        (tmp_path / "round1").mkdir()
        (tmp_path / "round1" / "augmented.yaml").write_text("new round 1")
        (tmp_path / "report.md").write_text("new report")
    assert _contents(tmp_path) == {"round1/augmented.yaml": "new round 1", "report.md": "new report",
                                   "notes.txt": "the user's"}  # no round2 of the old run beside the new report


@pytest.mark.parametrize("error", [KeyboardInterrupt, VphsError, RuntimeError])
def test_a_run_that_fails_leaves_the_previous_output_as_it_was(tmp_path, error):
    before = _previous_run(tmp_path)
    with pytest.raises(error):
        with replacing(tmp_path):
            (tmp_path / "report.json").write_text("{\"new\": true}")  # written before the run stopped
            (tmp_path / "round1").mkdir()
            (tmp_path / "round1" / "screening.yaml").write_text("new")
            raise error("stopped")
    assert _contents(tmp_path) == before


def test_a_run_killed_outright_is_undone_by_the_next(tmp_path):
    before = _previous_run(tmp_path)
    (tmp_path / PREVIOUS).mkdir()  # as a killed run leaves it: the previous output aside, its own beside it
    for name in ("report.md", "round1", "round2", "report.json", "experiment_augmented.yaml"):
        (tmp_path / name).rename(tmp_path / PREVIOUS / name)
    (tmp_path / "report.json").write_text("half a run")
    with pytest.raises(VphsError):
        with replacing(tmp_path):
            raise VphsError("bad input")
    assert _contents(tmp_path) == before


def _split(folder: Path, aside: str, names: tuple) -> None:
    (folder / aside).mkdir()
    for name in names:
        (folder / name).rename(folder / aside / name)


@pytest.mark.parametrize("moved", [(), ("report.md",), ("report.md", "round1", "round2")])
def test_a_run_killed_while_moving_the_previous_output_aside_loses_none_of_it(tmp_path, moved):
    """Killed with some entries in .previous.partial, the rest still in the folder (moving aside, or moving
    back in a restore): the next run moves them back and deletes nothing."""
    before = _previous_run(tmp_path)
    _split(tmp_path, output.MOVING, moved)
    with pytest.raises(VphsError):
        with replacing(tmp_path):
            raise VphsError("bad input")
    assert _contents(tmp_path) == before


def test_a_run_killed_while_deleting_the_previous_output_keeps_its_own(tmp_path):
    """Killed after its report, while deleting the previous output (renamed .discard): the folder holds the
    finished run's output, which the next run keeps as its previous one."""
    before = _previous_run(tmp_path)
    _split(tmp_path, output.DISCARD, ("round2",))  # what was left of the deletion
    with pytest.raises(VphsError):
        with replacing(tmp_path):
            raise VphsError("bad input")
    assert _contents(tmp_path) == {k: v for k, v in before.items() if not k.startswith("round2")}


def test_an_interrupt_while_moving_aside_moves_everything_back(tmp_path, monkeypatch):
    before = _previous_run(tmp_path)
    renames = []
    real = Path.rename

    def interrupted(self, target):
        renames.append(self.name)
        if len(renames) == 3:
            raise KeyboardInterrupt
        return real(self, target)

    monkeypatch.setattr(Path, "rename", interrupted)
    with pytest.raises(KeyboardInterrupt):
        with replacing(tmp_path):
            pytest.fail("the body must not run")
    monkeypatch.setattr(Path, "rename", real)
    assert _contents(tmp_path) == before


@pytest.mark.parametrize("kind", ["file", "symlink"])
def test_a_previous_that_is_not_its_folder_is_bad_input(tmp_path, kind):
    before = _previous_run(tmp_path)
    if kind == "file":
        (tmp_path / PREVIOUS).write_text("not ours")
    else:
        (tmp_path / "elsewhere").mkdir()
        (tmp_path / PREVIOUS).symlink_to(tmp_path / "elsewhere")
    with pytest.raises(VphsError, match=r"\.previous is not a folder of vphs calibrate's"):
        with replacing(tmp_path):
            pytest.fail("the body must not run")
    assert {k: v for k, v in _contents(tmp_path).items() if k != PREVIOUS} == before


def test_a_body_that_removes_the_folder_it_was_given_keeps_its_own_error(tmp_path):
    import shutil

    with pytest.raises(RuntimeError, match="the real error"):
        with replacing(tmp_path / "out") as folder:
            shutil.rmtree(folder)
            raise RuntimeError("the real error")


def test_a_folder_the_run_made_is_removed_when_it_fails(tmp_path):
    with pytest.raises(VphsError):
        with replacing(tmp_path / "new" / "out"):
            raise VphsError("bad input")
    assert not (tmp_path / "new" / "out").exists()


def test_only_what_a_calibration_writes_is_owned():
    for name in ("report.md", "report.json", "residuals.png", "fit.png", "latent_trace.png",
                 "experiment_augmented.yaml", "exchange", "elimination", "round1", "round12"):
        assert output.OWNED.fullmatch(name), name
    for name in ("notes.txt", "report.md.bak", "round", "data.csv", PREVIOUS):
        assert not output.OWNED.fullmatch(name), name


def test_an_output_folder_under_a_file_is_refused_before_the_fit(tmp_path, capsys):
    (tmp_path / "afile.txt").write_text("x")
    assert cli.main(["calibrate", str(EXPERIMENT), "-o", str(tmp_path / "afile.txt" / "sub"), "-q"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"vphs: output folder {tmp_path / 'afile.txt' / 'sub'}: {tmp_path / 'afile.txt'} is a file, "
                   f"not a folder; give another folder (-o)")


def test_an_interrupted_calibration_keeps_the_previous_report(tmp_path, monkeypatch, capsys):
    before = _previous_run(tmp_path)

    def interrupted(exp, out, progress=None, warn=None):
        (out / "report.json").write_text("{\"new\": true}")
        raise KeyboardInterrupt

    monkeypatch.setattr("blocks.calibrate.run.calibrate", interrupted)
    assert cli.main(["calibrate", str(EXPERIMENT), "-o", str(tmp_path), "-q"]) == 130
    assert "interrupted" in capsys.readouterr().err
    assert _contents(tmp_path) == before
