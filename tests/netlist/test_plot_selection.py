"""`vphs run --plot FILE --x SIGNAL --y SIGNAL ...`: what the plot draws, against what, and the refusals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import cli

ROOT = Path(__file__).resolve().parents[2]
STEP = ROOT / "tests" / "circuits" / "netlists" / "second_order_step.yaml"
RC = ROOT / "tests" / "circuits" / "netlists" / "linear_rest.yaml"


@pytest.fixture
def drawn(monkeypatch):
    """Every curve drawn: (label, x, y) as matplotlib received them."""
    from matplotlib.axes import Axes

    curves, real_plot = [], Axes.plot

    def spy(self, x, y, *args, **kwargs):
        curves.append((kwargs.get("label"), np.asarray(x), np.asarray(y), self))
        return real_plot(self, x, y, *args, **kwargs)

    monkeypatch.setattr(Axes, "plot", spy)
    return curves


def test_chosen_signals_against_another_signal_in_display_units(tmp_path, capsys, drawn):
    csv, png = tmp_path / "r.csv", tmp_path / "r.png"
    assert cli.main(["run", str(RC), "-q", "-o", str(csv), "--plot", str(png), "--x", "qi", "--y", "p"]) == 0
    assert [c[0] for c in drawn] == ["p"]
    table = np.genfromtxt(csv, delimiter=",", names=True)
    header = csv.read_text().splitlines()[0]
    assert header == "t [s],p [bar],qi [SI]"
    label, x, y, ax = drawn[0]
    np.testing.assert_allclose(x, table["qi_SI"])
    np.testing.assert_allclose(y, table["p_bar"])  # bar, as the CSV
    assert ax.get_xlabel() == "qi [SI]" and ax.get_ylabel() == "[bar]"
    assert png.stat().st_size > 5000


@pytest.mark.parametrize("x", [[], ["--x", "t"]])
def test_without_x_and_y_every_signal_against_time(tmp_path, capsys, drawn, x):
    assert cli.main(["run", str(STEP), "-q", "--plot", str(tmp_path / "r.png"), *x]) == 0
    assert sorted(c[0] for c in drawn) == ["so", "tf", "tf_full"]
    assert drawn[0][3].figure.axes[-1].get_xlabel() == "t [s]"


@pytest.mark.parametrize("args, message", [
    (["--x", "so"], "--x chooses what --plot draws: give --plot FILE too"),
    (["--y", "so"], "--y chooses what --plot draws: give --plot FILE too"),
    (["--plot", "{tmp}/r.png", "--y", "sO"], "--y 'sO': not a logged signal of"),
    (["--plot", "{tmp}/r.png", "--x", "time"], "--x 'time': not a logged signal of"),
    (["--plot", "{tmp}/r.png", "--y", "so", "--y", "so"], "--y 'so': named twice"),
    (["--plot", "{tmp}/r.png", "--x", "so", "--y", "so"], "--x and --y name only 'so': nothing to plot against it"),
])
def test_refusals(tmp_path, capsys, args, message):
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    assert cli.main(["run", str(STEP), "-q", *args]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []
