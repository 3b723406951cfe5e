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
    assert f"{axis.resolve()} changed" in message and "\n" not in message


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
    assert f"{ref.resolve()} changed" in message


def test_resume_without_a_log_is_an_error_naming_the_folder(tmp_path, capsys):
    import cli

    path = write_job(tmp_path, str(ROOT / "netlists" / "opt" / "drive_line.yaml"), "Kp",
                     "pos: {kind: ise, signal: x, reference: x_ref, unit: mm}")
    assert cli.main(["optimise", str(path), "--resume", "--workers", "1", "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"vphs: {tmp_path / 'out'}: --resume, but") and "no evaluation log" in err
    assert err.count("\n") == 1 and not (tmp_path / "out").exists()  # nothing started
