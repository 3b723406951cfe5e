"""Errors that reach the user as one line naming the file, the place in it and what is wrong."""

from __future__ import annotations


class VphsError(Exception):
    """Base of every user-facing error: the CLI prints ``str(error)`` and exits with code 2."""


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
        return f"{where}: {self.message}".replace("\r", "\\r").replace("\n", "\\n")


class SimulationError(VphsError):
    """The solver could not finish: says when, which states failed and which blocks own them."""
