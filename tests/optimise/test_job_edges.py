"""A free parameter whose range reaches designs the blocks refuse is said before the run (blocks/optimise/job.py).

The user review's case: a relief valve's p_set free up to 200 bar with its p_open fixed at 190 bar. A part of
the box is a design no valve can be (p_open must be above p_set); its evaluations failed and cost the
penalty, and only the final count of failures said so.
"""

from pathlib import Path

from blocks.optimise.job import load_job

ROOT = Path(__file__).resolve().parents[2]
NETLIST = ROOT / "netlists" / "components" / "power_unit.yaml"

JOB = f"""\
netlist: {NETLIST}
parameters:
  relief.p_set: {{min: "{{low}}", max: "{{high}}"}}
cost:
  terms:
    v: {{kind: ise, signal: v, reference: "0.1 m/s"}}
algorithm: {{method: complex, max_evaluations: 10}}
"""


def _job(tmp_path, low: str, high: str):
    path = tmp_path / "job.yaml"
    path.write_text(JOB.replace("{low}", low).replace("{high}", high))
    return path, load_job(path)


def test_a_bound_past_what_the_netlist_allows_is_said(tmp_path):
    path, job = _job(tmp_path, "100 bar", "200 bar")
    assert job.warnings == [
        f"{path}: parameters.relief.p_set.max = 200 bar (the rest at the netlist's values) is refused: relief: "
        f"p_open = 190 bar must be above p_set = 200 bar (the valve opens over p_set ... p_open) "
        f"({NETLIST}:28:34); designs there fail and cost the penalty"]


def test_a_range_the_netlist_allows_says_nothing(tmp_path):
    assert _job(tmp_path, "100 bar", "185 bar")[1].warnings == []


def test_a_bound_refused_in_one_load_case_only_names_it(tmp_path):
    # the review of session 22: only the first load case was tried
    path = tmp_path / "job.yaml"
    path.write_text(JOB.replace("{low}", "100 bar").replace("{high}", "185 bar")
                    + 'load_cases:\n  open_190: {relief.p_open: "190 bar"}\n  open_183: {relief.p_open: "183 bar"}\n')
    job = load_job(path)
    assert len(job.warnings) == 1
    assert job.warnings[0].startswith(f"{path}: parameters.relief.p_set.max = 185 bar (load case open_183, the rest at "
                                      f"the netlist's values) is refused: relief: p_open = 183 bar must be above "
                                      f"p_set = 185 bar")
