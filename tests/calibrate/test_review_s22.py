"""Findings of user review s22 of `vphs calibrate` (input and report fixes; no statistic or decision changed).

- An empty cell in the grouping column was a group named '': with ``groups:`` the error blamed the YAML
  ("no parameter values for group(s)  of column 'setting'", a blank name), without it the row silently
  became a group of its own (a held-out fold of one point). It is now the data file's error at that cell.
- ``corrections: {pM: {offset: 0.5}}`` meant in bar was taken as 0.5 Pa, where a bare noise is refused; and
  the tool's own experiment_augmented.yaml wrote the fitted offset bare, in SI (53415.01...), so that the
  file it writes would now be refused. A bare offset is refused as a bare noise is; the written offset
  carries the channel's unit, every digit.
- The console gave an accepted offset in SI without a unit ("5.342e+04 +- 1.3e+04") where the verdict says
  "0.5342 +- 0.13 bar": both now use one function (blocks.calibrate.candidates.sensor_offset.shown_text).
- A Ctrl-C just after the last "wrote ..." line ended the run with 130 (no message, or "interrupted; nothing
  half-written was left behind" with the output whole): once the output is in place it is ignored, exit 0.
- report.md: BIC with one format (two decimals); an unchanged model said so instead of "after (augmented
  model)"; the held-out error said to be a mean chi^2 per held-out reading where first shown. report.json:
  every path absolute (calibrated_netlist was relative to the working folder, the inputs absolute).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import signal
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest
import yaml

import cli
from blocks.calibrate.experiment import load_experiment

DATA = Path(__file__).resolve().parent / "data"
NETLIST = DATA / "orifice_relief.yaml"
MEASURED = DATA / "orifice_relief_offset.csv"  # a pM sensor offset of +0.5 bar planted
DRIVE = Path(__file__).resolve().parents[2] / "netlists" / "experiments" / "circuits" / "drive_line_open.yaml"
FIRST_ROW_LINE = 4  # two comment lines and the header above the first data row


def spec(**changes) -> dict:
    """The experiment of the orifice and relief rig at two crack settings (steady points)."""
    out = {"description": "orifice + relief rig, steady points at two relief settings", "netlist": str(NETLIST),
           "data": str(MEASURED), "group": "setting",
           "inputs": {"Q": {"parameter": "Q_in", "noise": "0.3 l/min"}},
           "outputs": {"pP": {"signal": "pP", "noise": "0.2 bar"}, "pM": {"signal": "pM", "noise": "0.2 bar"}},
           "groups": {"1": {"p_set": "60 bar"}, "2": {"p_set": "100 bar"}},
           "free": {"A_orf": {"initial": "15 mm^2", "lower": "1 mm^2", "upper": "200 mm^2"},
                    "A_rv": {"initial": "15 mm^2", "lower": "1 mm^2", "upper": "200 mm^2"}},
           "heldout": {"scheme": "leave_one_group_out"}}
    out.update(changes)
    return {k: v for k, v in out.items() if v is not None}


def write(folder: Path, experiment: dict) -> Path:
    path = folder / "exp.yaml"
    path.write_text(yaml.safe_dump(experiment, sort_keys=False))
    return path


def refused(capsys, path: Path) -> str:
    """The one line `vphs calibrate` refuses ``path`` with (exit 2)."""
    code = cli.main(["calibrate", str(path), "-o", str(path.parent / "out"), "-q"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    return err.strip()


def calibrated(folder: Path, experiment: dict, argv_extra=()) -> tuple[str, Path]:
    """`vphs calibrate exp.yaml -o out` run from ``folder`` (relative paths, as a user types them): its stderr
    and the output folder; the SIGINT handler found before is found again after (an in-process caller's)."""
    write(folder, experiment)
    before, cwd, err = signal.getsignal(signal.SIGINT), os.getcwd(), io.StringIO()
    try:
        os.chdir(folder)
        with contextlib.redirect_stderr(err):
            code = cli.main(["calibrate", "exp.yaml", "-o", "out", *argv_extra])
    finally:
        os.chdir(cwd)
    assert code == 0, err.getvalue()
    assert signal.getsignal(signal.SIGINT) is before
    return err.getvalue(), folder / "out"


@pytest.fixture(scope="module")
def offset_run(tmp_path_factory):
    """The planted pM offset found (stderr, output folder, report.json)."""
    err, out = calibrated(tmp_path_factory.mktemp("offset"), spec())
    return err, out, json.loads((out / "report.json").read_text())


# ---------------------------------------------------------------- 1. an empty cell in the grouping column
@pytest.mark.parametrize("groups", [True, False], ids=["with groups", "without groups"])
def test_an_empty_cell_of_the_grouping_column_is_refused_at_that_cell(tmp_path, capsys, groups):
    lines = MEASURED.read_text().splitlines()
    k = FIRST_ROW_LINE + 2 - 1  # the third data row
    assert lines[k].startswith("1,")
    lines[k] = lines[k][1:]  # its setting left empty
    (tmp_path / "data.csv").write_text("\n".join(lines) + "\n")
    path = write(tmp_path, spec(data="data.csv", groups=None if not groups else spec()["groups"]))
    line = refused(capsys, path)
    assert line == f"vphs: {tmp_path / 'data.csv'}:{k + 1}:1: column 'setting': empty cell: every row needs its " \
                   f"group label"


# ---------------------------------------------------------------- 2. a sensor offset's unit
def test_a_bare_offset_is_refused_as_a_bare_noise_is_and_a_bare_gain_is_not(tmp_path, capsys):
    path = write(tmp_path, spec(corrections={"pM": {"offset": 0.5}}))
    line = refused(capsys, path)
    assert re.fullmatch(rf"vphs: {re.escape(str(path))}:\d+:\d+: corrections\.pM\.offset: 0\.5 has no unit; write it "
                        rf"with one \(e\.g\. \"0\.5 bar\"\): a bare number would be read in SI, as 0\.5 Pa", line), line
    exp = load_experiment(write(tmp_path, spec(corrections={"pM": {"offset": "0.5 bar", "gain": 0.01}})))
    assert exp.corrections["pM"] == {"offset": pytest.approx(0.5e5, rel=1e-12), "gain": 0.01}


def test_a_bare_offset_is_refused_where_the_data_column_gives_the_channels_dimension(tmp_path, capsys):
    """A profile's levels take any unit, so the column decides the input's dimension (bar here), as for its
    noise: a bare offset would be read in SI."""
    (tmp_path / "data.csv").write_text("t [s],cmd [bar],pA [bar]\n" + "".join(f"{k / 10:g},0,20\n" for k in range(8)))
    path = write(tmp_path, {"netlist": str(DRIVE), "data": "data.csv",
                            "inputs": {"cmd": {"signal": "cmd", "latent": ["u1"], "noise": "0.01 bar"}},
                            "outputs": {"pA": {"signal": "pA", "noise": "1 bar"}},
                            "corrections": {"cmd": {"offset": 0.5}}})
    line = refused(capsys, path)
    assert re.fullmatch(rf"vphs: {re.escape(str(path))}:\d+:\d+: corrections\.cmd\.offset: 0\.5 has no unit, but cmd "
                        rf"is in the column 'cmd \[bar\]' of data\.csv, a pressure \(Pa\): write it with one "
                        rf"\(e\.g\. \"0\.5 bar\"\)", line), line


def test_the_augmented_experiment_gives_the_fitted_offset_in_its_channels_unit(offset_run):
    _, out, report = offset_run
    (effect,) = report["effects"]
    assert effect["key"] == "sensor_offset@pM"
    written = yaml.safe_load((out / "experiment_augmented.yaml").read_text())["corrections"]["pM"]["offset"]
    number, unit = written.split()
    assert unit == "bar" and float(number) * 1e5 == pytest.approx(effect["value"], rel=1e-12)
    exp = load_experiment(out / "experiment_augmented.yaml")  # a file it writes is one it accepts
    assert exp.corrections["pM"]["offset"] == pytest.approx(effect["value"], rel=1e-12)


# ---------------------------------------------------------------- 3. the console's values carry their unit
def test_the_console_gives_an_accepted_offset_in_the_unit_the_report_and_verdict_give_it(offset_run):
    err, _, report = offset_run
    (effect,) = report["effects"]
    said = re.search(r"accepted sensor_offset@pM = (\S+) \+- (\S+)( bar)?$", err, re.M)
    assert said and said.group(3) == " bar", err
    assert float(said.group(1)) == pytest.approx(effect["value"] / 1e5, rel=1e-3)
    assert f"offset:pM = {said.group(1)} +- {said.group(2)} bar" in " ".join(report["verdict"])


# ---------------------------------------------------------------- 4. a Ctrl-C once the output is complete
def test_a_ctrl_c_once_the_output_is_in_place_is_ignored_to_the_process_exit(tmp_path, monkeypatch, capsys):
    """The `vphs` process (cli.entry): a Ctrl-C just after the last "wrote" line is ignored (exit 0, nothing
    said), and so is one after the command has returned, while the interpreter would shut down."""
    write(tmp_path, spec(trace={"only": ["sensor_offset"]}))
    real_print = print
    sent = []

    def print_then_ctrl_c(*args, **kwargs):
        real_print(*args, **kwargs)
        if args and str(args[0]).startswith("vphs: wrote ") and not sent:
            sent.append(True)
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(cli, "print", print_then_ctrl_c, raising=False)
    monkeypatch.setattr(sys, "argv", ["vphs", "calibrate", str(tmp_path / "exp.yaml"), "-o", str(tmp_path / "out")])
    handlers = {number: signal.getsignal(number) for number in (signal.SIGINT, signal.SIGTERM)}
    try:
        with pytest.raises(SystemExit) as exited:
            cli.entry()
        assert sent and exited.value.code == 0
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN  # through the interpreter's exit
        os.kill(os.getpid(), signal.SIGINT)  # as if while it shuts down: nothing happens
    finally:
        for number, handler in handlers.items():
            signal.signal(number, handler)
    err = capsys.readouterr().err
    assert "interrupted" not in err and err.rstrip().splitlines()[-1].startswith("vphs: wrote ")
    assert (tmp_path / "out" / "report.md").is_file() and not (tmp_path / "out" / ".previous").exists()


# ---------------------------------------------------------------- 5. report cosmetics and paths
def test_report_json_gives_every_path_absolute(offset_run):
    _, out, report = offset_run
    paths = [report["experiment"], report["netlist"], report["data"], report["calibrated_netlist"]]
    paths += [r[key] for r in report["rounds"] for key in ("netlist", "screening_netlist", "augmented_netlist")
              if r[key] is not None]
    assert all(Path(p).is_absolute() and Path(p).exists() for p in paths), paths
    assert Path(report["calibrated_netlist"]) == (out / "calibrated.yaml").resolve()


def test_the_fit_section_gives_bic_in_one_format_and_says_what_the_held_out_error_is(offset_run):
    _, out, _ = offset_run
    text = (out / "report.md").read_text()
    assert "## Fit, before (declared model) and after (augmented model)" in text
    lines = [line for line in text.splitlines() if line.startswith(("- before: chi^2", "- after: chi^2"))]
    assert len(lines) == 2
    bics = [re.search(r"BIC = (\S+),", line).group(1) for line in lines]
    assert all(re.fullmatch(r"-?\d+\.\d\d", b) for b in bics), bics
    said = "(the mean chi^2 per held-out reading of the outputs; leave one group out)"
    assert said in lines[0] and said not in lines[1] and "held-out error" not in text.split(lines[0])[0]


def test_a_model_nothing_was_added_to_is_said_to_be_unchanged(tmp_path):
    """The offset given as a correction: nothing left to find, the declared model is the final one."""
    _, out = calibrated(tmp_path, spec(corrections={"pM": {"offset": "0.5 bar"}}, trace={"only": ["sensor_offset"]}))
    text = (out / "report.md").read_text()
    assert "augmented model" not in text and "## Fit of the declared model (unchanged: no effect was added)" in text
    (line,) = [line for line in text.splitlines() if re.match(r"- (fit|before|after): chi\^2", line)]
    assert line.startswith("- fit: chi^2") and "(the mean chi^2 per held-out reading" in line


def test_a_model_whose_effects_were_all_removed_again_is_unchanged_too():
    """An effect accepted, then removed by the elimination check: the final model is the declared one."""
    from blocks.calibrate.report import fit_lines

    place = SimpleNamespace(key="leakage@P")
    rnd = SimpleNamespace(index=1, decision=SimpleNamespace(accepted=SimpleNamespace(score=SimpleNamespace(place=place))))
    fit = {"chi2": 30.0, "nu": 28, "chi2_nu": 30 / 28, "p_value": 0.4, "bic": 89.0987, "heldout_error": 1.1,
           "heldout_score": 1.1, "heldout_knots_propagated": 0, "heldout_scheme": "leave one group out",
           "heldout_unconverged_folds": [], "unsettled_points": 0, "lengthened_runs": {}, "fit_converged": True,
           "fit_evaluations": 12}
    cal = SimpleNamespace(rounds=[rnd], exchanges=[], initial=object(), final=object(),
                          removals=[SimpleNamespace(key="leakage@P", removed=True)])
    lines = fit_lines(cal, {"before": fit, "after": dict(fit, bic=151.19)}, steady=True)
    assert lines[0] == "## Fit of the declared model (unchanged: no effect was added)"
    assert "BIC = 89.10," in lines[2] and "BIC = 151.19," in lines[3]
    cal.removals[0].removed = False
    assert fit_lines(cal, {"before": fit, "after": fit}, steady=True)[0].endswith("after (augmented model)")


def test_a_plausible_range_refused_is_said_in_the_channels_unit():
    # the refit table's and the exchange's "why not" gave an offset's range in Pa ([-1.2e+05, 1.2e+05] Pa)
    from blocks.calibrate.candidates.base import Place
    from blocks.calibrate.candidates.sensor_offset import range_text

    exp = SimpleNamespace(channels=[SimpleNamespace(name="p1", unit="bar")])
    offset = Place("sensor_offset", "sensor_offset@p1", "channel p1", "offset:p1", "Pa", 0.0, -1e9, 1e9, 1.0,
                   (-1.2e5, 1.2e5), kind="channel")
    assert range_text(exp, offset) == "[-1.2, 1.2] bar"
    loss = Place("line_loss_laminar", "line_loss_laminar@a", "net a", "kl", "Pa*s/m^3", 0.0, 0.0, 1e20, 1.0,
                 (0.0, 1e12))
    assert range_text(exp, loss) == "[0, 1e+12] Pa*s/m^3"
