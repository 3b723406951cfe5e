"""Deciding between refitted candidates (blocks.calibrate.selection): which places the report calls ambiguous
with the accepted one, on hand-made scores (the unit vectors are the de-correlated sensitivities s_perp of the
screening); a refit cut short at its evaluation limit."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from blocks.calibrate import selection
from blocks.calibrate.model import FAILED_RESIDUAL
from blocks.calibrate.screening import Score


def _score(key, direction):
    v = np.asarray(direction, dtype=float)
    return Score(SimpleNamespace(key=key), "screened", T=50.0, s_perp=v / np.linalg.norm(v))


def _refit(score, dbic, passes=True):
    return SimpleNamespace(score=score, dbic=dbic, passes_fit_tests=passes)


def test_a_place_parallel_to_an_ambiguous_alternative_is_ambiguous_too(monkeypatch):
    """best: a turbulent loss (e1); a refitted laminar loss at meter.a passes within 10 in BIC (e2); the same
    laminar loss at meter.b was not refitted but moves the channels like meter.a's (|cos| = 0.99955): it is
    in the set. A leakage along e3 and a place parallel only to a refit that failed its tests are not."""
    monkeypatch.setattr(selection, "separate", lambda a, b: [f"{a.score.place.key} vs {b.score.place.key}"])
    turb = _score("turbulent@meter.b", [1, 0, 0, 0])
    lam_a = _score("laminar@meter.a", [0, 1, 0, 0])
    lam_b = _score("laminar@meter.b", [0, 1, 0.03, 0])
    leak = _score("leakage@P1-V1", [0, 0, 1, 0])
    gain = _score("sensor_gain@p1", [0, 0, 0, 1])
    gain_twin = _score("sensor_gain@p3", [0, 0.02, 0, 1])
    best = _refit(turb, -60.0)
    refits = [best, _refit(lam_a, -55.0), _refit(gain, -58.0, passes=False)]
    ambiguous, separation = selection.ambiguity(best, refits, [turb, lam_a, lam_b, leak, gain, gain_twin])
    assert ambiguous == ["laminar@meter.a", "laminar@meter.b"]
    assert separation[0] == "turbulent@meter.b vs laminar@meter.a"
    assert separation[1].startswith("laminar@meter.b moves the measured channels like laminar@meter.a (|cos| = "
                                    "0.9996") and separation[1].endswith("which is ambiguous with turbulent@meter.b")


def test_an_alternative_over_10_in_bic_behind_brings_no_look_alikes(monkeypatch):
    monkeypatch.setattr(selection, "separate", lambda a, b: [])
    turb = _score("turbulent@meter.b", [1, 0, 0])
    lam_a = _score("laminar@meter.a", [0, 1, 0])
    lam_b = _score("laminar@meter.b", [0, 1, 0.03])
    twin = _score("turbulent@meter.a", [1, 0.014, 0])
    best = _refit(turb, -60.0)
    ambiguous, separation = selection.ambiguity(best, [best, _refit(lam_a, -49.0)], [turb, lam_a, lam_b, twin])
    assert ambiguous == ["turbulent@meter.a"]
    assert separation == ["turbulent@meter.b and turbulent@meter.a move the measured channels alike (|cos| = "
                          "0.9999 after removing what the free parameters absorb)"]


def test_a_refit_cut_short_is_continued_once_from_where_it_stopped(monkeypatch):
    """The first attempt stops at its evaluation limit: the second starts at its end, the evaluations add
    up, and the reported chi^2 drop is the second's. A refit that converges is not repeated."""
    from blocks.calibrate.fit import FitResult

    calls = []

    def fake_fit(model, x0, active, rows, max_nfev):
        calls.append(np.array(x0))
        done = len(calls) >= model.attempts
        x = np.array(x0) + 1.0
        return FitResult(x, active, rows, np.zeros(3), np.zeros((3, 2)), 10.0 - len(calls), 3, 2, np.eye(2),
                         np.array([0.1, 0.1]), max_nfev - 5 * done, "", 0, [], converged=done)

    monkeypatch.setattr(selection, "fit", fake_fit)
    place = SimpleNamespace(key="k", zero=0.0, plausible=(-10.0, 10.0))
    score = Score(place, "screened", phi=0.5)
    base = SimpleNamespace(rows=np.ones(3, dtype=bool), active=np.array([True, False]))
    for attempts, evaluations in ((2, 75), (1, 35)):
        calls.clear()
        model = SimpleNamespace(attempts=attempts, residuals=lambda x, points: np.full(3, 2.0),
                                bounds=lambda: (np.full(2, -10.0), np.full(2, 10.0)), data=SimpleNamespace(kind="time"))
        rf = selection.refit(model, np.zeros(2), 1, base, score)
        assert len(calls) == attempts and rf.fit.nfev == evaluations and rf.fit.converged
        assert np.array_equal(calls[0], [0.0, 0.5])
        if attempts == 2:
            assert np.array_equal(calls[1], [1.0, 1.5]) and rf.dchi2 == (10.0 - 2) - 12.0


