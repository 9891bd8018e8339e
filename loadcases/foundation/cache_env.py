"""Where the caches of every run go when the user names one folder for them, and whether
the computed-array caches may store (not within `reading_only`: `loads validate`). Imports
nothing heavy: `loads validate` reads it without numpy's or scipy's submodules."""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path

__all__ = ["CACHE_ENV", "reading_only", "shared_cache_folder", "storing"]

CACHE_ENV = "LOADS_CACHE_DIR"  # a folder shared by every run and command
_STORING: ContextVar[bool] = ContextVar("loads_cache_storing", default=True)


@contextmanager
def reading_only() -> Iterator[None]:
    """Within the block, the reduction cache (`loadcases.flexible.cache.cached`) reads
    entries that exist but stores none (`loads validate` writes nothing: a reduction it
    needs is computed and forgotten)."""
    token = _STORING.set(False)
    try:
        yield
    finally:
        _STORING.reset(token)


def storing() -> bool:
    """Whether computed arrays may be stored now (False within `reading_only`)."""
    return _STORING.get()


def shared_cache_folder(kind: str) -> Path | None:
    """`$LOADS_CACHE_DIR/<kind>` when the variable is set, else None."""
    shared = os.environ.get(CACHE_ENV, "").strip()
    return Path(shared) / kind if shared else None
