"""The verdict's reading of effects (blocks/calibrate/verdict.py) and the column space of a Jacobian
(blocks/calibrate/fit.py column_space), against their definitions: an effect is "found" when |value| > 3 SE
whatever its sign; the final effects list the exchanged-in place where one was swapped; the column space
drops zero columns and directions below rel times the largest singular value of the unit-norm columns.

Added from a mutation-testing pass (session 26): each test failed on a mutant the existing tests let
through."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from blocks.calibrate.fit import column_space
from blocks.calibrate.verdict import final_effects, verdict


def test_a_negative_effect_over_3_se_from_zero_is_found():
    """|value| > 3 SE: -5e-3 +- 1e-3 (5 SE below zero) and 3.2e-3 +- 1e-3 are found, -2e-3 +- 1e-3 (2 SE)
    is superseded."""
    cal = SimpleNamespace(rounds=[], final=None, exchanges=[], removals=[], exp=None, accepted=[
        ("gain@p1", "sensor gain", "channel p1", "gain:p1", -5e-3, 1e-3, "1"),
        ("gain@p2", "sensor gain", "channel p2", "gain:p2", -2e-3, 1e-3, "1"),
        ("gain@p3", "sensor gain", "channel p3", "gain:p3", 3.2e-3, 1e-3, "1")])
    lines, _ = verdict(cal)
    assert lines[0].startswith("found: sensor gain channel p1: gain:p1 = ")
    assert lines[1].startswith("superseded: sensor gain channel p2: gain:p2 = ")
    assert lines[2].startswith("found: sensor gain channel p3: gain:p3 = ")


def _round(index, key):
    place = SimpleNamespace(key=key)
    return SimpleNamespace(index=index, decision=SimpleNamespace(accepted=SimpleNamespace(score=SimpleNamespace(
        place=place))))


def test_final_effects_in_round_order_with_the_exchanged_in_place():
    """No exchange made: the accepted places in round order. One made: the alternative's place stands where
    the effect it replaced stood; an exchange not made changes nothing."""
    rounds = [_round(1, "gain@p1"), SimpleNamespace(index=2, decision=SimpleNamespace(accepted=None)),
              _round(3, "leak@A-B")]
    cal = SimpleNamespace(rounds=rounds, exchanges=[])
    assert [(p.key, k) for p, k in final_effects(cal)] == [("gain@p1", 1), ("leak@A-B", 3)]
    flow_force = SimpleNamespace(key="flow_force@spool")
    cal.exchanges = [SimpleNamespace(made=False, out_key="leak@A-B", place=SimpleNamespace(key="other")),
                     SimpleNamespace(made=True, out_key="gain@p1", place=flow_force)]
    assert [(p.key, k) for p, k in final_effects(cal)] == [("flow_force@spool", 1), ("leak@A-B", 3)]


def test_column_space_of_columns_1e15_apart_with_a_zero_column():
    """Columns of scales 1e-9 and 1e6 and a zero column: the zero column is dropped (keep), the others are
    scaled to unit norm and both kept (rank 2), U is an orthonormal basis of their span."""
    rng = np.random.default_rng(14)
    base = rng.normal(size=(20, 2))
    J = np.column_stack([1e-9 * base[:, 0], np.zeros(20), 1e6 * base[:, 1]])
    keep, Js, U, s, Vt = column_space(J)
    assert keep.tolist() == [True, False, True]
    assert np.allclose(np.linalg.norm(Js, axis=0), 1.0, rtol=1e-12)
    assert U.shape == (20, 2) and np.allclose(U.T @ U, np.eye(2), atol=1e-12)
    proj = U @ (U.T @ base)  # the span of the kept columns is the span of base
    assert np.allclose(proj, base, rtol=0, atol=1e-10 * np.abs(base).max())


def test_column_space_cuts_directions_below_rel_of_the_largest_singular_value():
    """Unit columns a, a + 1e-3 b, a + 1e-3 b + 5e-11 c: the third singular value (about 3e-11) is below
    1e-9 of the largest but above 1e-9 of the second: rank 2."""
    rng = np.random.default_rng(15)
    a, b, c = np.linalg.qr(rng.normal(size=(25, 3)))[0].T
    cols = [a, a + 1e-3 * b, a + 1e-3 * b + 5e-11 * c]
    J = np.column_stack([v / np.linalg.norm(v) for v in cols])
    sv = np.linalg.svd(J, compute_uv=False)
    assert sv[2] < 1e-9 * sv[0] and sv[2] > 1e-9 * sv[1]
    assert column_space(J)[2].shape[1] == 2
