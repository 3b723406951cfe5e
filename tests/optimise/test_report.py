"""The best run's plot labels what each cost term measured."""

from types import SimpleNamespace

import numpy as np

from blocks.optimise import report
from blocks.optimise.costs import Term


def legend_labels(monkeypatch, terms) -> list[str]:
    figures = []
    monkeypatch.setattr(report, "atomic_write_figure", lambda fig, path: figures.append(fig))
    t = np.linspace(0.0, 1.0, 11)
    signals = {"pA": 1e5 * (1 + t), "x": t, "x_ref": 0.9 * t}
    result = type("Result", (), {"t": t, "__getitem__": lambda self, key: signals[key]})()
    report._signals_plot(SimpleNamespace(terms=terms), {"nominal": result}, None, "title")
    return [text.get_text() for ax in figures[0].axes for text in ax.get_legend().get_texts()]


def test_a_largest_error_without_reference_is_labelled_by_its_signal(monkeypatch):
    """Review: max_abs of pA without a reference was labelled 'pA - 0'."""
    labels = legend_labels(monkeypatch, [
        Term("peak", "max_abs", "pA", scale=1e5, unit="bar"),
        Term("band", "max_abs", "pA", offset=2e5, scale=1e5, unit="bar"),
        Term("track", "max_abs", "x", reference="x_ref", scale=1e-3, unit="mm")])
    assert labels[0] == "pA" and labels[2] == "pA - 2 bar" and labels[4] == "x - x_ref"
