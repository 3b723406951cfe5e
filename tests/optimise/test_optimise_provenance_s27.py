"""Reports name what they were made with (blocks.provenance): the versions of the packages that move a result's
last digits, checked against each package's own __version__, and the checkout's commit, checked against git.
A fitted value moved in its 4th digit between two machines (251.7 -> 251.8 bar) with nothing else changed."""

import json
import subprocess
import sys
from pathlib import Path

import llvmlite
import networkx
import numba
import numpy
import pydantic
import scipy

import cli
from blocks import provenance
from tests.optimise.test_units_shown import write_job

ROOT = Path(__file__).resolve().parents[2]


def test_the_versions_are_the_installed_packages_own():
    env = provenance.environment()
    assert env["python"] == ".".join(map(str, sys.version_info[:3]))
    for name, module in (("numpy", numpy), ("scipy", scipy), ("numba", numba), ("llvmlite", llvmlite),
                         ("networkx", networkx)):
        assert env[name] == module.__version__, name
    assert env["pydantic"] == pydantic.VERSION


def test_the_commit_is_the_checkouts_head_marked_when_its_files_differ():
    if not (ROOT / ".git").exists():
        return  # outside a git checkout there is no commit to name, and none is given
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True, text=True).stdout
    dirty = subprocess.run(["git", "-C", str(ROOT), "diff", "--quiet", "HEAD"]).returncode != 0
    commit = provenance.environment()["commit"]
    assert head.startswith(commit.removesuffix("-dirty")) and len(commit.removesuffix("-dirty")) >= 7
    assert commit.endswith("-dirty") == dirty


def test_the_line_names_every_package_and_its_version():
    env, line = provenance.environment(), provenance.environment_line()
    assert line.startswith(f"Made with vphs {env['vphs']}") and f"Python {env['python']}" in line
    for name in provenance.PACKAGES[1:]:
        assert f"{name} {env[name]}" in line


def test_an_optimisation_and_a_sweep_report_say_it(tmp_path):
    path = write_job(tmp_path)
    assert cli.main(["optimise", str(path), "--workers", "1", "-q"]) == 0
    assert f"- {provenance.environment_line()}" in (tmp_path / "out" / "report.md").read_text()
    assert json.loads((tmp_path / "out" / "best.json").read_text())["environment"] == provenance.environment()
    assert cli.main(["sweep", str(path), "--workers", "1", "-q"]) == 0
    assert f"- {provenance.environment_line()}" in (tmp_path / "out" / "sweep" / "report.md").read_text()


def test_a_recorded_environment_is_said_as_recorded_not_as_this_process_has_it():
    """A page written later from a report (the real-data study) states the report's environment: the line is
    built from the dict given, a package the report did not record shown as '?'."""
    recorded = {"python": "3.11.2", "vphs": "0.1.0", "numpy": "1.26.4", "scipy": "1.11.4", "numba": "0.59.0",
                "llvmlite": "0.42.0", "pydantic": "2.5.3", "commit": "0123abc-dirty"}
    assert provenance.environment_line(recorded) == (
        "Made with vphs 0.1.0 (commit 0123abc-dirty), Python 3.11.2, numpy 1.26.4, scipy 1.11.4, numba 0.59.0, "
        "llvmlite 0.42.0, pydantic 2.5.3, networkx ?.")
