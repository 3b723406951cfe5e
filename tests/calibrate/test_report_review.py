"""What a first user's review asked of the calibration report: the largest normalised residuals by data file
and line, with a verdict line when one is beyond what their number makes plausible (a gross error in one
reading); plots of the model against the data (fit.png); the conventions behind the numbers; fitted values in
calibrated.yaml to the digits their standard errors warrant. None of it changes what the calibration computes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy import stats as sps

import cli
from blocks.calibrate import outliers
from tests.calibrate.test_calibrate_end_to_end import ROOT, steady_case


def _with_outlier(tmp_path: Path, line: int, column: int, add: float) -> Path:
    """The relief rig's steady data (no planted effect) with ``add`` added to one cell (file line, column)."""
    exp = steady_case(tmp_path, 0.0, seed=6, only=["leakage"])
    lines = (tmp_path / "data.csv").read_text().splitlines()
    cells = lines[line - 1].split(",")
    cells[column] = f"{float(cells[column]) + add:.5f}"
    lines[line - 1] = ",".join(cells)
    (tmp_path / "data.csv").write_text("\n".join(lines) + "\n")
    return exp


def test_the_bound_is_the_two_sided_one_percent_bonferroni_bound():
    for n in (1, 48, 600, 6000):
        c = outliers.bound(n)
        assert n * 2 * sps.norm.sf(c) == pytest.approx(0.01, rel=1e-9)
    assert outliers.bound(48) == pytest.approx(3.709, abs=1e-3)


def test_a_gross_error_in_one_reading_is_named_by_file_and_line(tmp_path, capsys):
    """p1 on line 9 of the data (a point of setting 2) read 3 bar (15 sigma) too high: the verdict keeps its
    lines and adds one naming the reading by file and line; the report's table and report.json give it."""
    exp = _with_outlier(tmp_path, line=9, column=2, add=3.0)
    out = tmp_path / "out"
    assert cli.main(["calibrate", str(exp), "-o", str(out), "-q"]) == 0
    stdout = capsys.readouterr().out
    report = json.loads((out / "report.json").read_text())
    largest = report["largest_residuals"]
    assert largest["residuals"] == 21 * 4 and largest["bound"] == pytest.approx(outliers.bound(84))
    top = largest["rows"][0]
    assert (top["channel"], top["file"], top["line"], top["where"], top["group"]) == ("p1", "data.csv", 9,
                                                                                      "data.csv:9", "2")
    assert top["beyond_bound"] and top["z"] < -largest["bound"] and top["measured"] > top["fitted"]
    assert len(largest["rows"]) == 10 and largest["beyond_bound"] >= 1
    z = [abs(r["z"]) for r in largest["rows"]]
    assert z == sorted(z, reverse=True)
    line = report["verdict"][-1]
    assert "check the data at data.csv:9" in line and "a gross error pulls every estimate" in line, line
    assert "data.csv:9" not in "".join(report["verdict"][:-1])  # a line of its own, after the others
    assert line in stdout
    text = (out / "report.md").read_text()
    assert "## Largest normalised residuals (final model)" in text
    assert "| p1 | data.csv:9 | 2 |" in text
    assert (out / "fit.png").stat().st_size > 10000 and "![model against data](fit.png)" in text


def test_a_clean_fit_names_no_reading(tmp_path):
    exp = steady_case(tmp_path, 0.0, seed=6, only=["leakage"])
    out = tmp_path / "out"
    assert cli.main(["calibrate", str(exp), "-o", str(out), "-q"]) == 0
    report = json.loads((out / "report.json").read_text())
    assert report["largest_residuals"]["beyond_bound"] == 0
    assert not any("gross" in v for v in report["verdict"])
    assert "none is beyond it" in (out / "report.md").read_text()


