"""A point the job has evaluated already is answered from its record, not simulated again (review: the
Complex method simulated Kp = 2.0, clipped to its bound, five times in a row; nelder_mead with start:
netlist simulated the netlist's design twice). The path, the best and the counts are those of the job
without the answering; only the simulations, counted by a spy, drop."""

import json
from pathlib import Path

import pytest

from blocks.optimise import executors, runner
from blocks.optimise.job import load_job
from blocks.optimise.log import LOG_NAME, read_log
from blocks.optimise.repeats import Repeats
from blocks.optimise.runner import run_optimise
from tests.optimise.jobs import drive_line_job

def write_job(tmp_path, out: str, algorithm: str, parameters: str = "Kp: {min: 1, max: 3}") -> Path:
    name, bounds = parameters.split(": ", 1)
    return drive_line_job(tmp_path, out, {name: bounds}, algorithm)


class NoRepeats(Repeats):
    """The job as it was: every point simulated."""

    def original(self, x):
        return None


@pytest.fixture
def simulations(monkeypatch):
    """Counts the designs the (serial) executor simulates (not its warm-up, an empty design)."""
    count = {"n": 0}
    real = executors.evaluate_design

    def spy(spec, design):
        count["n"] += bool(design)
        return real(spec, design)

    monkeypatch.setattr(executors, "evaluate_design", spy)
    return count


def run(path: Path, simulations, resume: bool = False):
    """The job's summary and the number of designs it simulated."""
    before = simulations["n"]
    summary = run_optimise(load_job(path), resume=resume, workers=1, quiet=True, report=False)
    return summary, simulations["n"] - before


def answer_nothing(monkeypatch) -> None:
    """Every point simulated: none answered from earlier batches' records, nor from its batch's."""
    monkeypatch.setattr(runner, "Repeats", NoRepeats)
    monkeypatch.setattr(runner, "key", lambda z: object())


def path_of(summary):
    return [(r["index"], r["x"], r["step"], r["status"], r["cost"], r["parameters"]) for r in summary.records]


@pytest.mark.parametrize("candidates", [1, 3])  # 3: equal points within one batch too
def test_a_point_clipped_to_a_bound_again_is_not_simulated_again(tmp_path, simulations, monkeypatch, candidates):
    algorithm = f"{{method: complex, max_evaluations: 20, candidates: {candidates}}}"
    answered, ran = run(write_job(tmp_path, "answered", algorithm), simulations)
    answer_nothing(monkeypatch)
    simulated, ran_all = run(write_job(tmp_path, "simulated", algorithm), simulations)
    assert path_of(answered) == path_of(simulated) and len(answered.records) == 20
    assert (answered.best["x"], answered.best["cost"]) == (simulated.best["x"], simulated.best["cost"])
    assert (answered.reason, answered.iterations, answered.failed) == (simulated.reason, simulated.iterations,
                                                                      simulated.failed)
    assert [r["index"] for r in answered.discarded] == [r["index"] for r in simulated.discarded]
    _, logged = read_log(answered.folder)
    repeats = [r for r in logged if "repeat_of" in r]
    assert repeats and all(r["x"] in ([0.0], [1.0]) for r in repeats)  # on a bound
    assert ran == len(logged) - len(repeats) and ran_all == len(logged) == answered.total
    assert answered.repeated == len(repeats) and answered.evaluated == ran
    for r in repeats:
        original = logged[r["repeat_of"]]
        assert "repeat_of" not in original and original["x"] == r["x"] and original["cost"] == r["cost"]


def test_nelder_mead_starting_at_the_netlist_answers_its_start_from_evaluation_0(tmp_path, simulations):
    path = write_job(tmp_path, "nm", "{method: nelder_mead, max_evaluations: 6, start: netlist}",
                     parameters="Kp: {min: 2, max: 20, log: true}")
    summary, ran = run(path, simulations)
    _, logged = read_log(summary.folder)
    assert logged[0]["step"] == "netlist" and logged[1]["step"] == "simplex"
    assert logged[1]["repeat_of"] == 0 and logged[1]["x"] == logged[0]["x"]
    assert logged[1]["parameters"] == logged[0]["parameters"] == {"Kp": 4.0}  # the netlist's value exactly
    assert logged[1]["cost"] == logged[0]["cost"] and summary.records[0] is not summary.netlist_design
    assert len(summary.records) == 6 and ran == len(logged) - 1 - sum("repeat_of" in r for r in logged[2:])


def test_a_resumed_job_answers_repeats_of_points_read_back_from_the_log(tmp_path, simulations):
    path = write_job(tmp_path, "resumed", "{method: complex, max_evaluations: 20}")
    whole, _ = run(path, simulations)
    log = tmp_path / "resumed" / LOG_NAME
    lines = log.read_text().splitlines(keepends=True)
    cut = next(k for k, line in enumerate(lines) if "repeat_of" in line) + 1  # the first repeat kept
    log.write_text("".join(lines[:cut]))
    resumed, ran = run(path, simulations, resume=True)
    assert path_of(resumed) == path_of(whole)
    later = [json.loads(line) for line in lines[cut:] if json.loads(line)["type"] == "evaluation"]
    assert ran == sum("repeat_of" not in r for r in later) and resumed.repeated == len(later) - ran
    assert resumed.path_repeats == whole.path_repeats == sum("repeat_of" in r for r in whole.records) > 0


def test_nelder_mead_from_the_netlist_takes_the_same_path_as_before(tmp_path, simulations, monkeypatch):
    algorithm = "{method: nelder_mead, max_evaluations: 12, start: netlist}"
    answered, ran = run(write_job(tmp_path, "answered", algorithm, "Kp: {min: 2.2, max: 13.1}"), simulations)
    answer_nothing(monkeypatch)
    simulated, ran_all = run(write_job(tmp_path, "simulated", algorithm, "Kp: {min: 2.2, max: 13.1}"), simulations)
    assert path_of(answered) == path_of(simulated) and (answered.best["x"], answered.best["cost"]) == \
        (simulated.best["x"], simulated.best["cost"])
    assert ran < ran_all == 1 + 12
