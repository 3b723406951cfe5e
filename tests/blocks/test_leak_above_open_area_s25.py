"""A closed valve's leakage area above its open area is refused when the values are set (a physics audit:
``mcv_vaa``'s and ``mcv_vbso``'s check valves, the library's check and relief valves took it, and a closed
valve then passed more than the open one, its flow no longer monotone in its opening)."""

from __future__ import annotations

from pathlib import Path

import pytest

import cli

ROOT = Path(__file__).resolve().parents[2]
COMPONENTS = ROOT / "netlists" / "components"


@pytest.mark.parametrize("netlist, sets, message", [
    ("mcv_vaa_flow.yaml", ["check.A_cv2=1 mm^2", "check.A_leak=5 mm^2"],
     "check: A_leak = 5e-06 m^2 must not exceed A_cv2 = 1e-06 m^2 (the closed check valve 2 would pass more "
     "than the open one)"),
    ("mcv_vaa_flow.yaml", ["relief.A_cv1=1 mm^2", "relief.A_leak=5 mm^2"],
     "relief: A_leak = 5e-06 m^2 must not exceed A_cv1 = 1e-06 m^2 (the closed check valve 1 would pass more "
     "than the open one)"),
    ("mcv_vbso_flow.yaml", ["check.A_cv=1 mm^2", "check.A_leak=5 mm^2"],
     "check: A_leak = 5e-06 m^2 must not exceed A_cv = 1e-06 m^2 (the closed check valve would pass more than "
     "the open one)"),
    ("power_unit.yaml", ["relief.A_leak=50 mm^2"],
     "relief: A_leak = 5e-05 m^2 must not exceed A_max = 2e-05 m^2 (the closed valve would pass more than the "
     "open one)"),
])
def test_a_leak_above_the_open_area_is_refused(tmp_path, capsys, netlist, sets, message):
    out = tmp_path / "run.csv"
    args = ["run", str(COMPONENTS / netlist), "-o", str(out)]
    for s in sets:
        args += ["--set", s]
    code = cli.main(args)
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert message in err, err
    assert not out.exists()


def test_a_check_valve_leak_equal_to_its_area_is_allowed():
    """The bound is A_leak <= A_max: equal is a valve that does not close (a plain orifice), not a wrong one."""
    from blocks.library.hydraulic.check_valve import CheckValve

    values = {p.name: p.default for p in CheckValve.params}
    values.update(A_max=1e-6, A_leak=1e-6)
    assert CheckValve.check_values(values) is None
    values.update(A_leak=1.01e-6)
    assert "must not exceed A_max" in CheckValve.check_values(values)