def test_row_places_of_several_files_follow_the_files(tmp_path):
    """Rows of several data files: each file's own lines (comment lines counted), in the data's order."""
    from types import SimpleNamespace

    from blocks.datafile import read_table

    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    a.write_text("# rig A\nQ [l/min],p1 [bar]\n1,2\n3,4\n")
    b.write_text("Q [l/min],p1 [bar]\n# a remark\n\n5,6\n")
    exp = SimpleNamespace(data_files=[a, b], data=a, spec=SimpleNamespace(group=None))
    data = SimpleNamespace(table=read_table(a), n=3)
    assert outliers.row_places(exp, data) == [("a.csv", 3), ("a.csv", 4), ("b.csv", 4)]
    assert outliers.where(("a.csv", None), 4) == "a.csv row 5"


def test_a_fitted_value_lost_beside_a_huge_reading_is_not_shown():
    """A typo of 2.3e30 bar: the fitted value, reading + z*sigma, is lost in the rounding; shown as unknown
    rather than as 0."""
    from types import SimpleNamespace

    sigma = 2e4
    measured = np.array([2.312e35, 2.0e6])
    r = np.array([-measured[0] / sigma, 0.5])
    ch = SimpleNamespace(name="p1", role="output", unit="bar")
    model = SimpleNamespace(channels=[ch], row_channel=np.array([0, 0]), row_point=np.array([0, 1]),
                            measured=measured, row_sigma=np.full(2, sigma))
    stage = SimpleNamespace(model=model, fit=SimpleNamespace(rows=np.ones(2, bool), r=r))
    data = SimpleNamespace(n=2, kind="steady", groups={"all": [0, 1]}, labels=["all", "all"], t=None,
                           table=SimpleNamespace(lines=[2, 3]))
    exp = SimpleNamespace(data_files=[], data=Path("s.csv"), spec=SimpleNamespace(group=None))
    info = outliers.largest(exp, data, stage)
    assert info["rows"][0]["fitted"] is None and info["rows"][1]["fitted"] == pytest.approx(20.1)
    assert info["rows"][0]["where"] == "s.csv:2" and info["beyond_bound"] == 1
    line = outliers.verdict_line(info)[0]
    assert line.startswith("gross residual: p1 at s.csv:2 is 1.16e+31 sigma off the final fit (measured 2.312e+30 bar)")


def _fake_calibration(kind: str, runs: int):
    """A calibration's fitted stages as fit.png reads them: two outputs (y1 in bar, y2 in l/min) and an imposed
    input u, ``runs`` groups of 6 points or samples; the declared residuals 2, the final ones 0.5."""
    from types import SimpleNamespace

    n = 6 * runs
    labels = [f"g{k // 6}" for k in range(n)]
    channels = [SimpleNamespace(name="y1", role="output", unit="bar"),
                SimpleNamespace(name="y2", role="output", unit="l/min"),
                SimpleNamespace(name="u", role="input", unit="1")]
    rng = np.random.default_rng(1)
    measured = {"y1": 1e5 * rng.uniform(1, 9, n), "y2": rng.uniform(1e-4, 1e-3, n), "u": rng.uniform(0, 1, n)}
    sigma = {"y1": 2e4, "y2": 1e-5, "u": 0.01}
    groups = {}
    for k, label in enumerate(labels):
        groups.setdefault(label, []).append(k)
    data = SimpleNamespace(kind=kind, n=n, labels=labels, groups={g: np.array(v) for g, v in groups.items()},
                           t=np.tile(np.arange(6) * 0.1, runs) if kind == "time" else None, measured=measured,
                           sigma=sigma)

    def stage(r):
        model = SimpleNamespace(channels=channels, row_channel=np.repeat(np.arange(3), n),
                                row_point=np.tile(np.arange(n), 3),
                                measured=np.concatenate([measured[c.name] for c in channels]),
                                row_sigma=np.repeat([sigma[c.name] for c in channels], n))
        return SimpleNamespace(model=model, fit=SimpleNamespace(r=np.full(3 * n, r)),
                               lof=SimpleNamespace(reduced=r * r))

    exp = SimpleNamespace(outputs=channels[:2], inputs=channels[2:], file="exp.yaml", spec=SimpleNamespace(group="run"))
    return SimpleNamespace(exp=exp, data=data, initial=stage(2.0), final=stage(0.5))


