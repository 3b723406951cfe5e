"""Steady points from several data files: joined in order, each row remembers its file, units converted per
file, held out a file at a time; splitting one file in two changes nothing in the fit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

import cli
from blocks.calibrate.data import load_data
from blocks.calibrate.experiment import load_experiment
from blocks.calibrate.fit import fit
from blocks.calibrate.heldout import make_folds
from blocks.calibrate.model import Model
from blocks.circuit import Circuit

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "netlists" / "experiments" / "relief_rig_steady.yaml"
PSI = 6894.757293168


def split(tmp_path: Path) -> tuple[Path, Path]:
    """The example experiment as it is, and with its data in two files (setting 3 alone, pressures in psi)."""
    spec = yaml.safe_load(EXAMPLE.read_text())
    source = (EXAMPLE.parent / spec["data"]).resolve()
    lines = [ln for ln in source.read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    header, rows = lines[0], [ln.split(",") for ln in lines[1:]]
    names = [h.split(" [")[0] for h in header.split(",")]
    group = names.index(spec["group"])
    a = [",".join(r) for r in rows if r[group] != "3"]
    b_header = ",".join(h.replace("[bar]", "[psi]") for h in header.split(","))
    b = []
    for r in rows:
        if r[group] == "3":
            b.append(",".join(f"{float(v) * 1e5 / PSI:.9f}" if "[bar]" in h else v for v, h in zip(r, header.split(","))))
    (tmp_path / "a.csv").write_text("\n".join([header] + a) + "\n")
    (tmp_path / "b.csv").write_text("\n".join([b_header] + b) + "\n")
    whole = dict(spec, netlist=str((EXAMPLE.parent / spec["netlist"]).resolve()), data=str(source))
    parts = dict(whole, data=["a.csv", "b.csv"], heldout={"scheme": "leave_one_experiment_out"})
    (tmp_path / "whole.yaml").write_text(yaml.safe_dump(whole, sort_keys=False))
    (tmp_path / "parts.yaml").write_text(yaml.safe_dump(parts, sort_keys=False))
    return tmp_path / "whole.yaml", tmp_path / "parts.yaml"


def test_two_files_are_the_one_file_split(tmp_path):
    whole_file, parts_file = split(tmp_path)
    whole, parts = load_experiment(whole_file), load_experiment(parts_file)
    dw, dp = load_data(whole), load_data(parts)
    order = np.argsort([lb == "3" for lb in dw.labels], kind="stable")  # setting 3 moved to the end
    assert dp.n == dw.n and dp.labels == [dw.labels[k] for k in order]
    for name in dw.measured:
        assert dp.measured[name] == pytest.approx(dw.measured[name][order], rel=1e-9)
    assert dp.sources == ["a.csv"] * int(np.sum(np.array(dw.labels) != "3")) + ["b.csv"] * int(np.sum(np.array(dw.labels) == "3"))
    scheme, folds = make_folds(Model(Circuit.from_file(parts.netlist), parts, dp, list(parts.free)), parts.spec.heldout)
    assert scheme == "leave one experiment out" and [name for name, _ in folds] == ["a.csv", "b.csv"]
    assert sorted(np.concatenate([idx for _, idx in folds]).tolist()) == list(range(dp.n))
    # the same points, the same fit
    circuit = Circuit.from_file(whole.netlist)
    results = []
    for exp, data in ((whole, dw), (parts, dp)):
        model = Model(circuit, exp, data, list(exp.free))
        results.append(fit(model, model.initial(), np.ones(model.layout.size, dtype=bool), max_nfev=30))
    assert results[1].chi2 == pytest.approx(results[0].chi2, rel=1e-6)
    assert results[1].x[: len(whole.free)] == pytest.approx(results[0].x[: len(whole.free)], rel=1e-6)


def test_a_missing_second_file_and_a_time_series_among_several_are_located_errors(tmp_path, capsys):
    _, parts_file = split(tmp_path)
    spec = yaml.safe_load(parts_file.read_text())
    spec["data"] = ["a.csv", "nowhere.csv"]
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(spec, sort_keys=False))
    assert cli.main(["calibrate", str(bad), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "data: file not found: nowhere.csv" in err and f"{bad}:" in err
    spec["data"] = ["a.csv", "./a.csv"]
    bad.write_text(yaml.safe_dump(spec, sort_keys=False))
    assert cli.main(["calibrate", str(bad), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "./a.csv is listed twice" in err
    (tmp_path / "steady.csv").write_text("Q [l/min],p1 [bar],p2 [bar],p3 [bar]\n10,2,3,4\n20,2,3,4\n")
    (tmp_path / "series.csv").write_text("t [s],Q [l/min],p1 [bar],p2 [bar],p3 [bar]\n0,1,2,3,4\n0.1,1,2,3,4\n")
    spec["data"] = ["steady.csv", "series.csv"]
    spec.pop("group")
    bad.write_text(yaml.safe_dump(spec, sort_keys=False))
    assert cli.main(["calibrate", str(bad), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "series.csv" in err and not (tmp_path / "out").exists()


def test_an_effect_found_in_several_files_writes_an_experiment_that_loads(tmp_path):
    """The example's data carry a planted flow force (relief.c_ff = 0.3): found from the two files, and the
    augmented experiment lists both files and loads."""
    from blocks.calibrate.run import calibrate

    _, parts_file = split(tmp_path)
    spec = yaml.safe_load(parts_file.read_text())
    spec["trace"] = {"only": ["flow_force"], "rounds": 1, "top": 1}
    parts_file.write_text(yaml.safe_dump(spec, sort_keys=False))
    cal = calibrate(parts_file, tmp_path / "out", with_heldout=False)
    assert [a[0] for a in cal.accepted] == ["flow_force@relief"]
    written = yaml.safe_load((tmp_path / "out" / "experiment_augmented.yaml").read_text())
    assert [Path(f).name for f in written["data"]] == ["a.csv", "b.csv"]
    again = load_experiment(tmp_path / "out" / "experiment_augmented.yaml")
    assert [f.name for f in again.data_files] == ["a.csv", "b.csv"] and load_data(again).n == cal.data.n


def test_kfold_over_experiments_leaves_whole_files_out_together(tmp_path):
    """Four files (one per crack setting, setting 3 in two halves) dealt into two folds: every point held out
    exactly once, no file split across folds; k >= the number of files is leave one experiment out."""
    whole_file, _ = split(tmp_path)
    whole = load_experiment(whole_file)
    dw = load_data(whole)
    source = Path(whole.spec.data if isinstance(whole.spec.data, str) else whole.spec.data[0])
    lines = [ln for ln in source.read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    header, rows = lines[0], lines[1:]
    group = [h.split(" [")[0] for h in header.split(",")].index(whole.spec.group)
    files = {"s1.csv": [r for r in rows if r.split(",")[group] == "1"],
             "s2.csv": [r for r in rows if r.split(",")[group] == "2"]}
    third = [r for r in rows if r.split(",")[group] == "3"]
    files["s3a.csv"], files["s3b.csv"] = third[: len(third) // 2], third[len(third) // 2:]
    for name, body in files.items():
        (tmp_path / name).write_text("\n".join([header] + body) + "\n")
    spec = yaml.safe_load(whole_file.read_text())
    for k, expect in ((2, "2-fold over experiments"), (4, "leave one experiment out"),
                      (9, "leave one experiment out (k = 9 cut to the 4 data files)")):
        spec.update(data=list(files), heldout={"scheme": "kfold_experiments", "k": k, "seed": 3})
        path = tmp_path / f"k{k}.yaml"
        path.write_text(yaml.safe_dump(spec, sort_keys=False))
        exp = load_experiment(path)
        data = load_data(exp)
        assert data.n == dw.n
        scheme, folds = make_folds(Model(Circuit.from_file(exp.netlist), exp, data, list(exp.free)), exp.spec.heldout)
        assert scheme == expect and len(folds) == min(k, len(files))
        held = np.concatenate([idx for _, idx in folds])
        assert sorted(held.tolist()) == list(range(data.n))  # every point once
        sources = np.array(data.sources)
        for name, idx in folds:
            members = set(name.split(" + "))
            assert set(sources[idx]) == members  # the fold is its files, whole
            assert len(idx) == sum(len(files[m]) for m in members)