def test_a_refitted_place_is_judged_by_its_refit_not_by_its_direction(monkeypatch):
    """A place parallel to the best (|cos| = 0.9999) that was refitted and ended 11 behind in BIC is not
    ambiguous: its refit is the better evidence. The same place not refitted would be."""
    monkeypatch.setattr(selection, "separate", lambda a, b: [])
    turb = _score("turbulent@meter.b", [1, 0, 0])
    twin = _score("turbulent@meter.a", [1, 0.014, 0])
    best = _refit(turb, -60.0)
    assert selection.ambiguity(best, [best, _refit(twin, -49.0)], [turb, twin]) == ([], [])
    assert selection.ambiguity(best, [best], [turb, twin])[0] == ["turbulent@meter.a"]


def test_the_report_says_which_shared_parameters_the_ambiguous_choice_moves():
    """Two alternatives fitted beside a declared stiffness and an effect accepted earlier: the stiffness moves
    by 2 SE (named, in bar), the earlier effect by half an SE (not named); each alternative's own parameter
    is fitted in one model only, and a parameter held fixed in the other is not compared."""
    from blocks.calibrate.experiment import Free

    def alternative(own, x, active):
        names = ["mcv.kp", "mcv.c_ff", own, "held"]
        layout = SimpleNamespace(globals=[Free(n, 0.0, -1.0, 1.0, 1.0, "bar" if n == "mcv.kp" else "1")
                                          for n in names])
        layout.index = {n: k for k, n in enumerate(names)}.__getitem__  # KeyError, as Layout.index
        fit = SimpleNamespace(x=np.array(x), se=np.array([2e5, 0.04, 1e4, 1.0]), active=np.array(active))
        return SimpleNamespace(model=SimpleNamespace(layout=layout), fit=fit,
                               score=SimpleNamespace(place=SimpleNamespace(key=own)))

    a = alternative("sensor_offset@p1", [895e5, 0.43, 9e4, 0.0], [True, True, True, True])
    b = alternative("sensor_offset@p3", [891e5, 0.45, -9e4, 7.0], [True, True, True, False])
    assert selection.choice_moves(a, b) == ("sensor_offset@p1 vs sensor_offset@p3: the choice moves mcv.kp = 895 "
                                            "against 891 bar (2 SE)")
    b.fit.x[1] = 0.53  # a dimensionless one: no unit shown
    assert selection.choice_moves(a, b).endswith("mcv.kp = 895 against 891 bar (2 SE); mcv.c_ff = 0.43 against "
                                                  "0.53 (2.5 SE)")
    b.fit.x[0], b.fit.x[1] = 895.5e5, 0.45
    assert selection.choice_moves(a, b) is None


class _TwoBasins:
    """chi^2 with two minima along the candidate's parameter phi (entry 1; zero 0) and a declared parameter a
    (entry 0) fixed by its own row: r = [100 (phi - 1)(phi - 0.45), 3 (phi - 0.45), a - 2]. The global minimum is
    phi = 0.45 (chi^2 0); a local one lies near phi = 1 (chi^2 about 2.7), behind a ridge at phi = 0.725
    (chi^2 about 57)."""

    n_rows = 3
    data = SimpleNamespace(kind="time")

    def __init__(self):
        self.failures = []

    def residuals(self, x, points=None):
        a, phi = x
        return np.array([100.0 * (phi - 1.0) * (phi - 0.45), 3.0 * (phi - 0.45), a - 2.0])

    def jacobian(self, x, cols, points, r0):
        a, phi = x
        J = np.array([[0.0, 100.0 * (2.0 * phi - 1.45)], [0.0, 3.0], [1.0, 0.0]])
        return J[:, cols]

    def bounds(self):
        return np.array([-10.0, 0.0]), np.array([10.0, 10.0])

    def steps(self):
        return np.array([1e-6, 1e-6])


