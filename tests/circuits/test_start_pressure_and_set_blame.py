"""Two checks of a run's values before it starts (blocks/circuit.py, cli.py).

- Under the cavitation law no net starts below the fluid's vapour pressure: a net at -5 bar ran to exit 0 as
  40 l of vapour in a 0.5 l net, with -5 bar read to the end while a pump filled it. Without the law (the
  thesis's liquid law) such a start is a pressure, refused by nothing.
- A block's check of its values together (p_open above p_set) that fails only with a --set value names
  that --set; it pointed at the netlist's line, which is right as written.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from blocks.circuit import Circuit
from blocks.errors import NetlistError

ROOT = Path(__file__).resolve().parents[2]
POWER_UNIT = ROOT / "netlists" / "components" / "power_unit.yaml"
MCV = ROOT / "netlists" / "components" / "mcv_demo_with.yaml"


def _vphs(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "cli", *args], cwd=ROOT, capture_output=True, text=True)


def test_a_net_starting_below_the_vapour_pressure_is_refused_where_it_is_written(tmp_path):
    text = POWER_UNIT.read_text()
    assert 'P:      {ports: [q_pump.b, relief.a, valve.P], volume: V_P, initial: "0 bar"}' in text
    bad = tmp_path / "below.yaml"
    bad.write_text(text.replace('volume: V_P, initial: "0 bar"', 'volume: V_P, initial: "-5 bar"'))
    with pytest.raises(NetlistError) as caught:
        Circuit.from_file(bad, compile=False).vectors()
    line = 1 + text.splitlines().index('  P:      {ports: [q_pump.b, relief.a, valve.P], volume: V_P, initial: "0 bar"}')
    assert caught.value.line == line
    assert ("net 'P' starts at -5 bar, below the fluid's vapour pressure -0.9 bar (gauge): under the cavitation "
            "law that is a vapour cavity of ") in str(caught.value)


def test_a_start_at_the_vapour_pressure_itself_is_accepted():
    circuit = Circuit.from_file(POWER_UNIT, compile=False)
    p_vap = circuit.vectors().values["fluid.vapour_pressure"]
    assert p_vap == -0.9e5
    assert circuit.vectors({"P.initial": p_vap}).x0.min() == p_vap


def test_without_the_cavitation_law_or_in_a_blocks_own_node_a_start_below_it_is_a_pressure(tmp_path):
    # the liquid law holds there at any pressure (a run that goes below the vapour pressure is warned of)
    assert Circuit.from_file(MCV, compile=False).vectors({"mcv.initial.pt": -2e5}).x0.min() == -2e5
    liquid = tmp_path / "liquid.yaml"
    liquid.write_text(POWER_UNIT.read_text().replace("fluid: {", "fluid: {cavitation: false, ", 1))
    assert "cavitation: false" in liquid.read_text()
    assert Circuit.from_file(liquid, compile=False).vectors({"P.initial": -5e5}).x0.min() == -5e5


@pytest.mark.parametrize("sets, blamed", [
    (["relief.p_set=200 bar"], "--set 'relief.p_set=200 bar'"),
    (["V_line=2 l", "relief.p_set=200 bar"], "--set 'relief.p_set=200 bar'"),  # the one that fails alone
    (["relief.p_set=185 bar", "relief.p_open=183 bar"], "--set 'relief.p_set=185 bar', --set 'relief.p_open=183 bar'"),
    # an innocent --set beside two that fail only together; one that fails for another reason of its own
    (["relief.p_set=185 bar", "relief.p_open=183 bar", "V_line=2 l"],
     "--set 'relief.p_set=185 bar', --set 'relief.p_open=183 bar'"),
    (["relief.p_set=200 bar", "cyl.initial.x=5 m"], "--set 'relief.p_set=200 bar'"),
])
def test_a_values_check_failing_only_with_set_names_the_set(sets, blamed):
    done = _vphs("run", str(POWER_UNIT), *[a for s in sets for a in ("--set", s)], "-q")
    assert done.returncode == 2
    assert done.stderr.startswith(f"vphs: {blamed}: relief: p_open = ")
    assert f"(checked at {POWER_UNIT}:28:34, right as written there)" in done.stderr
    assert done.stderr.count("\n") == 1


def test_a_netlists_own_error_is_not_blamed_on_set(tmp_path):
    bad = tmp_path / "own.yaml"
    bad.write_text(POWER_UNIT.read_text().replace('p_set: "180 bar", p_open: "190 bar"', 'p_set: "195 bar", p_open: "190 bar"'))
    done = _vphs("run", str(bad), "--set", "V_line=2 l", "-q")
    assert done.returncode == 2
    assert done.stderr.startswith(f"vphs: {bad}:28:") and "--set" not in done.stderr


def test_a_fixed_step_for_another_solver_is_refused():
    done = _vphs("run", str(POWER_UNIT), "--fixed-step", "1 ms", "-q")
    assert done.returncode == 2
    assert done.stderr == ("vphs: --fixed-step '1 ms': the step of the fixed solver, and this run's solver is rodas "
                           "(add --solver fixed)\n")
