"""The limits every importer checks before it allocates (docs/flexible-bodies-import.md
"Limits"): matrix sizes and term counts read from a file's header against the input limits
and against what the file's own length can hold, file sizes, and node ids. Each returns
why a value is refused (a text for the caller's error), or None."""

from __future__ import annotations

from pathlib import Path

from loadcases.foundation.limits import MAX_FE_DOF, MAX_FE_FILE_BYTES, MAX_FE_TERMS, MAX_NODE_ID

__all__ = [
    "file_size_problem",
    "node_id_problem",
    "shape_limit_problem",
    "terms_problem",
]


def shape_limit_problem(rows: int, cols: int) -> str | None:
    """Why a declared rows x cols matrix cannot be read: not positive, or beyond MAX_FE_DOF."""
    if rows < 1 or cols < 1:
        return f"{rows} rows x {cols} columns: expected positive sizes"
    if max(rows, cols) > MAX_FE_DOF:
        return (
            f"{rows} rows x {cols} columns: at most {MAX_FE_DOF:,} (the input limit of an "
            "imported matrix)"
        )
    return None


def terms_problem(declared: int, room: int, what: str = "entries") -> str | None:
    """Why `declared` terms cannot be read when the rest of the file holds at most `room`
    of them (or they exceed MAX_FE_TERMS), or None."""
    if declared < 0:
        return f"{declared} {what}: expected a count of at least 0"
    if declared > MAX_FE_TERMS:
        return f"{declared} {what}: at most {MAX_FE_TERMS:,} (the input limit of one matrix)"
    if declared > room:
        return f"{declared} {what} declared, but the rest of the file holds at most {room}"
    return None


def file_size_problem(path: Path) -> str | None:
    """Why the file at `path` is too large to be read whole (MAX_FE_FILE_BYTES), or None."""
    size = Path(path).stat().st_size
    if size <= MAX_FE_FILE_BYTES:
        return None
    return f"{size:,} bytes: at most {MAX_FE_FILE_BYTES:,} (the input limit of one file)"


def node_id_problem(value: object) -> str | None:
    """Why `value` is not a node (grid) id: an integer from 1 to MAX_NODE_ID (not a
    boolean, not a float such as 1.0), or None."""
    if isinstance(value, bool) or not isinstance(value, int):
        return f"expected a node id (an integer 1-{MAX_NODE_ID}), got {_show(value)}"
    if not 1 <= value <= MAX_NODE_ID:
        return f"node id {_show(value)} out of range: expected an integer 1-{MAX_NODE_ID}"
    return None


def _show(value: object) -> str:
    text = "true" if value is True else "false" if value is False else repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
