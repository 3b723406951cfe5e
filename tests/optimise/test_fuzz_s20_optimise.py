"""Fuzzer round s20: algorithm settings that went to scipy (or the Complex method) unchecked.

``mutation: [2, 1]``, ``[0.5, 3]``, ``5``, ``-1`` and ``strategy: foo`` came out of scipy's
differential_evolution as "internal error: ValueError: ..." after the job had started (and left a log);
infinite tolerances stopped every method at once, popsize * n below 5 ran generations of scipy's 5 while the
budget counted popsize * n, and ``candidates: true`` ran as 1. Each is now one located line, exit 2, before any
evaluation."""

from pathlib import Path

import pytest

import cli
from blocks.errors import NetlistError
from blocks.optimise.job import DE_STRATEGIES, load_job

ROOT = Path(__file__).resolve().parents[2]
NETLIST = ROOT / "netlists" / "opt" / "drive_line.yaml"

JOB = f"""\
netlist: {NETLIST}
parameters:
  Kp: {{min: 1, max: 40, log: true}}
  Kv: {{min: 0.1, max: 1.0}}
cost:
  terms:
    pos: {{kind: ise, signal: x, reference: x_ref, unit: mm}}
algorithm:
  method: differential_evolution
  max_evaluations: 40
  SETTING
"""
ALGORITHM_LINE = 11  # the line of SETTING


def job_file(tmp_path, setting: str, method: str = "differential_evolution") -> Path:
    path = tmp_path / "job.yaml"
    path.write_text(JOB.replace("SETTING", setting).replace("differential_evolution", method)
                    + f"output: {tmp_path / 'out'}\n")
    return path


def refused(tmp_path, setting: str, method: str = "differential_evolution") -> NetlistError:
    path = job_file(tmp_path, setting, method)
    with pytest.raises(NetlistError) as info:
        load_job(path)
    error = info.value
    assert error.file == str(path) and error.line == ALGORITHM_LINE and "\n" not in str(error), str(error)
    return error


@pytest.mark.parametrize("mutation, message", [
    ("[2, 1]", "algorithm.mutation: [2, 1] is not a dither range: give [min, max] with 0 <= min < max < 2"),
    ("[0.5, 3]", "algorithm.mutation: [0.5, 3] is not a dither range"),
    ("[0.5, 2]", "algorithm.mutation: [0.5, 2] is not a dither range"),  # scipy refuses 2 in a range too
    ("[1, 0.5]", "algorithm.mutation: [1, 0.5] is not a dither range"),
    ("[-0.1, 0.5]", "algorithm.mutation: [-0.1, 0.5] is not a dither range"),
    ("5", "algorithm.mutation: 5 is outside [0, 2): give a number 0 <= F < 2"),
    ("-1", "algorithm.mutation: -1 is outside [0, 2)"),
    ("2", "algorithm.mutation: 2 is outside [0, 2)"),
    (".nan", "algorithm.mutation: nan is outside [0, 2)"),
    ("[0.5, 1, 1.5]", "algorithm.mutation: a list of 3 values; give one number 0 <= F < 2, or a dither range"),
    ("true", "algorithm.mutation: true is not a number"),
])
def test_a_mutation_scipy_would_refuse_is_refused_in_the_job(tmp_path, mutation, message):
    assert message in str(refused(tmp_path, f"mutation: {mutation}"))


@pytest.mark.parametrize("mutation, read", [("0", 0.0), ("1.5", 1.5), ("[0, 1.99]", (0.0, 1.99)),
                                             ("[0.5, 1.0]", (0.5, 1.0))])
def test_a_mutation_scipy_takes_is_kept(tmp_path, mutation, read):
    assert load_job(job_file(tmp_path, f"mutation: {mutation}")).settings.mutation == read


def test_an_unknown_strategy_is_refused_with_the_strategies_listed(tmp_path):
    message = str(refused(tmp_path, "strategy: foo"))
    assert f"algorithm.strategy: unknown strategy 'foo' (strategies: {', '.join(DE_STRATEGIES)})" in message


