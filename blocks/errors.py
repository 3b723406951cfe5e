"""Errors that reach the user as one line naming the file, the place in it and what is wrong."""

from __future__ import annotations

import os
import re

SHOWN_VALUE = 80
"""At most this many characters of a name or value the user wrote are echoed in a message (then '…')."""
_LONG_TOKEN = 200  # a run without spaces longer than this is a value too, quoted or not
_LONG_MESSAGE = 2000
_QUOTED = re.compile(r"(?<!\w)(['\"])((?:(?!\1).){%d,})\1(?!\w)" % (SHOWN_VALUE + 1), re.DOTALL)
_TOKEN = re.compile(r"\S{%d,}" % (_LONG_TOKEN + 1))


def shorten_values(message: str) -> str:
    """``message`` with each long name or value it quotes cut to :data:`SHOWN_VALUE` characters and an
    ellipsis ('éééé…'): a 200,000-character preset name is not repeated in full in a one-line error.

    The one place messages are bounded (every :class:`VphsError` and the CLI's error line pass through it),
    so that the code building a message may quote what it was given as it stands. Quoted text ('...' or
    "...", the quote not inside a word, so that "the netlist's" opens nothing) is cut; so is any run of more
    than 200 characters without a space (a value echoed unquoted), keeping its end too. A path of this
    machine (one that exists, or whose folder does: a file to write) is shown whole. A message still longer
    than 2000 characters keeps its start and its end (which says what to do), joined by ' … '."""
    if len(message) <= SHOWN_VALUE:
        return message

    def quoted(m: re.Match) -> str:
        return m[0] if _is_path(m[2]) else f"{m[1]}{m[2][:SHOWN_VALUE]}…{m[1]}"

    def token(m: re.Match) -> str:
        place = re.sub(r"(?::\d+)*[:,;)]*$", "", m[0].lstrip("'\"("))  # 'file.yaml:3:7:' -> file.yaml
        return m[0] if _is_path(place) else f"{m[0][:SHOWN_VALUE - 20]}…{m[0][-20:]}"

    message = _QUOTED.sub(quoted, message)
    message = _TOKEN.sub(token, message)
    if len(message) > _LONG_MESSAGE:
        message = message[:_LONG_MESSAGE // 2] + " … " + message[-_LONG_MESSAGE // 4:]
    return message


def _is_path(text: str) -> bool:
    """Whether ``text`` names a file or folder of this machine, or one in an existing folder."""
    if len(text) > 4096 or "/" not in text and os.sep not in text:
        return False
    try:
        return os.path.lexists(text) or os.path.isdir(os.path.dirname(text))
    except (OSError, ValueError):  # a name too long, a NUL byte
        return False


class VphsError(Exception):
    """Base of every user-facing error: the CLI prints ``str(error)`` and exits with code 2."""

    def __str__(self) -> str:
        return shorten_values(super().__str__())


class NetlistError(VphsError):
    """A problem in a netlist (or job, or experiment) file, located by line and column where known."""

    def __init__(self, file: str, message: str, line: int | None = None, column: int | None = None):
        self.file, self.message, self.line, self.column = file, message, line, column
        super().__init__(str(self))

    def __str__(self) -> str:
        where = self.file
        if self.line is not None:
            where += f":{self.line}"
            if self.column is not None:
                where += f":{self.column}"
        # one line whatever the file held: a value's text quoted in the message may contain line breaks
        message = shorten_values(self.message).replace("\r", "\\r").replace("\n", "\\n")
        return f"{where}: {message}"


class SimulationError(VphsError):
    """The solver could not finish: says when, which states failed and which blocks own them."""
