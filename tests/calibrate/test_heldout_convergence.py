"""Held-out folds are refitted to convergence: a fold's refit that stops at its evaluation limit is continued
from where it stopped. On this data (the relief rig with a leakage R->V, 21 points, three settings) the final
model's refit without setting 2 once needed more than 20 evaluations and, cut short there, predicted far worse
than the model can (a held-out error of over 10 against under 1): the fit then moved the leakage's start
(2e-11) to 1e-10, which blocks/calibrate/fit.py no longer does, and that refit now converges in a few
evaluations. The continuation is tested here with a budget of 8 evaluations per attempt, which that fold's
refit needs more than."""

from __future__ import annotations

from pathlib import Path

import yaml

from blocks.calibrate.heldout import heldout
from blocks.calibrate.run import calibrate

HERE = Path(__file__).parent
EXPERIMENTS = HERE.parents[1] / "netlists" / "experiments"


def test_a_fold_cut_short_is_continued_to_convergence(tmp_path):
    spec = yaml.safe_load((EXPERIMENTS / "relief_rig_steady.yaml").read_text())
    spec.update({"netlist": str(EXPERIMENTS / "circuits" / "relief_rig.yaml"),
                 "data": str(HERE / "data" / "relief_leakage.csv"), "trace": {"only": ["leakage"]}})
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    cal = calibrate(tmp_path / "exp.yaml", tmp_path / "out")
    assert [a[0] for a in cal.accepted] == ["leakage@R-V"]  # the planted effect
    final, spec_ho = cal.final, cal.exp.spec.heldout
    cut_short = heldout(final.model, final.fit, spec_ho, max_nfev=8, attempts=1)
    assert cut_short.unconverged == ["2"]  # premise: one attempt of 8 evaluations does not converge
    continued = heldout(final.model, final.fit, spec_ho, max_nfev=8)
    assert final.heldout.unconverged == [] and max(e for _, _, e in final.heldout.folds) < 2
    # steady points are predicted from their measured inputs: no knots, the score is the error itself
    assert final.heldout.knots == 0 and abs(final.heldout.score - final.heldout.error) <= 1e-12 * final.heldout.error
    generous = heldout(final.model, final.fit, spec_ho, max_nfev=500, attempts=1)
    assert generous.unconverged == [] and continued.unconverged == []
    assert abs(continued.error - generous.error) < 1e-6 * generous.error
    assert abs(final.heldout.error - generous.error) < 1e-3 * generous.error


def test_a_scheme_that_cannot_run_as_asked_says_so_on_stderr(tmp_path):
    """k = 30 folds over 21 points, and leave-one-group-out with no groups, ran as 21-fold and as k-fold; the
    report said so, the terminal did not."""
    from types import SimpleNamespace

    from blocks.calibrate.heldout import folds_of

    data = SimpleNamespace(kind="steady", n=21, groups={"all": list(range(21))}, sources=None)
    scheme, folds = folds_of(data, SimpleNamespace(scheme="kfold", k=30, seed=0))
    assert scheme == "21-fold over points (k = 30 cut to the 21 points)" and len(folds) == 21
    scheme, _ = folds_of(data, SimpleNamespace(scheme="leave_one_group_out", k=5, seed=0))
    assert scheme == "5-fold over points (no groups: leave_one_group_out fell back to kfold)"
    files = SimpleNamespace(kind="steady", n=6, groups={"all": list(range(6))}, sources=["a", "a", "b", "b", "c", "c"])
    scheme, folds = folds_of(files, SimpleNamespace(scheme="kfold_experiments", k=5, seed=0))
    assert scheme == "leave one experiment out (k = 5 cut to the 3 data files)" and len(folds) == 3
    assert folds_of(files, SimpleNamespace(scheme="kfold_experiments", k=3, seed=0))[0] == "leave one experiment out"
    said = []
    spec = yaml.safe_load((EXPERIMENTS / "relief_rig_steady.yaml").read_text())
    spec.update({"netlist": str(EXPERIMENTS / "circuits" / "relief_rig.yaml"),
                 "data": str(EXPERIMENTS / "data" / "relief_rig_steady.csv"), "heldout": {"scheme": "kfold", "k": 30},
                 "trace": {"rounds": 1, "only": ["leakage"]}})
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(spec, sort_keys=False))
    calibrate(tmp_path / "exp.yaml", tmp_path / "out", progress=said.append, rounds=1)
    assert said[1] == "held out: 21-fold over points (k = 30 cut to the 21 points)"  # after the first fit