def test_a_refit_in_a_local_minimum_is_found_lower_from_a_further_start():
    """Started at the linearised estimate 1.05 the refit ends in the local minimum near 1; from half its
    value (0.5) the further start crosses to the global one at 0.45: the refit reports that one, its chi^2
    drop, and both starts' chi^2, which differ (several minima)."""
    model = _TwoBasins()
    place = SimpleNamespace(key="gain@p1", zero=0.0, plausible=(0.0, 10.0))
    score = Score(place, "screened", phi=1.05)
    base = SimpleNamespace(rows=np.ones(3, dtype=bool), active=np.array([True, False]))
    first = selection.refit(model, np.array([2.0, 0.0]), 1, base, score)
    assert abs(first.phi - 1.0) < 0.01 and first.fit.chi2 > 2.5
    best = selection.restarted(first)
    assert abs(best.phi - 0.45) < 1e-4 and best.fit.chi2 < 1e-8
    base_chi2 = 100.0 ** 2 * 0.45 ** 2 + 9.0 * 0.45 ** 2  # phi at its zero, a at 2
    assert np.isclose(best.dchi2, -base_chi2, rtol=1e-6)
    assert [label for label, _ in best.starts] == ["its linearised estimate", "0.5 x its first value",
                                                   "1.5 x its first value"]
    assert selection.several_minima(best)


def test_only_refits_that_pass_and_lie_near_the_best_are_tried_from_more_starts(monkeypatch):
    """dBIC of the first refits: -100 (best that passes), -75 (25 behind: tried again), -65 (35 behind: not),
    -90 and -200 but under 3 SE (fail the fit tests: not tried, and the window is measured from -100, not from
    the failing -200). The one tried again is ranked by its better start."""
    first = {"a": -100.0, "b": -75.0, "c": -65.0, "d": -90.0, "e": -200.0}
    z = {"a": 20.0, "b": 20.0, "c": 20.0, "d": 2.0, "e": 1.0}
    tried = []

    def fake_refit(model, x0, column, base, score):
        key = score.place.key
        fitted = SimpleNamespace(run_failure=lambda beyond: "", n=100, p=3)  # degrees of freedom left
        return selection.Refit(score, None, fitted, z[key], 1.0, first[key] - 5.0, first[key], True)

    def fake_restarted(rf):
        tried.append(rf.score.place.key)
        rf.dbic -= 30.0
        return rf

    monkeypatch.setattr(selection, "refit", fake_refit)
    monkeypatch.setattr(selection, "restarted", fake_restarted)
    monkeypatch.setattr(selection, "_aligned", lambda base, base_model, model: base)
    monkeypatch.setattr(selection, "separate", lambda a, b: [])
    monkeypatch.setattr(selection, "choice_moves", lambda a, b: None)
    scores = [Score(SimpleNamespace(key=k, zero=0.0, plausible=(-1e9, 1e9)), "screened", T=50.0 - i)
              for i, k in enumerate("abcde")]
    decision = selection.decide(scores, 5, None, None, None, lambda s: (None, None, 0), with_heldout=False)
    assert sorted(tried) == ["a", "b"]
    assert [rf.score.place.key for rf in decision.refits] == ["e", "a", "b", "d", "c"]
    assert decision.accepted.score.place.key == "a"


class _ClosedLine:
    """A candidate that stops the model from running beyond phi = 2 (a turbulent loss so large that it closes
    a line and the solver's step falls below its minimum): every row then holds the failure value. Below it
    r = [10 (phi - 1.5), a - 2], whose minimum is phi = 1.5, a = 2 (chi^2 0)."""

    n_rows = 2
    data = SimpleNamespace(kind="time")

    def __init__(self):
        self.failures = []

    def residuals(self, x, points=None):
        a, phi = x
        if phi > 2.0:
            self.failures.append("the solver failed at t = 0.24 s: the step size fell below its minimum")
            return np.full(2, FAILED_RESIDUAL)
        return np.array([10.0 * (phi - 1.5), a - 2.0])

    def jacobian(self, x, cols, points, r0):
        J = np.zeros((2, 2)) if x[1] > 2.0 else np.array([[0.0, 10.0], [1.0, 0.0]])
        return J[:, cols]

    def bounds(self):
        return np.array([-10.0, 0.0]), np.array([10.0, 1e3])

    def steps(self):
        return np.array([1e-6, 1e-6])


def _closed_line_refit():
    place = SimpleNamespace(key="line_loss_turbulent@refill_B.b", zero=0.0, plausible=(0.0, 5.0), unit="-")
    base = SimpleNamespace(rows=np.ones(2, dtype=bool), active=np.array([True, False]))
    return selection.refit(_ClosedLine(), np.array([2.0, 0.0]), 1, base, Score(place, "screened", T=50.0, phi=30.0))


