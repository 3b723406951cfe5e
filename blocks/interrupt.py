"""Ctrl-C during compiled code: noted by the command's handler, so that no interrupt is lost.

A SIGINT that arrives while numba runs a compiled call comes out of it as a SystemError ("returned a result
with an exception set", the KeyboardInterrupt as its cause), and one that arrives in a ctypes callback while
numba compiles is printed as "Exception ignored" and dropped: the run went on as if never interrupted
(found by a review of `vphs calibrate`: 3 of 30 Ctrl-Cs ended in "internal error", 1 was ignored).

:func:`handling` installs a handler that notes each SIGINT before raising KeyboardInterrupt as Python's
own does, and an unraisable-exception hook that takes a KeyboardInterrupt dropped in a callback silently
(noted, not printed as "Exception ignored ... Traceback"); :func:`check` raises it again where an interrupt
may have been swallowed (after each compiled integration and each compilation, and before any error a
command ends in: an interrupted compilation fails later with "no compiled object yet", found by a fuzzer);
:func:`caused_by_interrupt` tells a SystemError of an interrupted compiled call from a bug.

SIGTERM (``kill``, a batch system's time limit, a service manager) is handled the same way: it raised
nothing and killed the process outright, leaving a calibration's output folder half-written (round1/, an
augmented experiment) where Ctrl-C leaves nothing behind. Within :func:`handling` it raises
:class:`Terminated`, a KeyboardInterrupt, so that every command stops as on Ctrl-C (its partial output
undone) and says so, exiting 128 + 15 = 143. A SIGTERM the process was started ignoring stays ignored.

Once a command's output is complete and in place (:func:`finished`), a Ctrl-C or SIGTERM is ignored to the
end: there is nothing left to stop or undo, and an exit 130 would tell a script that the run failed. A
review found a Ctrl-C just after `vphs calibrate`'s last "wrote ..." line ending the process with 130 and
no message, its output whole: the signal came while the interpreter shut down, after the handlers had been
put back. For the `vphs` process (:func:`handling` with ``process=True``) the signals stay ignored after the
command returns, through the interpreter's exit; a caller in the same process (a test) gets its handlers
back.
"""

from __future__ import annotations

import signal
import sys
import threading
from contextlib import contextmanager

_noted: list[int] = []
_state = {"handling": False, "finished": False}


class Terminated(KeyboardInterrupt):
    """A SIGTERM, raised as an interrupt: the command stops as on Ctrl-C; the process exits 143, not 130."""


def as_raised(signum: int) -> KeyboardInterrupt:
    """The exception a noted signal is raised as: :class:`Terminated` for SIGTERM, else KeyboardInterrupt."""
    return Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()


def _note_and_raise(signum, frame):
    _noted.append(signum)
    raise as_raised(signum)


@contextmanager
def handling(process: bool = False):
    """Within: every SIGINT and SIGTERM is noted (main thread only; elsewhere signals cannot be handled);
    a SIGTERM ignored when the command started (``nohup``-like launchers, a parent's choice) stays ignored.
    On leaving, the previous handlers are put back, unless ``process`` (the command is the whole process)
    and the command :func:`finished`: then the signals stay ignored through the interpreter's exit."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _noted.clear()
    _state.update(handling=True, finished=False)
    previous = {number: signal.signal(number, _note_and_raise) for number in (signal.SIGINT, signal.SIGTERM)
                if signal.getsignal(number) is not signal.SIG_IGN or number == signal.SIGINT}
    previous_hook = sys.unraisablehook

    def hook(unraisable):
        if isinstance(unraisable.exc_value, KeyboardInterrupt):  # raised in a callback that could not pass it
            _noted.append(signal.SIGTERM if isinstance(unraisable.exc_value, Terminated) else signal.SIGINT)
        else:
            previous_hook(unraisable)

    sys.unraisablehook = hook
    try:
        yield
    finally:
        if not (process and _state["finished"]):
            for number, handler in previous.items():
                signal.signal(number, handler)
        sys.unraisablehook = previous_hook
        _noted.clear()
        _state.update(handling=False, finished=False)


def finished() -> None:
    """The command's output is complete and in place: from here on a SIGINT or SIGTERM is ignored (module
    docstring), and one noted before but not yet taken is dropped (what it would have stopped is done).
    Only within :func:`handling` (a command of the `vphs` process or of a test calling it), in the main
    thread: elsewhere the caller's handlers are not this module's to change."""
    if not _state["handling"] or threading.current_thread() is not threading.main_thread():
        return
    for number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(number, signal.SIG_IGN)
    _noted.clear()
    _state["finished"] = True


@contextmanager
def deferred():
    """Within: a SIGINT or SIGTERM whose handler is a Python function (Ctrl-C's KeyboardInterrupt,
    :func:`handling`'s, an optimisation job's SIGTERM) is noted, not handled; on leaving, the first one
    noted is handed to its handler, which raises as it would have. For a step that must not stop half-way:
    the renames that put a set of result files in place, the clean-up that restores a calibration's output
    folder after an interrupt (a second Ctrl-C there left it half-restored), an evaluation in a compiled
    integrator. A signal ignored or left to the system's default stays so; outside the main thread (no
    handlers there) the body just runs. Nested, the inner one hands a signal on to the outer one."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held = {number: handler for number in (signal.SIGINT, signal.SIGTERM)
            if callable(handler := signal.getsignal(number))}
    pending: list[int] = []
    for number in held:
        signal.signal(number, lambda signum, frame: pending.append(signum))
    try:
        yield
    finally:
        for number, handler in held.items():
            signal.signal(number, handler)
        if pending:  # delivered now, even if the step raised: KeyboardInterrupt (or Terminated) wins
            held[pending[0]](pending[0], None)


def check() -> None:
    """Raise KeyboardInterrupt (:class:`Terminated` for a SIGTERM) if a signal was noted: once interrupted, a
    command stops at the next check."""
    if _noted:
        raise as_raised(_noted[0])


def interrupt_of(exc: BaseException) -> KeyboardInterrupt | None:
    """The KeyboardInterrupt (or :class:`Terminated`) ``exc`` is, or was raised while handling; else None."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return exc
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return None


def caused_by_interrupt(exc: BaseException) -> bool:
    """Whether ``exc`` is, or was raised while handling, a KeyboardInterrupt."""
    return interrupt_of(exc) is not None


def exit_code(exc: KeyboardInterrupt) -> int:
    """128 + the signal's number, as a shell reports a process the signal ended: 143 for SIGTERM, else 130."""
    return 128 + (signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)


def stopped(exc: KeyboardInterrupt) -> str:
    """'terminated' (SIGTERM) or 'interrupted' (Ctrl-C), for the command's last line."""
    return "terminated" if isinstance(exc, Terminated) else "interrupted"
