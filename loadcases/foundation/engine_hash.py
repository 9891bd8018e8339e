"""The engine's identity for reusing saved runs: a SHA-256 of the installed source (every
`.py` file of `mechlib`, `loadcases` and `cli`), so that a changed engine solves again
even when its version string did not change. Computed once per process."""

from __future__ import annotations

import hashlib
import importlib.util
from collections.abc import Iterable
from functools import lru_cache
from pathlib import Path

__all__ = ["ENGINE_PACKAGES", "engine_sha256", "file_sha256", "source_sha256"]

ENGINE_PACKAGES = ("mechlib", "loadcases", "cli")
_CHUNK = 1 << 20  # bytes read at a time when hashing a file


def source_sha256(folders: Iterable[Path]) -> str:
    """SHA-256 over the relative path and bytes of every `.py` file below the folders
    (sorted, so the same tree always gives the same hash)."""
    digest = hashlib.sha256()
    for folder in folders:
        folder = Path(folder)
        for path in sorted(folder.rglob("*.py")):
            digest.update(path.relative_to(folder.parent).as_posix().encode() + b"\0")
            digest.update(path.read_bytes())
            digest.update(b"\0")
    return digest.hexdigest()


@lru_cache(maxsize=1)
def engine_sha256() -> str:
    """The hash of the installed engine's source (see `source_sha256`), cached."""
    folders = []
    for name in ENGINE_PACKAGES:
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.submodule_search_locations:
            folders += [Path(p) for p in spec.submodule_search_locations]
    return source_sha256(folders)


def file_sha256(path: Path) -> str | None:
    """SHA-256 of a file's bytes, None if it cannot be read."""
    digest = hashlib.sha256()
    try:
        with open(path, "rb") as stream:
            for chunk in iter(lambda: stream.read(_CHUNK), b""):
                digest.update(chunk)
    except OSError:
        return None
    return digest.hexdigest()
