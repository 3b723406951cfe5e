"""Jobs end to end: evaluations logged once each, failures recorded, parallel = serial, resume after
Ctrl-C and after a kill, sweeps, reports, the CLI's exit codes."""

import json
import os
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from blocks.optimise.job import load_job
from blocks.optimise.log import LOG_NAME, EvaluationLog, LogError, read_log
from blocks.optimise.runner import run_optimise, run_sweep

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).parent
DRIVE_LINE = ROOT / "netlists" / "opt" / "drive_line.yaml"


def job_file(tmp_path, text: str, name: str = "job.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def small_job(tmp_path, budget=24, candidates=2, cases=1, out="out", extra="", seed=4, tol=0) -> Path:
    loads = "\n".join(f"  c{i}: {{m_load: \"{7.5 * i} t\"}}" for i in range(cases))
    return job_file(tmp_path, f"""\
name: small
netlist: {DRIVE_LINE}
output: {tmp_path / out}
seed: {seed}
parameters:
  Kp: {{min: 1, max: 40, log: true}}
  Kv: {{min: 0.1, max: 1.0}}
cost:
  terms:
    pos: {{kind: ise, signal: x, reference: x_ref, unit: mm, weight: 50}}
    vel: {{kind: ise, signal: v, reference: v_ref, unit: mm/s}}
    max_pos: {{kind: max_abs, signal: x, reference: x_ref, unit: mm, weight: 0}}
load_cases:
{loads}
algorithm: {{method: complex, max_evaluations: {budget}, tol_x: {tol}, tol_f: {tol}, candidates: {candidates}}}
{extra}""")


def evaluations(folder: Path) -> list[dict]:
    return [json.loads(line) for line in (folder / LOG_NAME).read_text().splitlines()
            if json.loads(line)["type"] == "evaluation"]


def by_index(records):
    return {r["index"]: (r["x"], r["cost"]) for r in records}


def test_serial_job_logs_every_evaluation_once_and_reports(tmp_path):
    job = load_job(small_job(tmp_path))
    s = run_optimise(job, workers=1, quiet=True)
    records = evaluations(job.output)
    assert sorted(r["index"] for r in records) == list(range(s.total)) and s.evaluated == s.total
    assert len(s.records) == 24 and s.total == 1 + 24 + len(s.discarded)  # the budget counts the path
    assert records[0]["step"] == "netlist" and records[0]["parameters"] == job.start_values  # off the path
    on_path = {r["index"] for r in s.records}
    best = min((r for r in records if r["index"] in on_path), key=lambda r: r["cost"])
    assert s.best["index"] == best["index"] and s.best["cost"] == best["cost"]
    for name in ("report.md", "convergence.png", "best_signals.png", "best.json", "best_c0.csv"):
        assert (job.output / name).stat().st_size > 0, name
    report = (job.output / "report.md").read_text()
    assert f"cost {best['cost']:.6g}" in report and "| Kp |" in report
    saved = json.loads((job.output / "best.json").read_text())
    assert saved["parameters"] == best["parameters"]
    # a record's cost is the weighted sum of its terms
    r = records[5]
    terms = r["cases"]["c0"]["terms"]
    assert r["cost"] == pytest.approx(50 * terms["pos"] + terms["vel"], rel=1e-12)
    # the logged parameters are the design's SI values: re-simulating them gives the logged cost
    from blocks.circuit import Circuit

    res = Circuit.from_file(DRIVE_LINE).simulate({**r["parameters"], "m_load": 0.0})
    e = (res["x"] - res["x_ref"]) / 1e-3
    assert terms["pos"] == pytest.approx(float(np.sum((e[1:] ** 2 + e[:-1] ** 2) / 2 * np.diff(res.t))), rel=1e-9)


def test_local_pool_gives_the_same_evaluations_as_serial(tmp_path):
    """Two load cases: the pool runs each case as a task of its own and puts the record together."""
    serial = load_job(small_job(tmp_path, out="serial", cases=2))
    pool = load_job(small_job(tmp_path, out="pool", cases=2))
    run_optimise(serial, workers=1, quiet=True, report=False)
    s = run_optimise(pool, workers=2, quiet=True, report=False)
    assert s.executor == "local" and s.workers == 2
    a, b = evaluations(serial.output), evaluations(pool.output)
    assert by_index(a) == by_index(b)
    strip = lambda r: {c: {"terms": v["terms"], "cost": v["cost"]} for c, v in r["cases"].items()}  # noqa: E731
    assert {r["index"]: strip(r) for r in a} == {r["index"]: strip(r) for r in b}
    # a batch's first task goes to the worker, the next is evaluated in this process
    pids = {pid for r in b for pid in r["pids"]}
    assert len(pids) == 2 and os.getpid() in pids


def test_the_result_does_not_depend_on_the_number_of_workers(tmp_path):
    """candidates auto: one at a time on 1 worker, the reflection and the next retraction at once on 2. The
    2-worker run evaluates retractions ahead that the path does not need, and on this seed some cost less
    than the best design of the path; they stay in the log, marked discarded, out of the result (they once
    made the 2-worker run report another best than the 1-worker run)."""
    runs = {}
    for workers in (1, 2):
        job = load_job(small_job(tmp_path, budget=150, candidates="auto", seed=5, tol=1e-2, out=f"w{workers}"))
        runs[workers] = run_optimise(job, workers=workers, quiet=True)
    one, two = runs[1], runs[2]
    assert (one.candidates, two.candidates) == (1, 2)
    assert (one.best["x"], one.best["cost"], one.best["parameters"]) == (two.best["x"], two.best["cost"],
                                                                           two.best["parameters"])
    assert one.reason == two.reason == "cost converged" and one.iterations == two.iterations
    assert [(r["x"], r["cost"]) for r in one.records] == [(r["x"], r["cost"]) for r in two.records]
    assert one.discarded == [] and min(r["cost"] for r in two.discarded) < one.best["cost"]  # what made them differ
    saved = [json.loads((s.folder / "best.json").read_text()) for s in (one, two)]
    assert saved[0]["parameters"] == saved[1]["parameters"] and saved[0]["cost"] == saved[1]["cost"]
    # the best design's number is its place on the path (the log's index also counts the discarded ones)
    # (and the netlist's own design, evaluated first: log index 0)
    assert saved[0]["evaluation"] == saved[1]["evaluation"] == saved[0]["log_index"] - 1 < saved[1]["log_index"] - 1
    report = (two.folder / "report.md").read_text()
    assert f"## Best design: evaluation {saved[0]['evaluation']} of the path (in the log: {saved[1]['log_index']})" \
        in report
    assert f"evaluations: {len(one.records)} on the method's path" in report
    assert f"{len(two.discarded)} more were evaluated ahead in parallel and discarded" in report
    # the log keeps every evaluation once and says which were discarded
    header, logged = read_log(two.folder)
    assert sorted(r["index"] for r in logged if r.get("discarded")) == sorted(r["index"] for r in two.discarded)
    assert len(logged) == two.total == 1 + len(one.records) + len(two.discarded)


def test_the_report_says_how_to_simulate_the_best_design_again(tmp_path, monkeypatch):
    """The best design's cost comes from the free parameters, the job's set: values and the load case's
    values together: the report's command line per load case, run as 'vphs run', gives that case's cost."""
    import shlex

    import cli
    from blocks.circuit import Circuit
    from blocks.optimise.costs import evaluate_term

    path = small_job(tmp_path, budget=8, candidates=1, cases=2, extra="set: {Kvp: 0.5}\n")
    job = load_job(path)
    run_optimise(job, workers=1, quiet=True)
    saved = json.loads((job.output / "best.json").read_text())
    assert saved["set"] == {"Kvp": 0.5} and saved["load_cases"] == {"c0": {"m_load": 0.0}, "c1": {"m_load": 7500.0}}
    report = (job.output / "report.md").read_text()
    commands = [line for line in report.splitlines() if line.startswith("vphs run ")]
    assert commands == list(saved["commands"].values()) and len(commands) == 2
    simulated = []
    original = Circuit.simulate
    monkeypatch.setattr(Circuit, "simulate",
                        lambda self, *a, **k: simulated.append(original(self, *a, **k)) or simulated[-1])
    for case, command in saved["commands"].items():
        simulated.clear()
        argv = shlex.split(command)[1:] + ["-o", str(tmp_path / f"{case}.csv"), "-q"]
        assert cli.main(argv) == 0
        (result,) = simulated
        cost = sum(t.weight * evaluate_term(t, result.t, result) for t in job.terms)
        assert cost == pytest.approx(saved["cases"][case]["cost"], rel=1e-9)
    # the free parameters alone simulate another design (Kvp and the load at the netlist's values)
    simulated.clear()
    free = [a for k, v in saved["parameters"].items() for a in ("--set", f"{k}={v!r}")]
    assert cli.main(["run", str(DRIVE_LINE), *free, "-o", str(tmp_path / "x.csv"), "-q"]) == 0
    cost = sum(t.weight * evaluate_term(t, simulated[0].t, simulated[0]) for t in job.terms)
    assert cost != pytest.approx(saved["cases"]["c1"]["cost"], rel=1e-3)


@pytest.mark.parametrize("algorithm", [
    "{method: nelder_mead, max_evaluations: 30, start: netlist}",
    "{method: differential_evolution, max_evaluations: 30, popsize: 5}"])
def test_scipy_methods_run_as_jobs(tmp_path, algorithm):
    path = small_job(tmp_path, budget=30)
    path.write_text(path.read_text().replace(
        "algorithm: {method: complex, max_evaluations: 30, tol_x: 0, tol_f: 0, candidates: 2}",
        f"algorithm: {algorithm}"))
    job = load_job(path)
    s = run_optimise(job, workers=2, quiet=True)
    records = evaluations(job.output)
    assert sorted(r["index"] for r in records) == list(range(s.total)) and 0 < s.total <= 1 + 30
    assert records[0]["step"] == "netlist" and s.best["cost"] == min(r["cost"] for r in records[1:])
    if "nelder_mead" in algorithm:  # starts at the netlist's values Kp = 4, Kv = 0.4
        assert records[1]["parameters"] == pytest.approx({"Kp": 4.0, "Kv": 0.4})
    else:
        pids = {pid for r in records[1:] for pid in r["pids"]}
        assert {r["step"] for r in records[1:]} == {"generation"} and len(pids) == 2 and os.getpid() in pids
    assert "## Best design" in (job.output / "report.md").read_text()


@pytest.mark.parametrize("budget,sampled", [(15, True), (20, False)])
def test_differential_evolution_that_only_samples_says_so(tmp_path, capsys, budget, sampled):
    """Review: a budget below two generations evaluates the initial population (popsize * n = 10 random
    designs) and nothing after it; the report and the console said nothing."""
    import cli

    path = small_job(tmp_path, budget=budget)
    path.write_text(path.read_text().replace(
        f"algorithm: {{method: complex, max_evaluations: {budget}, tol_x: 0, tol_f: 0, candidates: 2}}",
        f"algorithm: {{method: differential_evolution, max_evaluations: {budget}, popsize: 5}}"))
    assert cli.main(["optimise", str(path), "--workers", "1", "-q"]) == 0
    steps = Counter(r["step"] for r in evaluations(tmp_path / "out"))
    assert steps["generation"] == (10 if sampled else 20)  # the budget's generations: 1 or 2
    report = (tmp_path / "out" / "report.md").read_text()
    warning = "differential evolution only sampled: max_evaluations = 15 allows its initial population of " \
              "popsize * n = 10 random designs"
    assert (warning in report.replace("Differential", "differential")) == sampled
    assert (f"vphs: warning: {warning}" in capsys.readouterr().err) == sampled


def test_failed_simulations_are_recorded_with_a_penalty_and_the_job_goes_on(tmp_path):
    # growth.yaml: y' = k*y. k > ~709 overflows (SimulationError); 354 < k < 709 overflows int y^2 dt;
    # below, int y^2 dt = (exp(2k) - 1)/(2k) reaches 1e305, so the penalty must be above that.
    path = job_file(tmp_path, f"""\
netlist: {HERE / 'netlists' / 'growth.yaml'}
output: {tmp_path / 'out'}
parameters: {{k: {{min: 0.1, max: 1000}}}}
cost: {{penalty: 1e308, terms: {{y: {{kind: ise, signal: y}}}}}}
algorithm: {{method: complex, max_evaluations: 60, points: 6}}
sweep: {{parameters: {{k: [1, 500, 1000, 2]}}}}
""")
    job = load_job(path)
    s = run_sweep(job, workers=1, quiet=True)
    records = evaluations(job.output / "sweep")
    status = {r["parameters"]["k"]: (r["status"], r["cost"], r["error"]) for r in records}
    # int_0^1 exp(2t) dt = (e^2 - 1)/2; the trapezoid over 10 ms samples is high by (2*dt)^2/12 = 3.3e-5
    assert status[1.0][0] == "ok" and status[1.0][1] == pytest.approx((np.exp(2.0) - 1) / 2 * (1 + 3.3e-5), rel=1e-5)
    assert status[500.0][:2] == ("failed", 1e308) and "not finite" in status[500.0][2]
    assert status[1000.0][:2] == ("failed", 1e308) and "the solver failed" in status[1000.0][2]
    assert status[2.0][0] == "ok" and s.failed == 2
    report = (job.output / "sweep" / "report.md").read_text()
    assert "Failed points (2)" in report and "the solver failed" in report
    # and an optimisation over the same range goes on through its failures to the optimum at the lower bound
    s = run_optimise(job, workers=1, quiet=True)
    assert s.failed > 0 and s.reason in ("budget", "parameters converged", "cost converged")
    assert s.best["status"] == "ok" and s.best["parameters"]["k"] == pytest.approx(0.1, rel=1e-2)


def test_a_refused_parameter_value_is_a_failed_evaluation():
    from blocks.optimise.evaluate import evaluate_design

    job = load_job(ROOT / "netlists" / "jobs" / "drive_line_controller.yaml")
    record = evaluate_design(job.spec(), {"valve.Cd": -1.0})
    assert record["status"] == "failed" and record["cost"] == job.penalty and "Cd" in record["error"]


def test_sweep_grid_points_and_table(tmp_path):
    extra = "sweep:\n  parameters:\n    Kp: [2, 8]\n    Kv: {min: 0.2, max: 0.6, points: 3}\n"
    job = load_job(small_job(tmp_path, extra=extra))
    s = run_sweep(job, workers=2, quiet=True)
    records = evaluations(job.output / "sweep")
    asked = sorted((r["parameters"]["Kp"], round(r["parameters"]["Kv"], 12)) for r in records)
    assert asked == [(2.0, 0.2), (2.0, 0.4), (2.0, 0.6), (8.0, 0.2), (8.0, 0.4), (8.0, 0.6)]
    table = (job.output / "sweep" / "sweep.csv").read_text().splitlines()
    assert table[0].startswith("Kp,Kv,pos [(mm)^2*s]") and len(table) == 7
    assert (job.output / "sweep" / "sweep.png").stat().st_size > 0
    assert s.best["cost"] == min(r["cost"] for r in records)


def test_a_log_is_never_overwritten_or_resumed_by_another_job(tmp_path):
    job = load_job(small_job(tmp_path, budget=8))
    run_optimise(job, workers=1, quiet=True, report=False)
    before = (job.output / LOG_NAME).read_bytes()
    with pytest.raises(LogError, match="--resume"):
        run_optimise(job, workers=1, quiet=True)
    other = load_job(small_job(tmp_path, budget=9))  # another budget: another job
    with pytest.raises(LogError, match="different job"):
        run_optimise(other, resume=True, workers=1, quiet=True)
    assert (job.output / LOG_NAME).read_bytes() == before
    # resuming the finished job evaluates nothing and reproduces its result
    s = run_optimise(job, resume=True, workers=1, quiet=True, report=False)
    assert s.evaluated == 0 and s.replayed == s.total and len(s.records) == 8
    assert (job.output / LOG_NAME).read_bytes() == before


def test_a_line_cut_short_by_a_kill_is_dropped(tmp_path):
    job = load_job(small_job(tmp_path, budget=10, candidates=1))  # one evaluation a line, no discarded lines
    run_optimise(job, workers=1, quiet=True, report=False)
    log = job.output / LOG_NAME
    lines = log.read_text().splitlines(keepends=True)
    log.write_text("".join(lines[:-2]) + lines[-2][:40])  # the last evaluation lost, the one before torn
    s = run_optimise(job, resume=True, workers=1, quiet=True, report=False)
    assert (s.replayed, s.evaluated) == (9, 2)  # the netlist's design and 8 of the path
    header, records = read_log(job.output)
    assert [r["index"] for r in records] == list(range(11))
    assert all(line.startswith("{") and line.endswith("}") for line in log.read_text().splitlines())


def _start(args, tmp_path):
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    # Ctrl-C as a terminal delivers it, even where the tests run in the background (which ignores SIGINT)
    code = "import signal, sys, cli; signal.signal(signal.SIGINT, signal.default_int_handler); " \
           "sys.exit(cli.main(sys.argv[1:]))"
    return subprocess.Popen([sys.executable, "-c", code, *args],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            start_new_session=True, text=True)


def _wait_for_evaluations(process, log: Path, lines: int, timeout: float = 60.0) -> int:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        count = log.read_bytes().count(b'"type": "evaluation"') if log.exists() else 0
        if count >= lines:
            return count
        assert process.poll() is None, process.communicate()
        time.sleep(0.01)
    raise AssertionError(f"the job wrote fewer than {lines} evaluations in {timeout} s")


@pytest.mark.parametrize("workers", ["1", "2"])
def test_interrupt_kill_and_resume_lose_nothing_and_repeat_nothing(tmp_path, workers):
    """Ctrl-C (SIGINT to the job's process group) at >= 40 evaluations, resume, SIGKILL of the job's
    process alone at >= 95, resume to the end: the log holds every evaluation once, and they are the
    evaluations of the same job run without interruption (the job's own process evaluates too: Ctrl-C
    must not turn its evaluation into a failed one)."""
    path = small_job(tmp_path, budget=150, cases=3, out="interrupted")
    log = tmp_path / "interrupted" / LOG_NAME
    p = _start(["optimise", str(path), "--workers", workers], tmp_path)
    _wait_for_evaluations(p, log, 40)
    os.killpg(p.pid, signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    assert "interrupted" in err and "--resume" in err
    first = evaluations(log.parent)
    assert 40 <= len(first) < 150

    p = _start(["optimise", str(path), "--workers", workers, "--resume"], tmp_path)
    _wait_for_evaluations(p, log, 95)
    os.kill(p.pid, signal.SIGKILL)  # the job's process only: its workers must notice and end
    p.communicate(timeout=60)
    second = evaluations(log.parent)
    assert 95 <= len(second) < 150

    p = _start(["optimise", str(path), "--workers", workers, "--resume", "-q"], tmp_path)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 0, err
    final = evaluations(log.parent)
    assert not [r for r in final if r["status"] != "ok"]
    counts = Counter(r["index"] for r in final)
    assert sorted(counts) == list(range(len(counts))) and max(counts.values()) == 1
    assert len([r for r in read_log(log.parent)[1] if not r.get("discarded") and r["step"] != "netlist"]) == 150
    # the budget: the path
    kept = by_index(second)
    assert {i: v for i, v in by_index(final).items() if i in kept} == kept  # nothing re-evaluated

    reference = load_job(small_job(tmp_path, budget=150, cases=3, out="reference"))
    run_optimise(reference, workers=1, quiet=True, report=False)
    assert by_index(evaluations(reference.output)) == by_index(final)
    assert (log.parent / "report.md").exists()


def test_sigterm_stops_the_job_as_ctrl_c_does_with_the_resume_hint(tmp_path):
    """Review: SIGTERM (kill, a batch system's time limit) exited 143 without a word."""
    path = small_job(tmp_path, budget=150, cases=3, out="terminated")
    log = tmp_path / "terminated" / LOG_NAME
    p = _start(["optimise", str(path), "--workers", "1"], tmp_path)
    _wait_for_evaluations(p, log, 20)
    p.terminate()
    out, err = p.communicate(timeout=60)
    assert p.returncode == 143, err
    assert err.splitlines()[-1].startswith("vphs: terminated; ") and f"vphs optimise {path} --resume" in err
    first = evaluations(log.parent)
    assert 20 <= len(first) < 151 and all(r["status"] == "ok" for r in first)  # none cut into a failure
    p = _start(["optimise", str(path), "--workers", "1", "--resume", "-q"], tmp_path)
    assert p.wait(timeout=120) == 0 and all(r["status"] == "ok" for r in evaluations(log.parent))


def test_cli_bad_job_is_one_line_exit_2(tmp_path, capsys):
    import cli

    path = job_file(tmp_path, f"netlist: {DRIVE_LINE}\ncost: {{terms: {{a: {{kind: ise, signal: nope}}}}}}\n")
    assert cli.main(["optimise", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"vphs: {path}:2:") and "'nope' is not a logged signal" in err and "\n" not in err
    assert cli.main(["optimise", str(path), "--workers", "0"]) == 2
    capsys.readouterr()
    # review: "internal error: ValueError: missing port number in address 'notanaddress'", exit 1
    assert cli.main(["optimise", str(small_job(tmp_path)), "--scheduler", "notanaddress"]) == 2
    assert capsys.readouterr().err.startswith("vphs: --scheduler 'notanaddress': the port is missing")
    assert cli.main(["sweep", str(small_job(tmp_path))]) == 2  # no sweep: section
    assert "no sweep: section" in capsys.readouterr().err
