"""What a result was made with: the tool's version and source, and the packages that move its last digits.

A calibration's or an optimisation's numbers depend, in their last digits, on the compiled integrator and the
linear algebra under it: the same data and netlist gave a fitted stiffness of 251.7 bar on one machine and
251.8 on another, with numba, numpy and scipy at other versions. A report that names those versions lets a
reader tell such a difference from a change in the model. The source is the git commit of the checkout the
tool runs from, marked ``-dirty`` when its tracked files differ from it (absent outside a git checkout).
"""

from __future__ import annotations

import platform
import subprocess
from functools import lru_cache
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

PACKAGES = ("vphs", "numpy", "scipy", "numba", "llvmlite", "pydantic", "networkx")
SOURCE = Path(__file__).resolve().parents[1]  # the checkout holding blocks/


@lru_cache(maxsize=1)
def environment() -> dict[str, str]:
    """{"python": "3.11.7", "vphs": "0.1.0", "numpy": ..., ..., "commit": "a2ea64d" or "a2ea64d-dirty"}: each
    package's installed version ("not installed" if it is not); "commit" only in a git checkout."""
    found = {"python": platform.python_version()}
    for name in PACKAGES:
        try:
            found[name] = version(name)
        except PackageNotFoundError:
            found[name] = "not installed"
    commit = _commit()
    if commit:
        found["commit"] = commit
    return found


def _commit() -> str:
    if not (SOURCE / ".git").exists():
        return ""
    try:
        done = subprocess.run(["git", "-C", str(SOURCE), "describe", "--always", "--dirty", "--abbrev=7"],
                              capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):  # no git on the machine: the versions still stand
        return ""
    return done.stdout.strip() if done.returncode == 0 else ""


def environment_line(env: dict[str, str] | None = None) -> str:
    """One line for a markdown report: 'Made with vphs 0.1.0 (commit a2ea64d), Python 3.11.7, numpy 2.4.6, ...',
    of this process's environment or of ``env`` (one a report recorded)."""
    env = environment() if env is None else env
    tool = f"vphs {env['vphs']}" + (f" (commit {env['commit']})" if "commit" in env else "")
    return "Made with " + ", ".join([tool, f"Python {env['python']}"]
                                    + [f"{name} {env.get(name, '?')}" for name in PACKAGES if name != "vphs"]) + "."