@pytest.mark.parametrize("kind, runs, columns", [("time", 1, 1), ("time", 5, 4), ("steady", 3, 1)])
def test_fit_png_draws_the_fitted_values_of_both_models_against_the_data(monkeypatch, tmp_path, kind, runs, columns):
    """fit.png from the fits' own values (reading + residual x sigma, no new simulation): a time series's
    outputs against t, a column per run (the first 4); steady outputs against the imposed input, the models at
    their fitted inputs, a colour per group."""
    from blocks.calibrate import report

    drawn = {}
    monkeypatch.setattr(report, "atomic_write_figure", lambda fig, path: drawn.setdefault("fig", fig))
    cal = _fake_calibration(kind, runs)
    report.plot_fit(cal, tmp_path / "fit.png")
    axes = drawn["fig"].axes
    assert len(axes) == 4 * columns  # each output's panel and its misfit's beneath (test_fit_residuals_s23.py)
    y1 = cal.data.measured["y1"] / 1e5
    first = axes[0].get_lines()  # [measured (or its error bar's line), declared, final] per group
    if kind == "time":
        t, declared, final = first[0], first[1], first[2]
        assert np.allclose(t.get_ydata(), y1[:6]) and np.allclose(final.get_ydata(), y1[:6] + 0.5 * 0.2)
        assert np.allclose(declared.get_ydata(), y1[:6] + 2.0 * 0.2) and np.allclose(final.get_xdata(), cal.data.t[:6])
        titles = [ax.get_title() for ax in axes[:columns]]
        assert titles == ([""] if runs == 1 else ["run g0", "run g1", "run g2", "run g3"])
    else:
        finals = [line for line in first if line.get_marker() == "." and line.get_linestyle() == "-"]
        assert len(finals) == runs  # one per group
        u = cal.data.measured["u"][:6] + 0.5 * 0.01  # the final fit's input at the points
        order = np.argsort(u)
        assert np.allclose(finals[0].get_xdata(), u[order])
        assert np.allclose(finals[0].get_ydata(), (y1[:6] + 0.5 * 0.2)[order])
        assert len({line.get_color() for line in finals}) == runs


def test_residuals_png_draws_a_pressure_drop_on_its_x_axis():
    """A leakage across two measured nets is plotted against the drop between them (plot_against "a - b")."""
    from types import SimpleNamespace

    from blocks.calibrate.report import _axis

    channels = [SimpleNamespace(name="p2", unit="bar"), SimpleNamespace(name="p3", unit="bar")]
    data = SimpleNamespace(kind="steady", n=2, t=None,
                           measured={"p2": np.array([3e5, 4e5]), "p3": np.array([1e5, 1.5e5])})
    cal = SimpleNamespace(exp=SimpleNamespace(channels=channels), data=data)
    x, label = _axis(cal, "p2 - p3")
    assert np.allclose(x, [2.0, 2.5]) and label == "p2 - p3 [bar] (measured)"
    assert np.allclose(_axis(cal, "p3")[0], [1.0, 1.5]) and _axis(cal, "t")[1] == "point"


