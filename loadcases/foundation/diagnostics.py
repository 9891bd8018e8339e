"""Input diagnostics as data: every problem found, with file, line, column and key.

Only `cli/` formats them for people (gcc style, sorted by file and line).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from loadcases.foundation.clip import clip, clip_quotes, visible

__all__ = ["SHOWN_RUNS", "Diagnostic", "InputError", "format_diagnostic", "sort_diagnostics"]

Severity = Literal["error", "warning"]
SHOWN_RUNS = 5  # a set's runs a message names (`loads validate`'s problems, `loads run`'s footer)


@dataclass(frozen=True)
class Diagnostic:
    """One problem in an input file.

    `line` and `column` are 1-based (0 when unknown); `key` is the dotted path of the
    offending key (`joints.hinge.bodies[1]`); `hint` is an optional fix suggestion.
    """

    file: str
    line: int
    column: int
    key: str
    message: str
    severity: Severity = "error"
    hint: str | None = None

    def format(self) -> str:
        """gcc-style text: `file:line:col: error: key: message` (+ a `hint:` line). Input is
        quoted, never in full, and its hidden characters (a line break, U+202E) are shown
        as escapes (`\\n`, `\\u202e`): each line is one line, read as written."""
        where = visible(f"{self.file}:{self.line}:{self.column}")
        key = visible(clip(self.key)) + ": " if self.key else ""
        head = f"{where}: {self.severity}: {key}{visible(clip_quotes(self.message))}"
        if self.hint is None:
            return head
        return f"{head}\n{where}: hint: {visible(clip_quotes(self.hint))}"

    def keyed_message(self) -> str:
        """`key: message` (the message alone without a key), without the place: how a run's
        summary file and its status lines give the warnings of the input (hidden characters
        shown as escapes)."""
        return visible(f"{self.key}: {self.message}" if self.key else self.message)


def format_diagnostic(diagnostic: Diagnostic) -> str:
    """Text of one diagnostic, as `cli/` prints it."""
    return diagnostic.format()


def sort_diagnostics(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """Diagnostics ordered by file, line, column (errors before warnings at one place)."""
    return sorted(diagnostics, key=lambda d: (d.file, d.line, d.column, d.severity != "error"))


@dataclass
class InputError(Exception):
    """Raised by the load-case layer when input is invalid; carries every diagnostic found."""

    diagnostics: list[Diagnostic] = field(default_factory=list)

    def __str__(self) -> str:
        return "\n".join(d.format() for d in sort_diagnostics(self.diagnostics))