def test_the_strategies_listed_are_scipys():
    """Every strategy the job takes runs in scipy, and scipy takes no other (its own lists, where it has them)."""
    from scipy.optimize import differential_evolution

    for strategy in DE_STRATEGIES:
        differential_evolution(lambda x: float(x[0] ** 2), [(0, 1)], strategy=strategy, maxiter=2, popsize=6,
                               polish=False, updating="deferred", rng=0)
    with pytest.raises(ValueError, match="valid mutation strategy"):
        differential_evolution(lambda x: 0.0, [(0, 1)], strategy="foo", maxiter=1)
    from scipy.optimize._differentialevolution import DifferentialEvolutionSolver as solver

    known = getattr(solver, "_binomial", None), getattr(solver, "_exponential", None)
    if all(isinstance(k, dict) for k in known):
        assert set(DE_STRATEGIES) == set(known[0]) | set(known[1])


@pytest.mark.parametrize("setting, method, message", [
    ("tol: .inf", "differential_evolution", "algorithm.tol: must be a finite number, got inf"),
    ("atol: .inf", "differential_evolution", "algorithm.atol: must be a finite number, got inf"),
    ("xatol: .inf", "nelder_mead", "algorithm.xatol: must be a finite number, got inf"),
    ("fatol: .inf", "nelder_mead", "algorithm.fatol: must be a finite number, got inf"),
    ("tol_x: .inf", "complex", "algorithm.tol_x: must be a finite number, got inf"),
    ("tol_f: .inf", "complex", "algorithm.tol_f: must be a finite number, got inf"),
    ("candidates: true", "complex", "algorithm.candidates: true is not a number"),
])
def test_settings_that_stop_a_method_at_once_or_read_a_boolean_are_refused(tmp_path, setting, method, message):
    assert message in str(refused(tmp_path, setting, method))


@pytest.mark.parametrize("setting, message", [
    ("popsize: 2", "algorithm.popsize: popsize * n = 4 designs a generation for 2 free parameters; differential "
                   "evolution needs 5 at least (popsize: 3 or more)"),
    # rand2 draws 5 designs besides the one it mutates: with 5 in all, a ValueError inside scipy
    ("popsize: 2\n  strategy: rand2bin", "algorithm.popsize: popsize * n = 4 designs a generation for 2 free "
                                         "parameters; differential evolution needs 6 at least with strategy "
                                         "rand2bin (popsize: 3 or more)"),
])
def test_a_generation_smaller_than_scipy_can_use_is_refused(tmp_path, setting, message):
    """scipy makes a generation of max(5, popsize * n): the budget, counted in popsize * n, would be wrong."""
    assert message in str(refused(tmp_path, setting))
    assert load_job(job_file(tmp_path, "popsize: 3\n  strategy: rand2exp")).settings.popsize == 3


def test_rand2_with_five_designs_a_generation_is_refused_at_popsize(tmp_path):
    path = job_file(tmp_path, "strategy: rand2bin")
    path.write_text(path.read_text().replace("  Kv: {min: 0.1, max: 1.0}\n", "").replace(
        "strategy: rand2bin", "strategy: rand2bin\n  popsize: 5"))
    with pytest.raises(NetlistError) as info:
        load_job(path)
    assert info.value.line == 11 and "popsize * n = 5 designs a generation for 1 free parameter; differential " \
        "evolution needs 6 at least with strategy rand2bin (popsize: 6 or more)" in str(info.value), str(info.value)


@pytest.mark.parametrize("setting", ["mutation: [2, 1]", "mutation: [0.5, 3]", "mutation: 5", "mutation: -1",
                                     "strategy: foo"])
def test_vphs_optimise_says_one_line_exits_2_and_writes_nothing(tmp_path, capsys, setting):
    path = job_file(tmp_path, setting)
    assert cli.main(["optimise", str(path), "-q", "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"vphs: {path}:{ALGORITHM_LINE}:3: algorithm.") \
        and "internal error" not in err, err
    assert not (tmp_path / "out").exists()
