"""Job files: the examples load; every mistake is one located line naming the file, line and column."""

from pathlib import Path

import pytest

from blocks.errors import NetlistError
from blocks.optimise.job import load_job

ROOT = Path(__file__).resolve().parents[2]
NETLIST = ROOT / "netlists" / "opt" / "drive_line.yaml"

GOOD = f"""\
netlist: {NETLIST}
seed: 3
parameters:
  Kp: {{min: 1, max: 40, log: true}}
  V_line: {{min: "0.5 l", max: "2 l"}}
cost:
  terms:
    pos: {{kind: ise, signal: x, reference: x_ref, unit: mm, weight: 50}}
    vib: {{kind: hp_ise, signal: pA, wn: "16 Hz", weight: 3e-8}}
load_cases:
  empty: {{m_load: "0 kg"}}
  full: {{m_load: "15 t"}}
algorithm: {{method: complex, max_evaluations: 50}}
"""


def write(tmp_path, text: str) -> Path:
    path = tmp_path / "job.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("name", ["drive_line_controller.yaml", "drive_line_load_cases.yaml"])
def test_example_jobs_load(name):
    job = load_job(ROOT / "netlists" / "jobs" / name)
    assert job.free and job.terms and job.method == "complex" and job.sweep_points


def test_values_in_units_are_converted_to_si(tmp_path):
    job = load_job(write(tmp_path, GOOD))
    v_line = next(p for p in job.free if p.name == "V_line")
    assert (v_line.lower, v_line.upper) == pytest.approx((0.5e-3, 2e-3))
    assert job.cases == [("empty", {"m_load": 0.0}), ("full", {"m_load": 15000.0})]
    vib = next(t for t in job.terms if t.name == "vib")
    assert vib.wn == pytest.approx(2 * 3.141592653589793 * 16)  # Hz is an angular frequency of 2*pi rad/s
    pos = next(t for t in job.terms if t.name == "pos")
    assert (pos.scale, pos.weight, pos.reference) == (1e-3, 50.0, "x_ref")
    # normalised coordinates: log scaling maps z = 0.5 onto the geometric mean
    values = job.values([0.5, 0.5])
    assert values["Kp"] == pytest.approx(40 ** 0.5) and values["V_line"] == pytest.approx(1.25e-3)
    assert job.coordinates(values) == pytest.approx([0.5, 0.5])


@pytest.mark.parametrize("change,line,message", [
    (("seed: 3", "sed: 3"), 2, "unknown key 'sed' (did you mean seed, set?)"),
    (("seed: 3", "xyzzy: 3"), 2, "unknown key 'xyzzy' (allowed: algorithm, cost, description, load_cases, name"),
    (("seed: 3", "scheduler: notanaddress"), 2, "scheduler: 'notanaddress': the port is missing or not a number"),
    (("  Kp: {min: 1", "  Kpp: {min: 1"), 4, "'Kpp' is not a parameter of"),
    (("max: 40, log", "max: 0.5, log"), 4, "max (0.5) must be above min (1)"),
    (("{min: 1, max: 40, log: true}", "{min: 0, max: 40, log: true}"), 4, "log scaling needs min > 0"),
    (('min: "0.5 l"', 'min: "0.5 bar"'), 5, "parameters.V_line.min"),
    (("signal: x,", "signal: xx,"), 8, "'xx' is not a logged signal"),
    (("unit: mm,", "unit: bar,"), 8, "'bar' does not fit signal x"),
    (("reference: x_ref", "reference: pA"), 8, "reference pA is in m^-1*kg*s^-2, signal x in m"),
    (('wn: "16 Hz", ', ""), 9, "hp_ise needs wn"),
    (("kind: ise", "kind: iae"), 8, "cost.terms.pos.kind"),
    (("m_load: \"15 t\"", "m_load: \"15 bar\""), 12, "load_cases.full.m_load"),
    (("m_load: \"15 t\"", "Kp: 3"), 12, "Kp is varied by the job"),
    (("method: complex", "method: simplex"), 13, "unknown method 'simplex' (methods: complex, nelder_mead"),
    (("max_evaluations: 50", "max_evaluations: 3"), 13, "fewer than the 4 points"),
    (("max_evaluations: 50}", "max_evaluations: 50, alpah: 1.3}"), 13, "unknown key 'alpah' (did you mean alpha?)"),
    (("m_load: \"0 kg\"", "m_load: \"-1e6 kg\""), 11, "bridge: J = -3.61322 kg*m^2 is below its lower bound"),
    # a time window that keeps too few output samples would score 0 for every design (the run is 0 ... 3 s)
    (("weight: 50}", 'weight: 50, t_from: "5 s", t_to: "1 s"}'), 8, "cost.terms.pos.t_from: 5 s is after t_to (1 s)"),
    (("weight: 50}", 'weight: 50, t_from: "10 s"}'), 8, "t_from: 10 s is after the simulation's end (3 s)"),
    (("weight: 3e-8}", 'weight: 3e-8, t_to: "-1 s"}'), 9, "t_to: -1 s is before the simulation's start (0 s)"),
    (("weight: 50}", 'weight: 50, t_from: "1.0004 s", t_to: "1.0006 s"}'), 8, "holds 0 of the run's output samples"),
    (("weight: 50}", 'weight: 50, t_from: "3 s"}'), 8, "holds 1 of the run's output samples"),
    (("{min: 1, max: 40, log: true}", "{min: true, max: 40, log: true}"), 4, "parameters.Kp.min: true is not a number"),
    (("weight: 50}", "weight: yes}"), 8, "cost.terms.pos.weight: true is not a number"),  # was weight 1
    (("max_evaluations: 50}", "max_evaluations: on}"), 13, "algorithm.max_evaluations: true is not a number"),
    # review: workers: was silently ignored beside scheduler:; a name with '..' or '/' wrote outside out/
    (("seed: 3", "seed: 3\nworkers: 2\nscheduler: tcp://127.0.0.1:8786"), 3, "workers: sets the local processes"),
    (("seed: 3", "seed: 3\nname: ../../escaped"), 3, "name: '../../escaped' is not a plain name"),
    (("seed: 3", "seed: 3\nname: sub/dir"), 3, "name: 'sub/dir' is not a plain name"),
    (("seed: 3", "seed: 3\nname: '..'"), 3, "name: '..' is not a plain name"),
])
def test_mistakes_are_located(tmp_path, change, line, message):
    text = GOOD.replace(*change)
    assert text != GOOD
    path = write(tmp_path, text)
    with pytest.raises(NetlistError) as info:
        load_job(path)
    error = info.value
    assert message in str(error), str(error)
    assert error.file == str(path) and error.line == line, str(error)
    assert "\n" not in str(error)


