"""Where the thesis's measured data and result tables are (``mcv_vf250_*.csv``, ``thesis_*.csv``).

They are not in the repository: they sit in ``../shared/data`` beside it, or in the folder the environment
variable ``VPHS_THESIS_DATA`` names (a clone made elsewhere). The rig, the studies and the benchmarks read
them through :data:`DATA` and refuse a missing file in one line (:func:`require`)."""

from __future__ import annotations

import os
from pathlib import Path

from blocks.errors import VphsError

ENV = "VPHS_THESIS_DATA"
ROOT = Path(__file__).resolve().parents[1]
DATA = Path(os.environ[ENV]) if os.environ.get(ENV) else ROOT.parent / "shared" / "data"


class ThesisDataMissing(VphsError):
    """A thesis data file that is not where :data:`DATA` says."""


def require(*paths: Path) -> None:
    """Refuse, in one line, the first of ``paths`` that is not a file, saying where the folder was looked for
    and how to give another."""
    for path in paths:
        if not Path(path).is_file():
            where = f"{ENV} = {os.environ[ENV]}" if os.environ.get(ENV) else \
                "../shared/data beside the repository"
            raise ThesisDataMissing(f"{path}: the thesis's data file {Path(path).name} is not there (its folder is "
                                    f"taken from {where}; set {ENV} to the folder that holds it)")


def run(main) -> int:
    """``main()`` of a study or rig command, its user-facing errors (a missing data file, a bad CSV) said in
    one line with exit 2, as the ``vphs`` command says them, not as a traceback."""
    import sys

    try:
        return main()
    except VphsError as exc:
        print(f"vphs: {exc}", file=sys.stderr)
        return 2
