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


def test_a_ctrl_c_during_the_renames_is_taken_after_both(tmp_path, monkeypatch):
    """A real SIGINT sent just after the first rename (found by a review of the first version, which blocked
    the signal in the main thread only: another thread took it, and the first file was new, the second old)."""
    import os
    import signal

    a, b = tmp_path / "a.csv", tmp_path / "b.png"
    a.write_text("old a")
    b.write_text("old b")
    real_replace, calls = os.replace, []

    def replace_then_interrupt(src, dst):
        real_replace(src, dst)
        calls.append(dst)
        if len(calls) == 1:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(os, "replace", replace_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        write_together((a, lambda tmp: tmp.write_text("new a")), (b, lambda tmp: tmp.write_text("new b")))
    assert (a.read_text(), b.read_text()) == ("new a", "new b") and len(calls) == 2
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_two_files_of_one_path_are_refused(tmp_path):
    with pytest.raises(ValueError, match="two of the files are one path"):
        write_together((tmp_path / "r.png", lambda tmp: tmp.write_text("csv")),
                       (tmp_path / "r.png", lambda tmp: tmp.write_text("png")))
    assert list(tmp_path.iterdir()) == []


def test_vphs_run_interrupted_while_plotting_leaves_the_last_runs_csv_and_plot(tmp_path, monkeypatch, capsys):
    csv, png = tmp_path / "r.csv", tmp_path / "r.png"
    assert cli.main(["run", str(DRIVE), "-q", "--t-end", "0.2 s", "-o", str(csv), "--plot", str(png)]) == 0
    before = (csv.read_bytes(), png.read_bytes())

    def interrupted(self, path, title=None, x=None, y=None):
        raise KeyboardInterrupt

    monkeypatch.setattr(Result, "plot", interrupted)
    code = cli.main(["run", str(DRIVE), "-q", "--t-end", "0.3 s", "-o", str(csv), "--plot", str(png)])
    assert code == 130 and "interrupted" in capsys.readouterr().err
    assert (csv.read_bytes(), png.read_bytes()) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "r.png"]


def test_outputs_that_would_destroy_an_input_or_each_other_are_refused(tmp_path, capsys):
    """Found by a review: `-o same.png --plot same.png` lost the CSV, and `-o` naming the netlist replaced it."""
    netlist = tmp_path / "net.yaml"
    netlist.write_text(DRIVE.read_text())
    assert cli.main(["run", str(netlist), "-q", "-o", str(netlist)]) == 2
    assert "is an input of this command" in capsys.readouterr().err and netlist.read_text() == DRIVE.read_text()
    assert cli.main(["run", str(netlist), "-q", "-o", str(tmp_path / "r.png"), "--plot", str(tmp_path / "r.png")]) == 2
    assert "-o and --plot name one file" in capsys.readouterr().err and not (tmp_path / "r.png").exists()


def test_a_file_system_that_refuses_the_write_mid_run_is_one_line(tmp_path, monkeypatch, capsys):
    """A disk that fills (or a folder removed) while the run went on: one line naming the file, not an
    'internal error' with the exception's class."""
    import errno

    import blocks.result

    def full(*files):
        raise OSError(errno.ENOSPC, "No space left on device", str(files[0][0]))

    monkeypatch.setattr(blocks.result, "write_together", full)
    code = cli.main(["run", str(DRIVE), "-q", "--t-end", "0.1 s", "-o", str(tmp_path / "r.csv")])
    assert code == 1 and capsys.readouterr().err == f"vphs: {tmp_path / 'r.csv'}: No space left on device\n"


def test_a_symbolic_link_is_written_through_and_kept(tmp_path):
    """Found by a linearise review: `-o link.csv` replaced the link with a file and left its target stale."""
    (tmp_path / "real").mkdir()
    target = tmp_path / "real" / "results.csv"
    target.write_text("old")
    link = tmp_path / "link.csv"
    link.symlink_to(Path("real") / "results.csv")
    write_together((link, lambda tmp: tmp.write_text("new")))
    assert link.is_symlink() and target.read_text() == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv", "real"]


def test_a_named_pipe_is_written_into_not_replaced(tmp_path):
    """A pipe (or /dev/stdout) cannot be renamed over without being destroyed: the staged bytes go into it,
    and what reads the pipe gets them. With no process reading it, that is said at once (a wait there would
    not even yield to Ctrl-C, found by the diff review)."""
    import os

    fifo = tmp_path / "stream.csv"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="no process reads this pipe"):
        write_together((fifo, lambda tmp: tmp.write_text("t [s]\n0\n")))
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        write_together((fifo, lambda tmp: tmp.write_text("t [s]\n0\n")))
        assert os.read(reader, 100) == b"t [s]\n0\n"
    finally:
        os.close(reader)
    assert not fifo.is_file() and fifo.exists()  # still the pipe
    assert sorted(p.name for p in tmp_path.iterdir()) == ["stream.csv"]


def test_dev_stdout_is_appended_to_not_renamed_over(capfd):
    """`vphs run -o /dev/stdout >> log.csv`: /dev/stdout leads to the log file, which a rename would replace,
    losing what it held (found by the diff review)."""
    print("previous line", flush=True)
    write_together((Path("/dev/stdout"), lambda tmp: tmp.write_text("t [s]\n0\n")))
    assert capfd.readouterr().out == "previous line\nt [s]\n0\n"


def test_a_symbolic_link_loop_is_one_line(tmp_path, capsys):
    (tmp_path / "a.csv").symlink_to(tmp_path / "b.csv")
    (tmp_path / "b.csv").symlink_to(tmp_path / "a.csv")
    code = cli.main(["run", str(DRIVE), "--t-end", "0.01", "-q", "-o", str(tmp_path / "a.csv")])
    assert code == 2 and "is a symbolic link that leads back to itself" in capsys.readouterr().err


def test_a_full_device_is_one_line_naming_it(tmp_path, capsys):
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full here")
    code = cli.main(["run", str(DRIVE), "--t-end", "0.01", "-q", "-o", "/dev/full"])
    err = capsys.readouterr().err
    assert code == 1 and err == "vphs: /dev/full: No space left on device\n"
    assert Path("/dev/full").is_char_device()
