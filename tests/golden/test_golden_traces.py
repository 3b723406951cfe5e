"""Golden traces: the drive-line netlist against the independent hand-written model, a tolerance per signal.

The golden CSVs come from `bench/drive_line_reference.py` (the same equations written by hand, Radau rtol
1e-10; see make_drive_line_golden.py), so a wrong sign, unit or summation anywhere on the netlist ->
compiler -> solver path shows up here. Tolerances are set from the solver's rtol 1e-6: the measured errors
are about 20x below them (bench/drive_line.py prints them).
"""

import csv
from pathlib import Path

import numpy as np
import pytest

from blocks.circuit import Circuit

HERE = Path(__file__).parent
NETLIST = HERE.parent.parent / "netlists" / "examples" / "drive_line.yaml"
TOLERANCE = {"x": 0.005, "pA": 0.02, "pB": 0.02, "speed": 0.01}  # mm, bar, bar, rad/s
UNITS = {"x": "mm", "pA": "bar", "pB": "bar", "speed": "rad/s"}


def read_golden(path: Path) -> dict[str, np.ndarray]:
    with open(path) as handle:
        rows = [r for r in csv.reader(line for line in handle if not line.startswith("#"))]
    header = [h.split("[")[0].strip() for h in rows[0]]
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(header)}


@pytest.fixture(scope="module")
def circuit():
    return Circuit.from_file(NETLIST)


@pytest.mark.parametrize("volume, tag", [(1e-3, "1l"), (2e-5, "0.02l")])
def test_drive_line_matches_golden(circuit, volume, tag):
    golden = read_golden(HERE / f"drive_line_{tag}.csv")
    result = circuit.simulate({"V_line": volume})
    index = np.searchsorted(result.t, golden["t"] - 1e-9)
    assert np.allclose(result.t[index], golden["t"], atol=1e-9)
    for name, tol in TOLERANCE.items():
        simulated = result.in_unit(name, UNITS[name])[index]
        error = np.max(np.abs(simulated - golden[name]))
        assert error < tol, f"{name}: max error {error:.3g} {UNITS[name]} exceeds {tol} (V = {volume} m^3)"


def test_golden_comparison_detects_a_small_model_change(circuit):
    """The tolerances are tight enough to see a 1 % change in the motor displacement."""
    golden = read_golden(HERE / "drive_line_1l.csv")
    d_nominal = circuit.vectors().values["motors.D"]
    result = circuit.simulate({"V_line": 1e-3, "motors.D": 1.01 * d_nominal})
    index = np.searchsorted(result.t, golden["t"] - 1e-9)
    errors = {name: np.max(np.abs(result.in_unit(name, UNITS[name])[index] - golden[name])) for name in TOLERANCE}
    assert any(errors[name] > TOLERANCE[name] for name in TOLERANCE), errors
