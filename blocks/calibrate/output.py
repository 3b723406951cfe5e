"""The output folder of a calibration: a run's files replace the previous run's whole, or not at all.

A run writes many files (each round's screening, candidate and augmented netlists, the exchange and
elimination netlists, the augmented experiment, the report and its plots), each atomically; but not the set.
A second run into the same folder used to leave the first run's round files beside its own report (an
augmented netlist with an effect the new report says was not found), and an interrupted run left a new
report.json beside the old report.md. So, around a run (:func:`replacing`):

  - the entries of the folder that a calibration writes (:data:`OWNED`) are moved into ``.previous.partial``
    (renames within one folder: nothing is copied), which is renamed ``.previous`` once all are in; the run
    writes into a folder without them;
  - when the run and its report are written, the output is complete: a Ctrl-C or SIGTERM from then on is
    ignored (:func:`blocks.interrupt.finished`; it used to end the process with 130 and no message), and
    ``.previous`` is renamed ``.discard`` and deleted;
  - when the run fails or is interrupted, the entries it wrote are deleted and the previous ones moved back
    (a folder the run created is removed again); if it stops while the entries are being moved aside, they
    are moved back and nothing is deleted.

Each of these steps runs to its end before a Ctrl-C or SIGTERM is taken (:func:`blocks.interrupt.deferred`):
a second Ctrl-C while an interrupted run is being undone used to stop the undoing half-way, leaving the
folder with part of the unfinished run's entries and the previous output hidden in ``.previous``. Every
step leaves a state the next run can read, so a run killed outright (no chance to clean up) is undone
by the next one before it starts: a ``.discard`` is deleted (the run had finished); a ``.previous.partial``
is moved back whole (it stopped while moving aside: the folder holds the rest of the previous output); a
``.previous`` is restored (it stopped during the run: what the folder holds is that run's, unfinished).
Anything else in the folder (a user's notes) is never moved or deleted.
"""

from __future__ import annotations

import re
import shutil
from contextlib import contextmanager
from pathlib import Path

from blocks import interrupt
from blocks.errors import VphsError

PREVIOUS = ".previous"
MOVING = ".previous.partial"
DISCARD = ".discard"
OWNED = re.compile(r"(report\.(json|md)|residuals\.png|fit\.png|latent_trace\.png|experiment_augmented\.yaml"
                   r"|calibrated\.yaml|exchange|elimination|round\d+)")


def owned(folder: Path) -> list[Path]:
    """The entries of ``folder`` that a calibration writes."""
    return sorted(p for p in folder.iterdir() if OWNED.fullmatch(p.name)) if folder.is_dir() else []


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    else:
        path.unlink()


def _move_back(aside: Path, folder: Path) -> None:
    """Move every entry of ``aside`` back into ``folder`` and remove ``aside``."""
    for path in aside.iterdir():
        path.rename(folder / path.name)
    aside.rmdir()


def _restore(folder: Path) -> None:
    """Delete the owned entries of ``folder`` (a run's, unfinished) and move those in ``.previous`` back, by
    way of ``.previous.partial``: a restore cut short in the deleting is done again, in the moving back it is
    finished by moving the rest back (nothing deleted: what the folder then holds is the previous output)."""
    for path in owned(folder):
        _remove(path)
    if (folder / PREVIOUS).is_dir():
        (folder / PREVIOUS).rename(folder / MOVING)
        _move_back(folder / MOVING, folder)


def _recover(folder: Path) -> None:
    """Undo what a run killed outright left behind (module docstring)."""
    for name in (PREVIOUS, MOVING, DISCARD):
        path = folder / name
        if path.is_symlink() or (path.exists() and not path.is_dir()):
            raise VphsError(f"output folder {folder}: {path.name} is not a folder of vphs calibrate's; move it "
                            f"away or give another folder (-o)")
    if (folder / DISCARD).is_dir():
        shutil.rmtree(folder / DISCARD)
    if (folder / MOVING).is_dir():
        _move_back(folder / MOVING, folder)
    if (folder / PREVIOUS).is_dir():
        _restore(folder)


def _make(folder: Path) -> bool:
    """Create ``folder`` (and its parents); True if it did not exist. A file in the way, or a folder that
    cannot be created (no permission, a read-only or virtual file system), is bad input."""
    if folder.is_dir():
        return False
    for parent in [folder, *folder.parents]:
        if parent.exists() and not parent.is_dir():
            raise VphsError(f"output folder {folder}: {parent} is a file, not a folder; give another folder (-o)")
    try:
        folder.mkdir(parents=True)
    except OSError as exc:
        raise VphsError(f"output folder '{folder}': cannot be created ({exc.strerror or exc}); give another folder "
                        f"(-o)") from None
    return True


def check_creatable(folder: Path) -> None:
    """Before any work: an error (:func:`_make`'s) if ``folder`` cannot be created; the folders made to find
    out are removed again (a run that then fails on its input leaves nothing behind)."""
    folder = Path(folder)
    missing = [p for p in [folder, *folder.parents] if not p.exists()]
    if not missing:
        return
    _make(folder)
    for path in missing:  # the deepest first
        try:
            path.rmdir()
        except OSError:
            break


@contextmanager
def replacing(folder: Path):
    """Run the body with ``folder`` cleared of a previous calibration's entries; keep what the body wrote
    only if it ends normally (module docstring). Undoing a run, and discarding the previous output after
    one, runs to its end before a further Ctrl-C or SIGTERM is taken."""
    folder = Path(folder)
    created = _make(folder)
    _recover(folder)
    started = False
    try:
        _move_aside(folder)
        started = True
        yield folder
    except BaseException:
        with interrupt.deferred():
            _undo(folder, started)
            if created and folder.is_dir() and not any(folder.iterdir()):
                folder.rmdir()
        raise
    interrupt.finished()  # the run's output is complete and in place: nothing is left to stop or undo
    with interrupt.deferred():
        if (folder / PREVIOUS).is_dir():
            (folder / PREVIOUS).rename(folder / DISCARD)
            shutil.rmtree(folder / DISCARD)


def _move_aside(folder: Path) -> None:
    """The owned entries of ``folder`` moved into ``.previous.partial``, which is then renamed ``.previous``."""
    previous = owned(folder)
    if previous:
        moving = folder / MOVING
        moving.mkdir()
        for path in previous:
            path.rename(moving / path.name)
        moving.rename(folder / PREVIOUS)


def _undo(folder: Path, started: bool) -> None:
    """``folder`` put back as it was before a run that failed or was interrupted: stopped while the previous
    entries were being moved aside, those moved are moved back (nothing deleted: the folder holds the rest of
    the previous output); once they all were (``.previous``) or the run ``started``, the entries in the folder
    are the run's: deleted, and the previous ones restored."""
    if (folder / MOVING).is_dir():
        _move_back(folder / MOVING, folder)
    elif started or (folder / PREVIOUS).is_dir():
        _restore(folder)
