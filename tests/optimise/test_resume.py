"""--resume continues only the job that wrote the log, on the circuit it was built from: a changed
subsystem file or data file is refused by name (not only the job and its top netlist)."""

import shutil
from pathlib import Path

import pytest

from blocks.optimise.job import load_job
from blocks.optimise.log import LOG_NAME, LogError
from blocks.optimise.runner import run_optimise

ROOT = Path(__file__).resolve().parents[2]


def write_job(tmp_path, netlist: str, parameter: str, term: str) -> Path:
    path = tmp_path / "job.yaml"
    path.write_text(f"""\
netlist: {netlist}
output: {tmp_path / 'out'}
parameters:
  {parameter}: {{min: 2, max: 12}}
cost:
  terms:
    {term}
algorithm: {{method: complex, max_evaluations: 4}}
""")
    return path


def refused_after_edit(job_path: Path, edited: Path, old: str, new: str) -> str:
    job = load_job(job_path)
    run_optimise(job, workers=1, quiet=True, report=False)
    log = (job.output / LOG_NAME).read_bytes()
    run_optimise(load_job(job_path), resume=True, workers=1, quiet=True, report=False)  # unchanged: resumes
    text = edited.read_text()
    assert old in text
    edited.write_text(text.replace(old, new))
    with pytest.raises(LogError) as refused:
        run_optimise(load_job(job_path), resume=True, workers=1, quiet=True, report=False)
    assert (job.output / LOG_NAME).read_bytes() == log  # nothing written
    return str(refused.value)


def test_resume_refuses_a_changed_subsystem_file(tmp_path):
    shutil.copytree(ROOT / "netlists" / "examples", tmp_path / "nl")
    axis = tmp_path / "nl" / "parts" / "axis.yaml"
    message = refused_after_edit(write_job(tmp_path, "nl/three_axes.yaml", "bridge.Kp",
                                           "pk: {kind: max_abs, signal: pA_bridge, unit: bar}"),
                                 axis, 'V_line: "1 l"', 'V_line: "3 l"')
    assert "parts/axis.yaml changed" in message and "\n" not in message  # named from the netlist's folder


def test_resume_refuses_a_changed_csv_data_file(tmp_path):
    text = (ROOT / "netlists" / "opt" / "drive_line.yaml").read_text()
    inline = "params: {times: [0, 0.5, 2.5, 3.0], values: [0, 0.4, 0.4, 0]}"
    assert inline in text
    (tmp_path / "dl.yaml").write_text(text.replace(
        inline, "params: {times: {csv: ref.csv, column: t}, values: {csv: ref.csv, column: v}}"))
    ref = tmp_path / "ref.csv"
    ref.write_text("t [s],v [m/s]\n0,0\n0.5,0.4\n2.5,0.4\n3.0,0\n")
    message = refused_after_edit(write_job(tmp_path, "dl.yaml", "Kp",
                                           "pos: {kind: ise, signal: x, reference: x_ref, unit: mm}"),
                                 ref, "0.5,0.4\n2.5,0.4", "0.5,0.2\n2.5,0.2")
    assert "ref.csv changed" in message


def test_a_project_moved_elsewhere_resumes(tmp_path, monkeypatch):
    """The files are named relative to the netlist's folder (a review found a moved or remounted project
    refused: "... is no longer read by the netlist", though no file changed)."""
    shutil.copytree(ROOT / "netlists" / "examples", tmp_path / "a" / "nl")
    (tmp_path / "a" / "job.yaml").write_text(write_job(tmp_path, "nl/three_axes.yaml", "bridge.Kp",
                                                       "pk: {kind: max_abs, signal: pA_bridge, unit: bar}")
                                             .read_text().replace(f"output: {tmp_path / 'out'}", "output: out"))
    monkeypatch.chdir(tmp_path / "a")
    first = run_optimise(load_job(Path("job.yaml")), workers=1, quiet=True, report=False)
    shutil.move(tmp_path / "a", tmp_path / "b")
    monkeypatch.chdir(tmp_path / "b")
    again = run_optimise(load_job(Path("job.yaml")), resume=True, workers=1, quiet=True, report=False)
    assert again.evaluated == 0 and again.best["cost"] == first.best["cost"]


def test_resume_without_a_log_is_an_error_naming_the_folder(tmp_path, capsys):
    import cli

    path = write_job(tmp_path, str(ROOT / "netlists" / "opt" / "drive_line.yaml"), "Kp",
                     "pos: {kind: ise, signal: x, reference: x_ref, unit: mm}")
    assert cli.main(["optimise", str(path), "--resume", "--workers", "1", "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"vphs: {tmp_path / 'out'}: --resume, but") and "no evaluation log" in err
    assert err.count("\n") == 1 and not (tmp_path / "out").exists()  # nothing started


def test_a_log_of_an_earlier_version_is_refused_for_what_it_is(tmp_path):
    """A review: a log written before the netlist's design went first was refused as 'of another point than
    the resumed job asks for; the log does not belong to this job's run', which is untrue."""
    import json

    shutil.copytree(ROOT / "netlists" / "examples", tmp_path / "nl")
    job_path = write_job(tmp_path, "nl/three_axes.yaml", "bridge.Kp", "pk: {kind: max_abs, signal: pA_bridge, unit: bar}")
    job = load_job(job_path)
    run_optimise(job, workers=1, quiet=True, report=False)
    lines = (job.output / LOG_NAME).read_text().splitlines()
    header = json.loads(lines[0])
    del header["sources"]  # as an earlier vphs wrote it
    (job.output / LOG_NAME).write_text("\n".join([json.dumps(header)] + lines[1:]) + "\n")
    with pytest.raises(LogError, match="written by an earlier version of vphs .* run the job into another output"):
        run_optimise(load_job(job_path), resume=True, workers=1, quiet=True, report=False)
