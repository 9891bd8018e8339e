"""Input text quoted in messages is cut to at most 80 characters: a message stays one
readable line whatever a file holds (a 10 kB key, a pasted table in a value). Characters
that a terminal, a spreadsheet or a browser would not show as written (control
characters such as a line break or NUL, bidirectional controls such as U+202E, zero-width
characters) are found by `hidden_character` and written as escapes by `visible`; inside
`plain_text_plots()` matplotlib shows a `$` of a name as written (no math text, whose
parser fails on `a$^$b`), and `plain_log_ticks` labels log axes in plain numbers there."""

from __future__ import annotations

import contextlib
import re
import unicodedata
from collections.abc import Iterable, Iterator
from typing import Any

__all__ = [
    "QUOTE_LIMIT",
    "clip",
    "clip_quotes",
    "describe_character",
    "hidden_character",
    "plain_log_ticks",
    "plain_text_plots",
    "visible",
    "visible_fields",
]

QUOTE_LIMIT = 80  # characters of input a message quotes at most
_QUOTED = re.compile(rf"'([^']{{{QUOTE_LIMIT + 1},}})'")
# Unicode categories of hidden characters: controls (C0, DEL, C1), format characters (the
# bidirectional controls U+202A-U+202E and U+2066-U+2069, U+200E, U+200F, U+061C, zero-width
# characters, the byte-order mark), line and paragraph separators.
_HIDDEN_CATEGORIES = frozenset({"Cc", "Cf", "Zl", "Zp"})
_ASCII_CONTROL = re.compile(r"[\x00-\x1f\x7f]")
_NAMES = {"\n": "a line break", "\r": "a carriage return", "\t": "a tab"}


def clip(text: str, limit: int = QUOTE_LIMIT) -> str:
    """`text` cut to `limit` characters, ending with `...` when it was longer."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def clip_quotes(message: str) -> str:
    """`message` with every single-quoted part longer than the limit clipped."""
    return _QUOTED.sub(lambda match: f"'{clip(match.group(1))}'", message)


def _hidden(char: str) -> bool:
    return unicodedata.category(char) in _HIDDEN_CATEGORIES


def hidden_character(text: str) -> str | None:
    """The first hidden character of `text` (see the module), or None."""
    return next((char for char in text if _hidden(char)), None)


def describe_character(char: str) -> str:
    """`a tab (U+0009)`, `a control character (U+0007)`, `a right-to-left override
    (U+202E)`, `a no-break space (U+00A0)`."""
    code = f"U+{ord(char):04X}"
    if char in _NAMES:
        return f"{_NAMES[char]} ({code})"
    name = unicodedata.name(char, "")
    if not name or unicodedata.category(char) == "Cc":
        return f"a control character ({code})"
    article = "an" if name[0] in "AEIOU" else "a"
    return f"{article} {name.lower()} ({code})"


_ESCAPES = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def _escape(char: str) -> str:
    if char in _ESCAPES:
        return _ESCAPES[char]
    code = ord(char)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def visible(text: str) -> str:
    """`text` with each hidden character written as a Python-style escape (`\\x07`,
    `\\u202e`): what it holds can be seen, and it cannot reorder or break what follows."""
    if text.isascii() and not _ASCII_CONTROL.search(text):
        return text
    return "".join(_escape(char) if _hidden(char) else char for char in text)


def visible_fields(row: Iterable[object]) -> list[object]:
    """A CSV row with its text fields `visible`: a name or message from a file, written
    into a CSV file, is one line read as written (a line break in a run name would split
    its row for any reader that is not a CSV parser)."""
    return [visible(value) if isinstance(value, str) else value for value in row]


@contextlib.contextmanager
def plain_text_plots() -> Iterator[None]:
    """Within the block (or the function it decorates), matplotlib texts made are plain
    text: `$` in a case, run or body name is a dollar sign, not the start of math text."""
    import matplotlib  # only plotting code enters here

    with matplotlib.rc_context({"text.parse_math": False}):
        yield


def plain_log_ticks(axes: Any) -> None:
    """The tick labels of the log-scale axes of `axes` (a matplotlib Axes) written as plain
    numbers (`1e-02`, `3e-02`, matplotlib's minus sign a true minus). Matplotlib's own log
    labels are math text
    (`$\\mathdefault{10^{-2}}$`), which `plain_text_plots()` shows as written; its choice of
    which minor ticks to label (all of them only on less than a decade) is kept."""
    from matplotlib.ticker import LogFormatter

    for axis in (axes.xaxis, axes.yaxis):
        if axis.get_scale() == "log":
            axis.set_major_formatter(LogFormatter())
            axis.set_minor_formatter(LogFormatter(labelOnlyBase=False))
