"""An expression given from outside the netlist (``--set``, a job's ``set:``, an experiment's overrides) that
reads its own name through another of the netlist's names is refused (blocks/netlist/parameters.py,
``given_values``). Found by session 24's review: ``--set 'w0=sys.wn/3'`` with ``sys.wn = 2*w0`` was taken,
read sys.wn = 10 rad/s, and ran with sys.wn = 6.67 rad/s, which then followed the value given. Reading the
own name directly (``w0*2``: the netlist's value, doubled) is still taken, as is setting the other name.
"""

from __future__ import annotations

import cli

NETLIST = """\
parameters:
  w0: "5 rad/s"
components:
  one: {type: constant, params: {value: 1.0}}
  sys: {type: second_order, params: {k: 1, wn: "2*w0", zeta: 0.35}}
nets:
  u: [one.y, sys.u]
outputs:
  y: sys.y
simulation: {t_end: "0.1 s", dt_out: "10 ms"}
"""


def run(tmp_path, capsys, setting: str) -> tuple[int, str]:
    path = tmp_path / "sys.yaml"
    path.write_text(NETLIST)
    code = cli.main(["run", str(path), "-o", str(tmp_path / "out.csv"), "-q", "--set", setting])
    return code, capsys.readouterr().err.strip()


def test_reading_the_own_name_through_another_is_refused(tmp_path, capsys):
    code, err = run(tmp_path, capsys, "w0=sys.wn/3")
    assert code == 2 and len(err.splitlines()) == 1
    assert err == ("vphs: --set 'w0=sys.wn/3': 'sys.wn/3' reads sys.wn, which reads w0, the name it sets: sys.wn "
                   "would follow the value given, not the one read")


def test_reading_the_own_name_directly_or_setting_the_other_is_taken(tmp_path, capsys):
    assert run(tmp_path, capsys, "w0=w0*2") == (0, "")
    assert run(tmp_path, capsys, "sys.wn=w0*3") == (0, "")
