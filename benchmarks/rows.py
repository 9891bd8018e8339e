"""The measurement scripts' results: each row printed as JSON as it comes, all of them
written to the `-o` file (a JSON list) at the end."""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path
from typing import Any

__all__ = ["stream_rows", "write_rows"]


def stream_rows(rows: Iterable[dict[str, Any]], output: Path | None) -> list[dict[str, Any]]:
    """Print each row of `rows` (a generator: a long measurement shows its progress) as one
    JSON line, then write them all to `output` if given; the rows."""
    kept = []
    for row in rows:
        kept.append(row)
        print(json.dumps(row), flush=True)
    write_rows(kept, output)
    return kept


def write_rows(rows: list[dict[str, Any]], output: Path | None) -> None:
    """`rows` as an indented JSON list in `output` (nothing if None)."""
    if output:
        output.write_text(json.dumps(rows, indent=1) + "\n", encoding="utf-8")
