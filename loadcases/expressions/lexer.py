"""Tokenizer: numbers, names, operators; everything else is an error with its offset.

Numbers are written with the digits 0-9 and space is ASCII (a space, tab or line break): an
Arabic-Indic digit or a no-break space is an unexpected character, not a number or a gap.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass

from loadcases.foundation.number_text import UNSIGNED_NUMBER

from .errors import ExpressionError

__all__ = ["KEYWORDS", "Token", "tokenize"]

KEYWORDS = frozenset({"and", "or", "not"})

_TOKEN = re.compile(
    rf"""(?P<space>[ \t\r\n]+)
      | (?P<num>{UNSIGNED_NUMBER})
      | (?P<name>[^\W\d]\w*)
      | (?P<op>\*\*|<=|>=|==|!=|[-+*/^<>(),])""",
    re.VERBOSE,
)

# Characters that are not part of the language, with the message explaining why.
_REFUSED = {
    "'": "strings are not allowed",
    '"': "strings are not allowed",
    "[": "subscripts are not allowed",
    "=": "'=' is not allowed; use '==' to compare",
    "!": "use 'not' instead of '!'",
    "&": "use 'and' instead of '&'",
    "|": "use 'or' instead of '|'",
}


@dataclass(frozen=True, slots=True)
class Token:
    """`kind` is `num`, `name`, `op` (operators, parentheses, commas, and/or/not) or `end`."""

    kind: str
    text: str
    offset: int


def _refuse(text: str, pos: int, previous: Token | None) -> ExpressionError:
    char = text[pos]
    after_operand = previous is not None and (
        previous.kind in ("name", "num") or previous.text == ")"
    )
    if char == "." and after_operand:
        return ExpressionError("attribute access is not allowed", pos)
    message = _REFUSED.get(char, f"unexpected character {char!r}")
    return ExpressionError(message, pos)


def tokenize(text: str) -> Iterator[Token]:
    """The tokens of `text`, lazily (so errors come in reading order), then `end` tokens
    at offset len(text) for ever."""
    previous: Token | None = None
    pos = 0
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None:
            raise _refuse(text, pos, previous)
        kind = match.lastgroup or "space"
        if kind != "space":
            word = match.group()
            if kind == "name" and word in KEYWORDS:
                kind = "op"
            previous = Token(kind, word, pos)
            yield previous
        pos = match.end()
    while True:
        yield Token("end", "", len(text))
