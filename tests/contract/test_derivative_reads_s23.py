"""The Jacobian's sparsity pattern reads each block's ``derivatives`` per returned value
(blocks/compiler/output_reads.py): a valve's flows read its pressures and spool, its spool's rate its command.
A read the analysis misses would leave a true entry out of the Jacobian (the finite differences would then
be taken with columns grouped that must not be), so every registered block is checked here: each argument
of ``derivatives`` is moved at many points, and every returned value that changes must be one the analysis
says reads it. The analysis itself is checked on small functions whose reads are known.
"""

from __future__ import annotations

import inspect
import warnings

import numpy as np
import pytest

from blocks import registry
from blocks.compiler.output_reads import derivative_reads
from test_registry_contract import operating_points

TYPES = registry.all_types()
ANALYSED = [name for name, cls in TYPES.items() if cls.derivatives is not None
            and derivative_reads(cls.derivatives, len(cls.derivative_names())) is not None]


def _points(cls, rng, n: int) -> list[dict]:
    """The registry contract's two operating points, and ``n`` with every scalar argument drawn at random
    (parameters inside their bounds; ports, states and time over many decades, both signs)."""
    params = {p.name: p for p in cls.params}
    base = operating_points(cls)
    points = list(base)
    for _ in range(n):
        point = dict(base[0])
        for name, value in base[0].items():
            if isinstance(value, np.ndarray):
                point[name] = value * (1.0 + 0.1 * rng.random()) + 0.01 * rng.random()
                continue
            p = params.get(name)
            if p is not None:
                lo = -1e6 if p.lower is None else p.lower
                hi = 1e6 if p.upper is None else p.upper
                point[name] = float(np.clip(value * (0.5 + rng.random()) if value else 0.1 * min(hi, 1.0), lo, hi))
                if p.integer:
                    point[name] = float(round(point[name]))
            else:
                point[name] = float(rng.choice([-1.0, 1.0]) * 10 ** rng.uniform(-3, 7.5) * rng.random())
        points.append(point)
    return points


def _values(fn, point: dict):
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        out = fn(*[point[a].copy() if isinstance(point[a], np.ndarray) else point[a]
                   for a in inspect.signature(fn).parameters])
    return [np.asarray(v, dtype=float) for v in (out if isinstance(out, tuple) else (out,))]


@pytest.mark.parametrize("name", ANALYSED)
def test_every_read_a_returned_value_makes_is_one_the_analysis_found(name):
    cls = TYPES[name]
    names = cls.derivative_names()
    reads = derivative_reads(cls.derivatives, len(names))
    rng = np.random.default_rng(sum(map(ord, name)))  # fixed per block
    found = [set() for _ in names]
    evaluated = 0
    for point in _points(cls, rng, 60):
        try:
            before = _values(cls.derivatives, point)
        except (ZeroDivisionError, ValueError, OverflowError):
            continue
        evaluated += 1
        for arg, value in point.items():
            if arg not in inspect.signature(cls.derivatives).parameters:
                continue
            moved = dict(point)
            moved[arg] = value * 1.3 + 0.01 if isinstance(value, np.ndarray) else \
                value * (1.0 + 0.3 * rng.standard_normal()) + 0.1 * rng.standard_normal() * (abs(value) + 1e-3)
            try:
                after = _values(cls.derivatives, moved)
            except (ZeroDivisionError, ValueError, OverflowError):
                continue
            for k in range(len(names)):
                if not np.array_equal(before[k], after[k], equal_nan=True):
                    found[k].add(arg)
    assert evaluated >= 10, f"{name}: too few points where derivatives could be evaluated"
    missed = {names[k]: sorted(found[k] - reads[k]) for k in range(len(names)) if found[k] - reads[k]}
    assert not missed, f"{name}: a returned value changes with arguments the analysis says it does not read: {missed}"


def test_most_blocks_are_analysed():
    # a block the analysis cannot read is taken whole (correct, only slower); this guards the analysis
    # from quietly declining everything
    with_derivatives = [n for n, cls in TYPES.items() if cls.derivatives is not None]
    assert len(ANALYSED) >= 0.8 * len(with_derivatives), sorted(set(with_derivatives) - set(ANALYSED))


# ---- the analysis on functions whose reads are known ------------------------------------------------------
def _branch(a, b, c):
    x = a * 2.0
    if b > 0.0:
        x = x + c
    return x, b


def _early_return(a, b, c):
    if a > 0.0:
        return 0.0, 1.0
    return b, c


def _loop(a, b, n):
    total = 0.0
    carried = 0.0
    for k in range(int(n)):
        total = total + carried
        carried = a
    return total, b


def _helper(values, k):
    values[0] = k
    return 0.0


def _written_by_a_call(a, b):
    buffer = np.zeros(1)
    _ = _helper(buffer, a)
    return buffer[0], b


def _unknown(a, b):
    try:
        x = a
    except ValueError:
        x = b
    return x, b


def _bare_call(a, b):
    buffer = np.zeros(1)
    _helper(buffer, a)  # a statement the analysis does not read
    return buffer[0], b


@pytest.mark.parametrize("fn, reads", [
    (_branch, [{"a", "b", "c"}, {"b"}]),
    (_early_return, [{"a", "b"}, {"a", "c"}]),  # whether the first return ran decides both
    (_loop, [{"a", "n"}, {"b"}]),  # a value carried to the next pass
    (_written_by_a_call, [{"a"}, {"b"}]),  # a call may write into an array it is given
])
def test_the_analysis_on_known_functions(fn, reads):
    assert [set(r) for r in derivative_reads(fn, 2)] == reads


def test_what_the_analysis_does_not_know_is_none_so_the_block_is_taken_whole():
    assert derivative_reads(_unknown, 2) is None
    assert derivative_reads(_bare_call, 2) is None