def test_the_report_states_its_conventions(tmp_path):
    """How SEs are scaled (and by how much here), how chi^2/nu is shared between channels, what 'absorbed'
    means; a time series's report says nothing of unsettled points (a steady notion), a steady one does."""
    from blocks.calibrate.experiment import load_experiment
    from blocks.calibrate.report import write
    from blocks.calibrate.run import calibrate

    exp = load_experiment(ROOT / "netlists" / "experiments" / "drive_line_series.yaml")
    exp.spec.trace.only = ["sensor_offset"]  # no simulation to screen: a short test
    cal = calibrate(exp, tmp_path / "time", rounds=1, with_heldout=False)
    paths = write(cal, tmp_path / "time")
    text, info = paths["markdown"].read_text(), json.loads(paths["json"].read_text())
    assert "unsettled" not in text.lower()
    assert info["overall"]["after"]["unsettled_points"] == 0  # report.json keeps its field
    scale = info["se_scale"]
    assert scale["before"] == pytest.approx(np.sqrt(cal.initial.lof.reduced)) and scale["before"] > 1
    assert f"declared fit: x {scale['before']:.3g}" in text
    assert "## How to read the numbers" in text and "multiplied by sqrt(chi^2/nu)" in text
    assert "chi^2_c / (n_c nu / n)" in text and "'absorbed' column" in text
    assert paths["fit"].stat().st_size > 10000
    assert "| channel | data file:line | t [s] | measured |" in text  # the largest residuals, with their times
    rows = info["largest_residuals"]["rows"]
    assert all(r["file"] == "drive_line_series.csv" and r["line"] == r["point"] + 4 for r in rows)  # 2 comments, header
    assert all(r["t"] == pytest.approx(cal.data.t[r["point"]]) for r in rows)
    # steady points: unsettled points are said, and what they are
    out = tmp_path / "steady"
    assert cli.main(["calibrate", str(steady_case(tmp_path, 0.0, seed=6, only=["leakage"])), "-o", str(out), "-q"]) == 0
    text = (out / "report.md").read_text()
    assert "; unsettled points: 0" in text and "- Unsettled points: steady points read at the end" in text


@pytest.mark.parametrize("value, se, unit, text", [
    (0.004986927365810372, 4.1e-5, "kg*m^2", "0.0049869 kg*m^2"),  # the review's example
    (3.00722455637188, 0.041, "N*m", "3.0072 N*m"),
    (59.1181234567e5, 0.0123e5, "bar", "59.1181 bar"),  # in its display unit
    (2.88123456e-11, 3.7e-12, "m^3/(s*Pa)", "2.881e-11 m^3/(s*Pa)"),  # never fewer than 4 digits
    (0.0012345678, 0.5, "", 0.001235),  # an SE larger than the value: 4 digits
    (123.456789, float("inf"), "", 123.5),  # not fixed by the data: 4 digits
    (0.1234567891234, float("nan"), "", 0.1234567891234),  # no SE: every digit
    (0.0, 1e-3, "", 0.0)])
def test_a_fitted_value_is_written_to_the_digits_its_standard_error_warrants_plus_two(value, se, unit, text):
    from blocks.calibrate.patch import rounded

    assert rounded(value, se, unit) == text


def test_calibrated_yaml_keeps_every_digit_and_lists_them_rounded_for_people(tmp_path):
    """calibrated.yaml sets each fitted value with every digit (`vphs run` reproduces the fit), and its
    header lists each to the digits its SE warrants plus 2, with the SE (a review found 16-digit values
    hard to read)."""
    import yaml

    from blocks.calibrate.patch import rounded, written
    from blocks.calibrate.run import calibrate

    cal = calibrate(_with_outlier(tmp_path, line=9, column=2, add=0.0), tmp_path / "out", rounds=1,
                    with_heldout=False)
    layout, fit = cal.final.model.layout, cal.final.fit
    text = cal.calibrated.read_text()
    doc = yaml.safe_load(text)
    for name in ("k_s", "A_ret", "R_meter"):
        j = layout.index(name)
        g = layout.globals[j]
        assert doc["parameters"][name] == written(float(fit.x[j]), g.unit)
        listed = f"{name} = {rounded(float(fit.x[j]), float(fit.se[j]), g.unit)} +- "
        assert listed in text
        mantissa = listed.split(" = ")[1].split()[0].lower().split("e")[0]
        assert len(mantissa.replace(".", "").replace("-", "").lstrip("0")) <= 8  # a few digits, not 16
    # (the round's augmented netlist keeps every digit of the effect's value: test_calibrate_end_to_end's
    # test_time_series_coulomb_friction_is_found)
