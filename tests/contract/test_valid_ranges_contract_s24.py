"""Contract of the valid ranges (blocks/valid_ranges.py), walking the registry: a block that declares
checked signals gives, at its default point (or where a parameter turns its ranges on), a range for each of
those signals and for no other, lower <= upper, with a description of what it does outside; a declaration naming no port, or checked signals without
valid_ranges(), is refused at registration."""

from __future__ import annotations

import math

import pytest

from blocks.block import Block, ValidRange, check_declarations, signal_in, signal_out
from blocks import registry
from test_registry_contract import default_params

REGISTRY = registry.all_types()
CHECKING = sorted(name for name, cls in REGISTRY.items() if cls.checked)
# Blocks whose ranges apply only with a parameter set otherwise than by default, and the setting
WITH_RANGES = {"mcv_vaa": {"flow_force": 1.0}}  # the flow-force fit's range, with the flow force on


def test_some_blocks_check_their_signals():
    assert {"lookup_1d", "lookup_2d", "range_check", "lga_jib_load"} <= set(CHECKING)


@pytest.mark.parametrize("name", CHECKING)
def test_valid_ranges_at_the_default_point(name):
    cls = REGISTRY[name]
    ranges = cls.valid_ranges(default_params(cls) | WITH_RANGES.get(name, {}))
    assert ranges, f"{name}: declares {cls.checked} checked but gives no range at its defaults"
    assert {r.signal for r in ranges} == set(cls.checked), f"{name}: a checked signal without a range"
    for r in ranges:
        assert isinstance(r, ValidRange)
        assert r.signal in cls.checked, f"{name}: a range for '{r.signal}', which is not declared checked"
        assert not math.isnan(r.lower) and not math.isnan(r.upper) and r.lower <= r.upper, r
        assert len(r.outside) > 10, f"{name}: say what the block does outside the range"


def _throwaway(checked, with_ranges):
    class Checked(Block):
        """Throwaway block for the checked declarations: y = u.

        y = u
        """

        ports = (signal_in("u", "input"), signal_out("y", "output"))

        @staticmethod
        def outputs(u):
            return (u,)

    Checked.checked = checked
    if with_ranges:
        Checked.valid_ranges = classmethod(lambda cls, values: (ValidRange("u", 0.0, 1.0, "nothing happens"),))
    return Checked


@pytest.mark.parametrize("ref", ["w", "u.flow", "y.force"])
def test_a_checked_signal_must_name_a_port_or_a_physical_ports_through_value(ref):
    with pytest.raises(TypeError, match=f"checked signal '{ref}' is neither a port"):
        check_declarations(_throwaway((ref,), True))


def test_checked_signals_need_valid_ranges():
    with pytest.raises(TypeError, match="no valid_ranges"):
        check_declarations(_throwaway(("u",), False))
    check_declarations(_throwaway(("u",), True))


@pytest.mark.parametrize("name", sorted(REGISTRY))
def test_parameter_warnings_are_lines_and_none_at_the_defaults(name):
    """Block.parameter_warnings: a tuple of one-line texts; a block's defaults are inside what it was made for."""
    cls = REGISTRY[name]
    said = cls.parameter_warnings(default_params(cls))
    assert isinstance(said, tuple) and said == (), (name, said)
