"""The netlist's own design is evaluated first (log index 0, off the method's path) and the report and the
console say plainly when the best found is not better than it (review: a 30-evaluation "optimum" worse
than the starting design, with no word)."""

from pathlib import Path

from blocks.optimise.evaluate import evaluate_design
from blocks.optimise.job import load_job
from blocks.optimise.log import read_log
from blocks.optimise.runner import run_optimise

ROOT = Path(__file__).resolve().parents[2]
DRIVE_LINE = ROOT / "netlists" / "opt" / "drive_line.yaml"
KNOWN_OPTIMUM = Path(__file__).resolve().parent / "netlists" / "known_optimum.yaml"


def _job(tmp_path, netlist: Path, body: str) -> Path:
    """job.yaml in ``tmp_path``: the netlist, an output folder beside it, seed 3, then ``body``."""
    path = tmp_path / "job.yaml"
    path.write_text(f"netlist: {netlist}\noutput: {tmp_path / 'out'}\nseed: 3\n" + body)
    return path


def write_job(tmp_path, kp_bounds: str = "{min: 2, max: 20, log: true}", budget: int = 30) -> Path:
    return _job(tmp_path, DRIVE_LINE, f"""\
parameters:
  valve.A_max: {{min: "60 mm^2", max: "250 mm^2"}}
  spool.wn:    {{min: "4 Hz", max: "20 Hz"}}
  Kp:          {kp_bounds}
set: {{Kv: 0.4, m_load: "10 t"}}
cost:
  terms:
    pos: {{kind: ise, signal: x, reference: x_ref, unit: mm, weight: 50}}
    vel: {{kind: ise, signal: v, reference: v_ref, unit: mm/s}}
algorithm: {{method: complex, max_evaluations: {budget}}}
""")


def write_known_optimum_job(tmp_path) -> Path:
    """A job over tests/optimise/netlists/known_optimum.yaml, whose netlist design (k = 1) is the exact
    optimum, cost 0: no point the method tries can be better (k exactly 1.0 aside)."""
    return _job(tmp_path, KNOWN_OPTIMUM, """\
parameters:
  k:      {min: 0.5, max: 3}
  sys.wn: {min: "5 rad/s", max: "20 rad/s"}
cost:
  terms:
    err: {kind: ise, signal: y, reference: r}
algorithm: {method: complex, max_evaluations: 20}
""")


def test_a_best_worse_than_the_netlist_design_is_said(tmp_path, capsys):
    import cli

    path = write_known_optimum_job(tmp_path)
    job = load_job(path)
    own = evaluate_design(job.spec(), job.start_values)["cost"]
    assert own == 0.0  # y = 1 throughout: the netlist's design is the optimum
    assert cli.main(["optimise", str(path), "--workers", "1", "-q"]) == 0
    header, records = read_log(job.output)
    assert records[0]["step"] == "netlist" and records[0]["parameters"] == job.start_values
    assert records[0]["cost"] == own
    best = min(r["cost"] for r in records[1:])
    assert best > own
    report = (job.output / "report.md").read_text()
    sentence = f"not better than the netlist's own design (cost {own:.6g})"
    assert sentence in report.replace("NOT", "not")
    err = capsys.readouterr().err
    assert "warning" in err and sentence in err.replace("NOT", "not")
    # resumed, the netlist's design is read back, not evaluated again
    s = run_optimise(load_job(path), resume=True, workers=1, quiet=True, report=False)
    assert s.evaluated == 0 and s.netlist_design["cost"] == own


def test_a_netlist_design_outside_the_bounds_is_not_evaluated_and_the_report_says_why(tmp_path):
    job = load_job(write_job(tmp_path, kp_bounds="{min: 5, max: 20}", budget=8))  # the netlist has Kp = 4
    s = run_optimise(job, workers=1, quiet=True)
    header, records = read_log(job.output)
    assert "netlist" not in {r["step"] for r in records} and s.total == len(s.records) == 8
    report = (job.output / "report.md").read_text()
    assert "the netlist's own design was not evaluated: Kp = 4 is outside [5, 20]" in report.replace("The", "the")
