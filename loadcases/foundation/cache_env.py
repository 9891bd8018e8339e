"""Where the caches of every run go when the user names one folder for them."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["CACHE_ENV", "shared_cache_folder"]

CACHE_ENV = "LOADS_CACHE_DIR"  # a folder shared by every run and command


def shared_cache_folder(kind: str) -> Path | None:
    """`$LOADS_CACHE_DIR/<kind>` when the variable is set, else None."""
    shared = os.environ.get(CACHE_ENV, "").strip()
    return Path(shared) / kind if shared else None
