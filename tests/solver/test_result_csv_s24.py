"""A result's CSV is written a block of rows at a time (blocks/result.py, ``Result.write_csv_into``).

Found by the memory review (session 24): `vphs run -o` built the whole CSV as text before writing it (a
stacked copy of the table, the text, a copy of it, its bytes): 6.4 times the bare data at 300 s of the
drive line. The file is the same; what is held at once is one block of rows.
"""

from __future__ import annotations

import io

import numpy as np

import blocks.result as result_module
import cli
from blocks.result import Result


def _result(samples: int) -> Result:
    t = np.linspace(0.0, 1.0, samples)
    values = np.column_stack([1e5 * (1.0 + np.sin(t)), np.cos(3.0 * t) / 60000.0])
    return Result(file="x.yaml", t=t, names=["p", "q"], units=["Pa", "m^3/s"], display_units=["bar", "l/min"],
                  values=values, states=np.zeros((samples, 0)), state_names=[], stats={}, seconds=0.0)


def _expected(r: Result) -> str:
    rows = ["t [s],p [bar],q [l/min]"] + [f"{a:.10g},{b / 1e5:.10g},{c * 60000.0:.10g}"
                                            for a, b, c in zip(r.t, r.values[:, 0], r.values[:, 1])]
    return "\n".join(rows) + "\n"


class _Counting(io.StringIO):
    def __init__(self):
        super().__init__()
        self.largest = 0

    def write(self, text):
        self.largest = max(self.largest, len(text))
        return super().write(text)


def test_the_csv_is_the_same_and_written_a_block_at_a_time(monkeypatch):
    monkeypatch.setattr(result_module, "CSV_ROWS", 100)
    r = _result(1050)
    stream = _Counting()
    r.write_csv_into(stream)
    assert stream.getvalue() == _expected(r) == r.to_csv_text()
    assert stream.largest < 0.2 * len(stream.getvalue())  # no write of the whole table at once


def test_vphs_run_writes_its_csv_file_without_the_whole_text(tmp_path, monkeypatch):
    netlist = tmp_path / "n.yaml"
    netlist.write_text("""\
components:
  c: {type: constant, params: {value: 2}}
  g: {type: gain, params: {k: 3}}
nets:
  u: [c.y, g.u]
  y: [g.y]
outputs:
  y: y
simulation: {t_end: "1 s", dt_out: "1 ms"}
""")

    def refused(self):
        raise AssertionError("the whole CSV was built as text")

    monkeypatch.setattr(Result, "to_csv_text", refused)
    out = tmp_path / "out.csv"
    assert cli.main(["run", str(netlist), "-o", str(out), "-q"]) == 0
    lines = out.read_text().splitlines()
    assert lines[0] == "t [s],y [SI]" and len(lines) == 1002 and lines[-1] == "1,6"
    assert cli.main(["run", str(netlist), "-o", str(tmp_path / "o2.csv"), "--plot", str(tmp_path / "p.png"), "-q"]) == 0
    assert (tmp_path / "o2.csv").read_text() == out.read_text()
