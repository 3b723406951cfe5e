"""A process keeps each job's circuit under the digests of the files it is built from
(blocks/optimise/evaluate.py, ``circuit_for``).

Found by the memory review (session 24): circuits were kept by the netlist's path alone, so a process that
outlives a job (a Dask worker, a Python session running jobs one after the other) evaluated a later job's
designs on the netlist as the earlier job had read it, however it had been edited since.

The circuit: tests/circuits/netlists/flow_pulse.yaml, a 1 l volume drained by a laminar leak G = 1e-11
m^3/(s*Pa) taking a flow q; p rises to q/G (10 l/min: 16.67 bar, within 0.04 % by 1 s), the job's cost.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from blocks.errors import VphsError
from blocks.optimise import evaluate
from blocks.optimise.evaluate import circuit_for, evaluate_design
from blocks.optimise.job import load_job

FLOW_PULSE = Path(__file__).resolve().parents[1] / "circuits" / "netlists" / "flow_pulse.yaml"
G = 1e-11


def _write_netlist(path: Path, q_lpm: float) -> None:
    spec = yaml.safe_load(FLOW_PULSE.read_text())
    spec["parameters"].update({"t_p": "0.01 s", "w": "100 s", "q": f"{q_lpm} l/min"})
    spec["simulation"] = {"t_end": "1 s", "dt_out": "10 ms"}
    path.write_text(yaml.safe_dump(spec, sort_keys=False))


def _job(tmp_path: Path, q_lpm: float) -> Path:
    netlist = tmp_path / "pulse.yaml"
    _write_netlist(netlist, q_lpm)
    job = tmp_path / "job.yaml"
    job.write_text(f"""\
name: pulse
netlist: {netlist}
output: {tmp_path / "out"}
cost:
  terms:
    peak: {{kind: max_abs, signal: pA, unit: bar}}
parameters:
  w: {{min: "50 s", max: "200 s"}}
algorithm: {{method: complex, max_evaluations: 4}}
""")
    return job


def test_an_edited_netlist_is_read_again_by_the_next_job(tmp_path):
    first = load_job(_job(tmp_path, 10.0))
    record = evaluate_design(first.spec(), {"w": 100.0})
    assert record["status"] == "ok", record
    assert record["cost"] == pytest.approx(10.0 / 60000 / G / 1e5, rel=1e-3)
    second = load_job(_job(tmp_path, 20.0))  # the same path, edited: the flow doubled
    record = evaluate_design(second.spec(), {"w": 100.0})
    assert record["status"] == "ok", record
    assert record["cost"] == pytest.approx(20.0 / 60000 / G / 1e5, rel=1e-3)


def test_a_file_changed_since_the_job_read_it_fails_the_evaluation_and_says_why(tmp_path):
    job = load_job(_job(tmp_path, 10.0))
    evaluate._CIRCUITS.clear()  # a fresh worker
    _write_netlist(Path(job.netlist), 20.0)  # edited after the job started
    record = evaluate_design(job.spec(), {"w": 100.0})
    assert record["status"] == "failed"
    assert "pulse.yaml changed since the job read it" in record["error"]
    with pytest.raises(VphsError, match="changed since the job read it"):
        circuit_for(job.netlist, job.spec().sources)


def test_a_process_keeps_a_few_circuits_only(tmp_path):
    evaluate._CIRCUITS.clear()
    for k in range(evaluate._KEPT + 2):
        netlist = tmp_path / f"pulse{k}.yaml"
        _write_netlist(netlist, 10.0 + k)
        assert circuit_for(str(netlist)) is circuit_for(str(netlist))  # kept while in use
    assert len(evaluate._CIRCUITS) == evaluate._KEPT


def test_without_digests_an_edited_netlist_is_read_again(tmp_path):
    """A caller that gives no digests (a study script, a benchmark) gets the files as they are now."""
    netlist = tmp_path / "pulse.yaml"
    _write_netlist(netlist, 10.0)
    first = circuit_for(str(netlist))
    assert circuit_for(str(netlist)) is first
    _write_netlist(netlist, 20.0)
    again = circuit_for(str(netlist))
    assert again is not first and again.vectors().values["q"] == 2 * first.vectors().values["q"]
