"""The rig and the studies find the thesis's data beside the repository or where VPHS_THESIS_DATA says, and
refuse a missing file in one line with exit 2 (a user review: in a clone made elsewhere,
`python -m vphs_blocks.rig` ended in a traceback)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run_rig(env_folder: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "VPHS_THESIS_DATA": str(env_folder)}
    return subprocess.run([sys.executable, "-m", "vphs_blocks.rig", "--skip-crack", "--skip-step", "-o",
                           str(env_folder / "out.csv")], cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=600)


def test_a_missing_data_folder_is_one_line_naming_the_variable(tmp_path):
    done = run_rig(tmp_path)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip() == (f"vphs: {tmp_path / 'mcv_vf250_multistep.csv'}: the thesis's data file "
                                   f"mcv_vf250_multistep.csv is not there (its folder is taken from "
                                   f"VPHS_THESIS_DATA = {tmp_path}; set VPHS_THESIS_DATA to the folder that holds it)")
    assert not (tmp_path / "out.csv").exists()


def test_the_folder_the_variable_names_is_read(tmp_path):
    """The three files the rig reads, copied elsewhere: the rig runs from there (the measured p1 RMSE of the
    multistep points with the flow force, 2.22 bar, as README gives it)."""
    shared = ROOT.parent / "shared" / "data"
    for name in ("mcv_vf250_multistep.csv", "mcv_vf250_crack.csv", "thesis_sim_multistep.csv"):
        (tmp_path / name).write_bytes((shared / name).read_bytes())
    done = run_rig(tmp_path)
    assert done.returncode == 0, done.stderr
    assert "p1: RMSE 2.22 bar" in done.stdout
