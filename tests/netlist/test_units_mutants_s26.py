"""Unit factors (blocks/units.py) against their definitions, and the dimension of each: every unit of the
table, with its SI factor derived here from what the unit is (1 bar = 1e5 Pa, 1 psi = 1 lbf/in^2 with the
international pound and inch and standard gravity, 1 l/min = 1e-3 m^3 / 60 s, 1 rpm = 2 pi rad / 60 s).

Added from a mutation-testing pass (session 26): the existing conversions test a dozen units; a factor or a
dimension of the others changed silently. Tolerance rel 1e-12: the factors are products of a few exact
decimal constants and pi, equal to the last few ulps."""

from __future__ import annotations

import math

import pytest

from blocks.units import UnitError, convert, display_factor, from_si, parse_unit, si_value, to_si

REV = 2 * math.pi
LBF = 0.45359237 * 9.80665  # N: the international avoirdupois pound (exact kg) under standard gravity (exact)
INCH = 0.0254  # m, exact by definition

# (unit, SI factor from its definition, SI unit of its dimension)
DEFINITIONS = [
    ("m", 1.0, "m"), ("mm", 1e-3, "m"), ("cm", 1e-2, "m"), ("um", 1e-6, "m"), ("km", 1e3, "m"), ("in", INCH, "m"),
    ("l", 1e-3, "m^3"), ("L", 1e-3, "m^3"), ("ml", 1e-6, "m^3"), ("cc", 1e-6, "m^3"),
    ("kg", 1.0, "kg"), ("g", 1e-3, "kg"), ("t", 1e3, "kg"),
    ("s", 1.0, "s"), ("ms", 1e-3, "s"), ("us", 1e-6, "s"), ("min", 60.0, "s"), ("h", 3600.0, "s"),
    ("rad", 1.0, "rad"), ("deg", math.pi / 180, "rad"), ("rev", REV, "rad"), ("rpm", REV / 60, "rad/s"),
    ("Hz", REV, "rad/s"),
    ("N", 1.0, "kg*m/s^2"), ("kN", 1e3, "kg*m/s^2"), ("MN", 1e6, "kg*m/s^2"), ("Nm", 1.0, "kg*m^2/s^2"),
    ("Pa", 1.0, "kg/(m*s^2)"), ("kPa", 1e3, "kg/(m*s^2)"), ("MPa", 1e6, "kg/(m*s^2)"), ("GPa", 1e9, "kg/(m*s^2)"),
    ("bar", 1e5, "kg/(m*s^2)"), ("mbar", 1e2, "kg/(m*s^2)"), ("psi", LBF / INCH ** 2, "kg/(m*s^2)"),
    ("J", 1.0, "kg*m^2/s^2"), ("kJ", 1e3, "kg*m^2/s^2"), ("W", 1.0, "kg*m^2/s^3"), ("kW", 1e3, "kg*m^2/s^3"),
    ("cSt", 1e-6, "m^2/s"), ("St", 1e-4, "m^2/s"),
    ("K", 1.0, "K"), ("A", 1.0, "A"), ("mA", 1e-3, "A"), ("%", 0.01, "1"), ("1", 1.0, "1"),
]


@pytest.mark.parametrize("unit, factor, dims", DEFINITIONS, ids=[d[0] for d in DEFINITIONS])
def test_every_unit_has_the_factor_and_dimension_of_its_definition(unit, factor, dims):
    """Factor to SI from the unit's definition; dimension equal to the base-unit expression's."""
    u = parse_unit(unit)
    assert u.factor == pytest.approx(factor, rel=1e-12)
    base = parse_unit(dims)
    assert base.factor == 1.0  # the reference is SI-coherent
    assert u.same_dimension(base) and base.same_dimension(u)


