"""The bounds the netlist reference shows agree with the check, for every parameter of every registered block
(session 22's user review: ``variable_pump.tau_c`` was shown as [0, 10] while ``--set pump.tau_c=0`` said
"must be positive"; so were ``pipe.l`` and ``pipe.d``).

Each parameter's row of the generated table (:func:`blocks.docs.block_reference`) is read back: ``[a`` must
accept a and refuse the next number below it, ``(a`` refuse a and accept the next above it, ``-inf`` accept
any very negative value; the same for the upper side. The bound written must be the declared one (to the six
digits the table shows)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from blocks import registry
from blocks.block import Param
from blocks.docs import block_reference

PARAMS = [(name, p) for name, cls in registry.all_types().items() for p in cls.params]
INTERVAL = re.compile(r"(?P<open>[\[(])(?P<lower>\S+), (?P<upper>\S+)(?P<close>[\])])")


def documented(type_name: str, param: Param) -> re.Match:
    """The bounds cell of ``param``'s row in its block's generated table, parsed as an interval."""
    table = block_reference(registry.all_types()[type_name])
    for row in table.splitlines():
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", row)]
        if len(cells) == 7 and re.fullmatch(rf"`{param.name}`( \((array|integer)\))?", cells[1]):
            match = INTERVAL.fullmatch(cells[4])
            assert match, f"{type_name}.{param.name}: bounds cell {cells[4]!r} is no interval"
            return match
    raise AssertionError(f"{type_name}.{param.name}: no row in the parameter table")


def accepts(param: Param, value: float) -> bool:
    return param.check((value,) if param.array else value) is None


def check_side(param: Param, written: str, bound: float | None, closed: bool, outward: float, where: str) -> None:
    """One side of the interval: as written (``closed``: '[' or ']'), the declared ``bound`` is accepted or
    refused, and the next number beyond it (towards ``outward``) is refused, or the one inside accepted."""
    if bound is None:
        assert written.lstrip("-") == "inf" and not closed, f"{where}: no bound, written {written!r}"
        assert accepts(param, outward * 1e300), f"{where}: written without bound, but {outward * 1e300:g} is refused"
        return
    assert float(written) == pytest.approx(bound, rel=1e-5, abs=0), f"{where}: written {written}, declared {bound}"
    assert accepts(param, bound) == closed, \
        f"{where}: {bound:g} is {'refused' if closed else 'accepted'} ({param.check(bound)}) but written " \
        f"{'closed' if closed else 'open'}"
    beyond = np.nextafter(bound, outward * np.inf) if closed else np.nextafter(bound, -outward * np.inf)
    assert accepts(param, float(beyond)) != closed, f"{where}: the bound is not where it is written"


@pytest.mark.parametrize("type_name, param", PARAMS, ids=[f"{t}.{p.name}" for t, p in PARAMS])
def test_the_documented_bounds_are_the_checked_ones(type_name, param):
    interval = documented(type_name, param)
    where = f"{type_name}.{param.name}"
    check_side(param, interval["lower"], param.lower, interval["open"] == "[", -1.0, where + " (lower)")
    check_side(param, interval["upper"], param.upper, interval["close"] == "]", 1.0, where + " (upper)")


@pytest.mark.parametrize("type_name, param", [(t, p) for t, p in PARAMS if p.positive],
                         ids=[f"{t}.{p.name}" for t, p in PARAMS if p.positive])
def test_an_open_lower_bound_is_said_as_it_is(type_name, param):
    """'must be positive' only where the excluded bound is 0 (line_loss.L's is 1e-9: 5e-10 is positive)."""
    problem = param.check((param.lower,) if param.array else param.lower)
    assert ("must be positive" in problem) == (param.lower == 0), problem
    assert param.lower == 0 or f"must lie above {param.lower:g}" in problem, problem
