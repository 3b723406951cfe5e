"""A value given from outside a netlist (--set, a job's set:, an experiment's overrides) is checked against
the dimension the netlist gives its parameter, a bare number's included: the dimension its readers take it
in (ParameterTable.value_si). Found by a usability review: `--set "n_gear=39 rpm"` ran with n = 4.08 and
`--set "spool.zeta=0.9 bar"` with a damping ratio of 90000, both to exit 0."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

import cli
from blocks.circuit import Circuit
from blocks.errors import NetlistError
from blocks.units import UnitError

ROOT = Path(__file__).resolve().parents[2]
DRIVE = ROOT / "netlists" / "examples" / "drive_line.yaml"


@pytest.fixture(scope="module")
def table():
    return Circuit.from_file(DRIVE, compile=False).flat.parameters


def test_a_bare_number_takes_the_dimension_its_readers_give_it(table):
    # bridge.J = 0.085 + m_load*r_pinion**2/n_gear**2 is a moment of inertia only with n_gear a plain number
    assert table.value_si("n_gear", "39") == 39.0 and table.value_si("n_gear", 39) == 39.0
    assert table.value_si("n_gear", "3900 %") == pytest.approx(39.0)
    with pytest.raises(UnitError, match=r"wrong unit 'rpm': with n_gear in s\^-1\*rad, bridge\.J: wrong unit: "
                                        r"'0\.085 \+ m_load\*r_pinion\*\*2/n_gear\*\*2' is in .*, expected kg\*m\^2 "
                                        r"\(at .*drive_line\.yaml:\d+\)"):
        table.value_si("n_gear", "39 rpm")
    # a written unit fixes the dimension; a declared one too
    assert table.value_si("m_load", "15 t") == 15000.0
    with pytest.raises(UnitError, match=r"wrong unit 'bar': m_load is in kg"):
        table.value_si("m_load", "15 bar")
    with pytest.raises(UnitError, match=r"wrong unit 'bar'"):
        table.value_si("spool.zeta", "0.9 bar")  # a damping ratio is declared dimensionless
    with pytest.raises(UnitError, match=r"expected a number"):
        table.value_si("n_gear", True)
    # a bare number read only where any unit goes (a generic gain of the controller): converted, unchecked
    assert table.value_si("Kp", "4 1/mm") == pytest.approx(4000.0)


def test_a_refused_unit_leaves_the_tables_dimensions_as_they_were(table):
    before = (dict(table._dims), {name: e.dims for name, e in table.entries.items()})
    with pytest.raises(UnitError):
        table.value_si("n_gear", "39 rpm")
    assert (dict(table._dims), {name: e.dims for name, e in table.entries.items()}) == before


def test_an_expressions_dimension_and_an_arrays_places_count_too(tmp_path):
    """Found by a review of the first version: a parameter written as an expression ('m_base + 0 kg') and a
    bare number put in a profile's times (an array of durations) took any unit."""
    doc = yaml.safe_load(DRIVE.read_text())
    doc["parameters"].update(m_base="7500 kg", m_load="m_base + 0 kg", t_acc=0.5)
    doc["components"]["v_ref"]["params"]["times"] = [0, "t_acc", 2.5, 3.0]
    (tmp_path / "net.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    table = Circuit.from_file(tmp_path / "net.yaml", compile=False).flat.parameters
    with pytest.raises(UnitError, match=r"wrong unit 'm': m_load is in kg"):
        table.value_si("m_load", "3 m")
    with pytest.raises(UnitError, match=r"wrong unit 'bar': t_acc is in s"):
        table.value_si("t_acc", "0.5 bar")
    assert table.value_si("t_acc", "500 ms") == pytest.approx(0.5)
    with pytest.raises(UnitError, match=r"v_ref\.times is an array \(a table\)"):
        table.value_si("v_ref.times", "1 s")
    with pytest.raises(UnitError, match=r"'1e400' is not a finite number"):
        table.value_si("n_gear", "1e400")


def test_set_of_a_unit_the_netlist_contradicts_is_refused(capsys, tmp_path):
    code = cli.main(["run", str(DRIVE), "--set", "n_gear=39 rpm", "-o", str(tmp_path / "r.csv")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and err.startswith("vphs: --set 'n_gear=39 rpm': wrong unit 'rpm'")
    assert not (tmp_path / "r.csv").exists()


def test_a_netlist_that_writes_a_damping_ratio_in_bar_is_refused(tmp_path):
    doc = yaml.safe_load(DRIVE.read_text())
    doc["components"]["spool"]["params"]["zeta"] = "0.9 bar"
    (tmp_path / "net.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    with pytest.raises(NetlistError, match=r"net\.yaml:\d+:\d+: .*zeta.*wrong unit 'bar'"):
        Circuit.from_file(tmp_path / "net.yaml", compile=False)


def test_a_jobs_set_value_is_checked_the_same_way(tmp_path, capsys):
    job = yaml.safe_load((ROOT / "netlists" / "jobs" / "drive_line_controller.yaml").read_text())
    job.update(netlist=str(ROOT / "netlists" / "opt" / "drive_line.yaml"), output=str(tmp_path / "out"))
    job.setdefault("set", {})["n_gear"] = "39 rpm"
    (tmp_path / "job.yaml").write_text(yaml.safe_dump(job, sort_keys=False))
    code = cli.main(["optimise", str(tmp_path / "job.yaml")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert "job.yaml:" in err and "set.n_gear: wrong unit 'rpm': with n_gear in s^-1*rad, bridge.J" in err, err


def test_a_line_break_inside_a_value_stays_in_a_one_line_message(tmp_path):
    """Found by the netlist fuzz test: a quoted value with a blank line in it ('7500 k\\n\\ng' in YAML reads
    as '7500 k\\ng') was quoted into the message as it stands, and the message spanned two lines."""
    text = DRIVE.read_text().replace('m_load: "7500 kg"', 'm_load: "7500 k\n\ng"')
    assert text != DRIVE.read_text()
    (tmp_path / "net.yaml").write_text(text)
    with pytest.raises(NetlistError) as caught:
        Circuit.from_file(tmp_path / "net.yaml", compile=False)
    assert len(str(caught.value).splitlines()) == 1 and "7500 k\\ng" in str(caught.value), str(caught.value)
