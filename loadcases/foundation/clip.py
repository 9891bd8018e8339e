"""Input text quoted in messages is cut to at most 80 characters: a message stays one
readable line whatever a file holds (a 10 kB key, a pasted table in a value)."""

from __future__ import annotations

import re

__all__ = ["QUOTE_LIMIT", "clip", "clip_quotes"]

QUOTE_LIMIT = 80  # characters of input a message quotes at most
_QUOTED = re.compile(rf"'([^']{{{QUOTE_LIMIT + 1},}})'")


def clip(text: str, limit: int = QUOTE_LIMIT) -> str:
    """`text` cut to `limit` characters, ending with `...` when it was longer."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def clip_quotes(message: str) -> str:
    """`message` with every single-quoted part longer than the limit clipped."""
    return _QUOTED.sub(lambda match: f"'{clip(match.group(1))}'", message)
