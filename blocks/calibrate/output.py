"""The output folder of a calibration: a run's files replace the previous run's whole, or not at all.

A run writes many files (each round's screening, candidate and augmented netlists, the exchange and
elimination netlists, the augmented experiment, the report and its plots), each atomically; but not the set.
A second run into the same folder used to leave the first run's round files beside its own report (an
augmented netlist with an effect the new report says was not found), and an interrupted run left a new
report.json beside the old report.md. So, around a run (:func:`replacing`):

  - the entries of the folder that a calibration writes (:data:`OWNED`) are moved aside into
    ``<folder>/.previous`` (renames within one folder: nothing is copied); the run writes into a folder
    without them;
  - when the run and its report are written, ``.previous`` is deleted;
  - when the run fails or is interrupted, the entries it wrote are deleted and the previous ones moved back
    (a folder the run created is removed again);
  - a run killed outright leaves ``.previous`` behind: the next run moves it back first, as if the killed run
    had failed.

Anything else in the folder (a user's notes) is never moved or deleted.
"""

from __future__ import annotations

import re
import shutil
from contextlib import contextmanager
from pathlib import Path

from blocks.errors import VphsError

PREVIOUS = ".previous"
OWNED = re.compile(r"(report\.(json|md)|residuals\.png|latent_trace\.png|experiment_augmented\.yaml"
                   r"|exchange|elimination|round\d+)")


def owned(folder: Path) -> list[Path]:
    """The entries of ``folder`` that a calibration writes."""
    return sorted(p for p in folder.iterdir() if OWNED.fullmatch(p.name)) if folder.is_dir() else []


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    else:
        path.unlink()


def _restore(folder: Path) -> None:
    """Delete the owned entries of ``folder`` and move those in its ``.previous`` back."""
    aside = folder / PREVIOUS
    for path in owned(folder):
        _remove(path)
    if aside.is_dir():
        for path in aside.iterdir():
            path.rename(folder / path.name)
        aside.rmdir()


def _make(folder: Path) -> bool:
    """Create ``folder`` (and its parents); True if it did not exist. A file in the way is bad input."""
    if folder.is_dir():
        return False
    for parent in [folder, *folder.parents]:
        if parent.exists() and not parent.is_dir():
            raise VphsError(f"output folder {folder}: {parent} is a file, not a folder; give another folder (-o)")
    folder.mkdir(parents=True)
    return True


@contextmanager
def replacing(folder: Path):
    """Run the body with ``folder`` cleared of a previous calibration's entries; keep what the body wrote
    only if it ends normally (module docstring)."""
    folder = Path(folder)
    created = _make(folder)
    aside = folder / PREVIOUS
    if aside.is_dir():  # a run killed outright: its previous output is the last complete one
        _restore(folder)
    previous = owned(folder)
    if previous:
        aside.mkdir()
        for path in previous:
            path.rename(aside / path.name)
    try:
        yield folder
    except BaseException:
        _restore(folder)
        if created and not any(folder.iterdir()):
            folder.rmdir()
        raise
    if aside.is_dir():
        shutil.rmtree(aside)
