"""``ParameterTable.dimension``: the dimension a netlist gives a name (what a measured column imposed as it
must have, :mod:`blocks.calibrate.experiment`). Expected dimensions are those of the units written here."""

from __future__ import annotations

from pathlib import Path

import pytest

from blocks.circuit import Circuit
from blocks.units import parse_unit

CIRCUITS = Path(__file__).resolve().parents[2] / "netlists" / "experiments" / "circuits"
RIG = (CIRCUITS / "relief_rig.yaml").read_text()


def table(tmp_path: Path, text: str = RIG, **replace: str):
    for old, new in replace.items():
        old = old.replace("__", " ")
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "net.yaml"
    path.write_text(text)
    return Circuit.from_file(path, compile=False).flat.parameters


def same(dims, unit: str) -> bool:
    return dims is not None and dims.same_dimension(parse_unit(unit))


def test_declared_written_and_computed_units(tmp_path):
    t = table(tmp_path, **{'Q_in: "40 l/min"': 'Q_nom: "20 l/min"\n  Q_in: "2*Q_nom"'})
    assert same(t.dimension("pump.q"), "m^3/s")  # declared by the flow source
    assert same(t.dimension("Q_nom"), "l/min") and same(t.dimension("Q_in"), "l/min")  # written, computed
    assert same(t.dimension("R_meter"), "Pa*s/m^3")


@pytest.mark.parametrize("edit", [
    {'Q_in: "40 l/min"': "Q_in: 6.7e-4"},  # put as q, as it stands
    {'Q_in: "40 l/min"': "Q_in: 6.7e-4", "q: Q_in": "q: -Q_in"},  # negated
    {'Q_in: "40 l/min"': "Q_in: 6.7e-4\n  Q_a: Q_in", "q: Q_in": "q: Q_a"},  # under another name
])
def test_a_bare_number_takes_the_declared_unit_of_its_place(tmp_path, edit):
    assert same(table(tmp_path, **edit).dimension("Q_in"), "m^3/s")


def test_a_bare_number_read_inside_an_expression_is_not_known(tmp_path):
    t = table(tmp_path, **{'Q_in: "40 l/min"': "Q_in: 6.7e-4", "q: Q_in": 'q: "1.0*Q_in"'})
    assert t.dimension("Q_in") is None
    drive = table(tmp_path, (CIRCUITS / "drive_line_open.yaml").read_text())
    assert drive.dimension("n_gear") is None  # J: "0.085 + m_load*r_pinion**2/n_gear**2": it adapts


def test_a_bare_number_in_places_of_two_dimensions_is_not_known(tmp_path):
    t = table(tmp_path, **{'Q_in: "40 l/min"': "Q_in: 6.7e-4", 'A_max: "60 mm^2"': "A_max: Q_in"})
    assert t.dimension("Q_in") is None


def test_a_bare_number_only_where_any_unit_goes_is_not_known(tmp_path):
    """A generic place takes SI of any unit: the number may be a flow there (a constant block driving a
    flow source's signal) as well as a plain number (a command level). Calling it dimensionless refused
    a Q [l/min] column imposed as it (found in review)."""
    drive = table(tmp_path, (CIRCUITS / "drive_line_open.yaml").read_text())
    assert drive.dimension("u1") is None  # a profile's values (SI of any unit), written without unit
    assert same(drive.dimension("m_load"), "kg")
    t = table(tmp_path, **{'Q_in: "40 l/min"': "Q_in: 6.7e-4\n  Q_note: Q_in"})  # an alias put nowhere
    assert same(t.dimension("Q_in"), "m^3/s")  # the flow source's q still says what it is