def test_a_refit_from_where_the_model_does_not_run_is_started_again_nearer_the_candidates_zero():
    """Linearised to 30, where the model does not run: the fit stays there (chi^2 2e6, worse than 225 with the
    candidate at its zero), and so does the one from 3; from 0.3 it ends at the minimum 1.5 with chi^2 0, its
    start labelled as moved."""
    rf = _closed_line_refit()
    assert abs(rf.phi - 1.5) < 1e-6 and rf.fit.chi2 < 1e-10 and rf.fit.failed_rows == 0
    assert np.isclose(rf.dchi2, -225.0)
    assert rf.starts[0][0] == ("its linearised estimate moved 100 times nearer its zero (from farther out the refit "
                               "ended worse than the candidate at its zero)")
    active, rows = np.array([True, True]), np.ones(2, dtype=bool)
    attempts = [selection._fit_continued(_ClosedLine(), np.array([2.0, phi]), active, rows) for phi in (30.0, 3.0, 0.3)]
    assert rf.fit.nfev == sum(f.nfev for f in attempts)  # the evaluations of every start tried


class _Saturating(_ClosedLine):
    """The model runs everywhere, but beyond phi = 5 its output no longer moves: r = [10 (min(phi, 5) - 1.5),
    a - 2]. From the linearised 30 the fit has no slope (chi^2 1225, worse than 225 at zero)."""

    def residuals(self, x, points=None):
        a, phi = x
        return np.array([10.0 * (min(phi, 5.0) - 1.5), a - 2.0])

    def jacobian(self, x, cols, points, r0):
        return np.array([[0.0, 0.0 if x[1] > 5.0 else 10.0], [1.0, 0.0]])[:, cols]


def test_a_refit_stuck_where_the_outputs_no_longer_move_is_started_again_nearer_the_candidates_zero(monkeypatch):
    place = SimpleNamespace(key="line_loss_turbulent@relief_A.a", zero=0.0, plausible=(0.0, 5.0), unit="-")
    base = SimpleNamespace(rows=np.ones(2, dtype=bool), active=np.array([True, False]))
    score = Score(place, "screened", T=50.0, phi=30.0)
    rf = selection.refit(_Saturating(), np.array([2.0, 0.0]), 1, base, score)
    assert abs(rf.phi - 1.5) < 1e-6 and rf.starts[0][0].startswith("its linearised estimate moved 10 times")
    monkeypatch.setattr(selection, "START_RETREATS", 0)
    stuck = selection.refit(_Saturating(), np.array([2.0, 0.0]), 1, base, score)
    assert stuck.phi == 30.0 and np.isclose(stuck.dchi2, 1225.0 - 225.0)


def test_a_refit_whose_runs_fail_at_its_end_says_so_before_its_other_reasons(monkeypatch):
    """Without the retreat the refit stays where it started (no slope where every row failed), with chi^2 =
    2 rows x FAILED_RESIDUAL^2; the decision names the failure first, not only a dBIC of 2e6."""
    monkeypatch.setattr(selection, "START_RETREATS", 0)
    rf = _closed_line_refit()
    assert rf.phi == 30.0 and rf.fit.chi2 == 2 * FAILED_RESIDUAL ** 2 and rf.fit.failed_rows == 2
    monkeypatch.setattr(selection, "refit", lambda model, x0, column, base, score: rf)
    monkeypatch.setattr(selection, "_aligned", lambda base, base_model, model: base)
    decision = selection.decide([rf.score], 1, None, None, None, lambda s: (None, None, 1), with_heldout=False)
    assert decision.refits[0].reasons[0] == ("the model does not run at the fit's end (2 of 2 rows failed; the last "
                                             "solver message in the fit: the solver failed at t = 0.24 s: the step "
                                             "size fell below its minimum)")
    assert decision.accepted is None and not rf.passes_fit_tests


class _OnePointAlwaysFails(_ClosedLine):
    """_ClosedLine with a third row whose run fails whatever phi is (a point the declared model cannot run)."""

    n_rows = 3

    def residuals(self, x, points=None):
        return np.append(super().residuals(x, points), FAILED_RESIDUAL)

    def jacobian(self, x, cols, points, r0):
        return np.vstack([super().jacobian(x, cols, points, r0), np.zeros(len(cols))])


def test_a_run_that_fails_with_the_candidate_at_zero_too_is_not_held_against_it():
    place = SimpleNamespace(key="gain@p1", zero=0.0, plausible=(0.0, 5.0), unit="-")
    base = SimpleNamespace(rows=np.ones(3, dtype=bool), active=np.array([True, False]))
    rf = selection.refit(_OnePointAlwaysFails(), np.array([2.0, 0.0]), 1, base, Score(place, "screened", phi=1.0))
    assert rf.fit.failed_rows == 1 and rf.base_failed_rows == 1 and rf.run_failure == ""
    assert abs(rf.phi - 1.5) < 1e-6 and np.isclose(rf.dchi2, -225.0)
    # nor in its standard error: 0.1 from the row 10 (phi - 1.5) alone, not inflated by the failed row's 1e6
    assert np.isclose(rf.se, 0.1) and rf.passes_fit_tests
