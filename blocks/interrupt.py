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
"""

from __future__ import annotations

import signal
import sys
import threading
from contextlib import contextmanager

_noted: list[int] = []


def _note_and_raise(signum, frame):
    _noted.append(signum)
    raise KeyboardInterrupt


@contextmanager
def handling():
    """Within: every SIGINT is noted (main thread only; elsewhere signals cannot be handled)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _noted.clear()
    previous = signal.signal(signal.SIGINT, _note_and_raise)
    previous_hook = sys.unraisablehook

    def hook(unraisable):
        if isinstance(unraisable.exc_value, KeyboardInterrupt):
            _noted.append(signal.SIGINT)  # raised in a callback that could not pass it on: noted, not printed
        else:
            previous_hook(unraisable)

    sys.unraisablehook = hook
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        sys.unraisablehook = previous_hook
        _noted.clear()


def check() -> None:
    """Raise KeyboardInterrupt if a SIGINT was noted: once interrupted, a command stops at the next check."""
    if _noted:
        raise KeyboardInterrupt


def raises_interrupt(handler) -> bool:
    """Whether ``handler`` is one that raises KeyboardInterrupt: Python's own, or :func:`handling`'s."""
    return handler in (signal.default_int_handler, _note_and_raise)


def caused_by_interrupt(exc: BaseException) -> bool:
    """Whether ``exc`` is, or was raised while handling, a KeyboardInterrupt."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False
