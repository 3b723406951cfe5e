"""fit.png shows the misfit (fault s23-5): its panels were scaled to the data's whole range, so a misfit of
0.3 bar on a 50 bar signal did not show (residuals.png did). Beneath each output's panel is now a panel of
its residuals, data - model, declared and final, in the channel's unit, with the band of one noise sigma,
on the same x axis. Checked on the figure object, with the fake calibration of test_report_review.py
(residuals of the declared model 2 sigma, of the final one 0.5 sigma; y1 in bar, sigma 0.2 bar; y2 in
l/min, sigma 0.6 l/min)."""

from __future__ import annotations

import numpy as np
import pytest

from test_report_review import _fake_calibration


def figure(monkeypatch, tmp_path, kind: str, runs: int):
    from blocks.calibrate import report

    drawn = {}
    monkeypatch.setattr(report, "atomic_write_figure", lambda fig, path: drawn.setdefault("fig", fig))
    cal = _fake_calibration(kind, runs)
    report.plot_fit(cal, tmp_path / "fit.png")
    return cal, drawn["fig"]


@pytest.mark.parametrize("kind, runs, columns", [("time", 1, 1), ("time", 5, 4), ("steady", 3, 1)])
def test_each_output_has_a_residual_panel_beneath_it_on_the_same_x_axis(monkeypatch, tmp_path, kind, runs, columns):
    _, fig = figure(monkeypatch, tmp_path, kind, runs)
    assert len(fig.axes) == 4 * columns  # two outputs, each a panel and its residuals' panel, per column
    grid = np.array(fig.axes).reshape(4, columns)  # rows: y1, y1's residuals, y2, y2's residuals
    for row, (name, unit, sigma) in enumerate((("y1", "bar", 0.2), ("y2", "l/min", 0.6))):
        panels, below = grid[2 * row], grid[2 * row + 1]
        assert panels[0].get_ylabel() == f"{name} [{unit}]"
        assert below[0].get_ylabel() == f"{name}: data - model [{unit}]"
        for top, bottom in zip(panels, below):
            assert top.get_shared_x_axes().joined(top, bottom)
            assert bottom.get_position().y1 <= top.get_position().y0 + 1e-9  # beneath it
            drawn = [line.get_ydata() for line in bottom.get_lines() if len(line.get_ydata()) > 2]
            # data - model = -(residual in sigmas)*sigma: -2 sigma declared, -0.5 sigma final, at every point
            assert any(np.allclose(y, -2.0 * sigma) for y in drawn), drawn
            assert any(np.allclose(y, -0.5 * sigma) for y in drawn), drawn
            low, high = bottom.get_ylim()
            assert -3 * sigma < low < -2 * sigma and sigma <= high < 3 * sigma  # the misfit's scale, with the band
            band = bottom.collections[0].get_paths()[0].vertices[:, 1]
            assert np.isclose(band.min(), -sigma) and np.isclose(band.max(), sigma)
