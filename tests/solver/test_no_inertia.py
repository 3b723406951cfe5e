"""A rigid body with nothing to accelerate (every inertia and mass on it 0) fails at its first step; the
message says so (blocks.circuit.Circuit._no_inertia). Found by a physics review: it said only that the
speed became NaN."""

from __future__ import annotations

import pytest
import yaml

from blocks.circuit import Circuit
from blocks.errors import SimulationError

DRIVEN = {"components": {"src": {"type": "pressure_source", "params": {"p": "100 bar"}}, "tank": {"type": "tank"},
                         "motor": {"type": "hydraulic_motor", "params": {"D": "10 cm^3/rev", "J_m": 0}},
                         "gear": {"type": "gear", "params": {"n": 5}},
                         "load": {"type": "inertia", "params": {"J": 0}}},
          "nets": {"P": ["src.port", "motor.a"], "T": ["tank.port", "motor.b"],
                   "fast": ["motor.shaft", "gear.a"], "slow": ["gear.b", "load.port"]},
          "simulation": {"t_end": "0.1 s"}}


def _circuit(tmp_path, doc) -> Circuit:
    (tmp_path / "net.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return Circuit.from_file(tmp_path / "net.yaml")


def test_a_body_with_no_inertia_across_a_gear_is_named_with_its_zero_parameters(tmp_path):
    with pytest.raises(SimulationError, match=r"nothing on it has inertia \((motor\.J_m = 0, load\.J = 0|load\.J = 0, "
                                              r"motor\.J_m = 0)\): a rigid body needs a mass or an inertia"):
        _circuit(tmp_path, DRIVEN).simulate()


def test_one_inertia_anywhere_on_the_body_runs_and_is_not_blamed(tmp_path):
    result = _circuit(tmp_path, DRIVEN).simulate({"load.J": 0.1})
    assert result.t[-1] == pytest.approx(0.1)


def test_validate_and_run_refuse_it_before_any_run(tmp_path, capsys):
    """Found by the session-20 fuzzer: `vphs validate` said ok, and only the run failed (exit 1). A zero
    mass is bad input: exit 2, at the parameter, from validate, run and diff alike (session 27: diff ran
    the netlist and failed at its first step, exit 1; the simulation call
    itself still says it as above, for an optimiser's or a calibration's parameter vector)."""
    import cli

    (tmp_path / "net.yaml").write_text(yaml.safe_dump(DRIVEN, sort_keys=False))
    (tmp_path / "ref.csv").write_text("t [s],slow [rpm]\n0,0\n0.1,1\n")
    for command in (["validate"], ["run", "-q", "-o", str(tmp_path / "r.csv")],
                    ["diff", str(tmp_path / "ref.csv"), "-q", "-o", str(tmp_path / "d.csv")]):
        assert cli.main([command[0], str(tmp_path / "net.yaml"), *command[1:]]) == 2
        err = capsys.readouterr().err
        assert "nothing on the rigid body" in err and "has inertia, and it needs a mass or an inertia" in err
        assert ("motor.J_m = 0, load.J = 0" in err or "load.J = 0, motor.J_m = 0" in err) and err.count("\n") == 1
    assert not (tmp_path / "r.csv").exists() and not (tmp_path / "d.csv").exists()