def test_a_cost_whose_weights_are_all_zero_is_refused(tmp_path):
    """Review: every design cost 0, and the job reported a 'best' among equals."""
    text = GOOD.replace("weight: 50}", "weight: 0}").replace("weight: 3e-8}", "weight: 0}")
    with pytest.raises(NetlistError) as info:
        load_job(write(tmp_path, text))
    assert "cost.terms: every weight is 0" in str(info.value) and info.value.line == 7


def test_workers_beside_a_scheduler_is_refused_on_the_command_line(tmp_path, capsys):
    """Review: --scheduler ADDR --workers N ignored --workers silently."""
    import cli

    path = write(tmp_path, GOOD)
    assert cli.main(["optimise", str(path), "--scheduler", "tcp://127.0.0.1:9", "--workers", "2"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("vphs: --workers 2 sets the local processes, but --scheduler tcp://127.0.0.1:9") \
        and err.count("\n") == 1, err


def test_a_netlist_given_as_a_job_says_so(tmp_path):
    """Review: `vphs optimise <netlist>` said "parameters...: Input should be a valid dictionary or instance
    of FreeParameter"."""
    with pytest.raises(NetlistError) as info:
        load_job(NETLIST)
    assert str(info.value) == (f"{NETLIST}: this is a netlist (it has components:, nets:), not an optimisation job; "
                               f"run it with vphs run")


def test_a_window_on_one_sample_is_enough_for_a_largest_error(tmp_path):
    """max_abs at one instant (a sample of the run) means something; an integral over it would not."""
    text = GOOD.replace("    vib:", '    end: {kind: max_abs, signal: x, reference: x_ref, t_from: "3 s"}\n    vib:')
    end = next(t for t in load_job(write(tmp_path, text)).terms if t.name == "end")
    assert (end.t_from, end.t_to) == (3.0, None)


SPEED_COMMAND = """\
components:
  cmd:   {type: step, params: {t_step: "0.1 s", y1: 10}}
  drive: {type: speed_source}
  load:  {type: inertia, params: {J: "0.1 kg*m^2"}}
nets:
  w:     [cmd.y, drive.w]
  shaft: [drive.port, load.port]
outputs:
  w_cmd: cmd.y
simulation: {t_end: "0.5 s"}
"""


@pytest.mark.parametrize("unit, refused", [("bar", True), ("rpm", False)])
def test_term_unit_on_a_generic_signal_read_as_a_speed(tmp_path, unit, refused):
    """A step's output is generic (SI), but the speed source reads it as w [rad/s]: the netlist knows it is a
    speed (blocks.circuit.ResolvedOutput.declared), so a cost term may not express it in bar."""
    (tmp_path / "speed.yaml").write_text(SPEED_COMMAND)
    text = (f"netlist: speed.yaml\nparameters:\n  load.J: {{min: 0.05, max: 0.2}}\n"
            f"cost:\n  terms:\n    w: {{kind: max_abs, signal: w_cmd, unit: {unit}}}\n")
    if refused:
        with pytest.raises(NetlistError, match=r"job.yaml:6:\d+: cost.terms.w.unit: 'bar' does not fit signal w_cmd"):
            load_job(write(tmp_path, text))
    else:
        assert load_job(write(tmp_path, text)).terms[0].unit == "rpm"


def test_out_of_netlist_bounds_and_missing_sections(tmp_path):
    with pytest.raises(NetlistError, match=r"job.yaml:\d+:\d+: .*valve.Cd.*(above|below)"):
        load_job(write(tmp_path, GOOD.replace("  Kp: {min: 1, max: 40, log: true}", "  valve.Cd: {min: 0.5, max: 2}")))
    with pytest.raises(NetlistError, match="missing 'cost'"):
        load_job(write(tmp_path, f"netlist: {NETLIST}\n"))
    with pytest.raises(NetlistError, match="netlist: file not found"):
        load_job(write(tmp_path, GOOD.replace(str(NETLIST), "nowhere.yaml")))
    with pytest.raises(NetlistError, match="array parameter"):
        load_job(write(tmp_path, GOOD.replace("  Kp: {min: 1, max: 40, log: true}", "  v_ref.times: {min: 0, max: 1}")))


def test_sweep_grid_and_list(tmp_path):
    text = GOOD + "sweep:\n  parameters:\n    Kp: [2, 4, 8]\n    Kv: {min: 0.2, max: 0.6, points: 3}\n"
    job = load_job(write(tmp_path, text))
    assert len(job.sweep_points) == 9 and job.sweep_names == ["Kp", "Kv"]
    assert job.sweep_points[0] == {"Kp": 2.0, "Kv": 0.2} and job.sweep_points[1] == pytest.approx({"Kp": 2.0, "Kv": 0.4})
    listed = load_job(write(tmp_path, text + "  combine: list\n"))
    assert [p["Kp"] for p in listed.sweep_points] == [2.0, 4.0, 8.0]
    assert [p["Kv"] for p in listed.sweep_points] == pytest.approx([0.2, 0.4, 0.6])
    with pytest.raises(NetlistError, match="equally many"):
        load_job(write(tmp_path, text.replace("points: 3", "points: 4") + "  combine: list\n"))
    with pytest.raises(NetlistError, match="sweep.parameters"):
        load_job(write(tmp_path, GOOD + "sweep:\n  parameters: {Kp: [1], Kv: [1], m_load: [1]}\n"))
    with pytest.raises(NetlistError, match=r"job.yaml:\d+:\d+: sweep.parameters.Kp: expected a list of values, or"):
        load_job(write(tmp_path, GOOD + "sweep:\n  parameters: {Kp: 5}\n"))
    with pytest.raises(NetlistError, match="sweep.parameters.Kp.points: missing 'points'"):
        load_job(write(tmp_path, GOOD + "sweep:\n  parameters: {Kp: {min: 1, max: 3}}\n"))


def test_an_output_that_is_a_file_is_said_at_output(tmp_path, monkeypatch, capsys):
    """output: is relative to the working directory; a file there (or on its way) is one located line,
    exit 2, before any worker starts -- not the operating system's 'File exists' from the log."""
    import cli

    monkeypatch.chdir(tmp_path)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "dl.csv").write_text("t,x\n")
    for output, message in (("out/dl.csv", "output 'out/dl.csv' is a file, not a folder"),
                            ("out/dl.csv/sub", "output 'out/dl.csv/sub': 'out/dl.csv' is a file, not a folder")):
        path = write(tmp_path, GOOD.replace("seed: 3", f"seed: 3\noutput: {output}"))
        for command in ("optimise", "sweep"):
            assert cli.main([command, str(path), "--workers", "1"]) == 2
            err = capsys.readouterr().err
            assert err == f"vphs: {path}:3:1: {message}\n", err
    assert (tmp_path / "out" / "dl.csv").read_text() == "t,x\n"
    # the sweep's own subfolder taken by a file: the log says so when it would be written
    (tmp_path / "res").mkdir()
    (tmp_path / "res" / "sweep").write_text("")
    path = write(tmp_path, GOOD.replace("seed: 3", "seed: 3\noutput: res") + "sweep: {parameters: {Kp: [2]}}\n")
    assert cli.main(["sweep", str(path), "--workers", "1"]) == 2
    assert "'res/sweep' is a file, not a folder" in capsys.readouterr().err
    # the default output folder out/<name>: said too, without a line to point at
    (tmp_path / "out" / "job").write_text("")
    with pytest.raises(NetlistError, match="the default output folder 'out/job' \\(set output:\\) is a file"):
        load_job(write(tmp_path, GOOD))