@pytest.mark.parametrize("text, factor, dims", [
    ("l/min", 1e-3 / 60, "m^3/s"),
    ("cm^3/rev", 1e-6 / REV, "m^3/rad"),
    ("bar/(l/min)", 1e5 / (1e-3 / 60), "kg/(m^4*s)"),
    ("m^3/s/Pa", 1.0, "m^4*s/kg"),  # left-associative: (m^3/s)/Pa
    ("kN*mm", 1.0, "kg*m^2/s^2"),
    ("mm^-2", 1e6, "1/m^2"),
    ("N m", 1.0, "kg*m^2/s^2"),  # juxtaposition multiplies
    ("(mm)^3", 1e-9, "m^3"),
    ("km^0.5", math.sqrt(1e3), "m^0.5"),
    ("rpm^2", (REV / 60) ** 2, "rad^2/s^2"),
])
def test_compound_units_combine_factors_and_dimensions(text, factor, dims):
    """Products, quotients (left to right) and powers combine the factors as arithmetic does."""
    u = parse_unit(text)
    assert u.factor == pytest.approx(factor, rel=1e-12)
    assert u.same_dimension(parse_unit(dims))


def test_conversions_in_both_directions_use_the_factor():
    """to_si multiplies by the factor, from_si divides; display_factor is the factor, 1 for '', '1', 'SI'."""
    assert to_si(2.0, "bar") == pytest.approx(2e5, rel=1e-15)
    assert from_si(2e5, "bar") == pytest.approx(2.0, rel=1e-15)
    assert from_si(1e-3 / 60, "l/min") == pytest.approx(1.0, rel=1e-12)
    assert display_factor("bar") == 1e5 and display_factor("l/min") == pytest.approx(1e-3 / 60, rel=1e-12)
    assert display_factor("") == display_factor("1") == display_factor("SI") == 1.0
    assert convert(3.0, "mbar", "Pa") == pytest.approx(300.0, rel=1e-12)
    assert si_value("4 h") == pytest.approx(14400.0, rel=1e-15) and si_value(7) == 7.0
    assert si_value("250 mbar", parse_unit("Pa")) == pytest.approx(2.5e4, rel=1e-12)


@pytest.mark.parametrize("given, declared", [("1 bar", "m"), ("1 rpm", "1/s"), ("1 l/min", "m^3"),
                                             ("1 Nm", "N*m/rad"), ("1 cSt", "Pa*s")])
def test_a_unit_of_another_dimension_is_refused(given, declared):
    """A dimension mismatch is an error, never a silent conversion (rpm is rad/s, not 1/s)."""
    from blocks.units import quantity

    with pytest.raises(UnitError):
        quantity(given, declared)
    with pytest.raises(UnitError):
        si_value(given, parse_unit(declared))


def test_exponent_limits():
    """|exponent| up to 12 is read (m^12: 1e-36 for mm^12); beyond it the unit is refused as implausible."""
    assert parse_unit("mm^12").factor == pytest.approx(1e-36, rel=1e-12)
    assert parse_unit("mm^-12").factor == pytest.approx(1e36, rel=1e-12)
    for text in ("m^13", "m^-13", "m^12.5"):
        with pytest.raises(UnitError, match="implausible"):
            parse_unit(text)


def test_a_generic_si_parameter_takes_any_unit_by_its_factor():
    """A parameter declared 'SI' (a gain, a limit, a table) takes a quantity of any dimension, in SI: its
    number times the unit's factor (2 bar -> 2e5, 30 l/min -> 5e-4)."""
    assert convert(2.0, "bar", "SI") == pytest.approx(2e5, rel=1e-15)
    assert convert(30.0, "l/min", "SI") == pytest.approx(30e-3 / 60, rel=1e-12)


def test_a_decimal_comma_is_refused_but_a_comma_between_arguments_is_not():
    """'150,5 bar' is a decimal comma (an error that says 150.5); in 'max(1,2)' the comma separates arguments."""
    from blocks.units import decimal_comma

    assert "150.5" in decimal_comma("150,5 bar")
    assert decimal_comma("max(1,2)") is None and decimal_comma("max(1, 2) + 3") is None
    assert "1500" in decimal_comma("1,500 bar")  # three decimals: maybe a thousands separator, said
    assert "without a thousands separator" not in decimal_comma("1,50 bar")
