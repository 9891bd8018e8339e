"""Atomic file writes: a file appears whole under its final name, or not at all.

Data goes to a temporary file in the target's own directory (so the final `os.replace`
is a rename within one file system, which is atomic on POSIX and Windows); on any error the
temporary file is removed and the previous content of the target, if any, is untouched.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "atomic_write_bytes", "atomic_write_text"]

# mkstemp creates files readable by the owner only; results are meant to be shared like any
# file the user creates, so the final file gets the usual mode (0o666 minus the umask).
_UMASK = os.umask(0o022)
os.umask(_UMASK)
_FILE_MODE = 0o666 & ~_UMASK


@contextlib.contextmanager
def atomic_path(target: Path, *, overwrite: bool = True) -> Iterator[Path]:
    """Yield a temporary path next to `target`; rename it onto `target` on success.

    The caller writes the whole file to the yielded path (e.g. `workbook.save(tmp)`).
    Parent folders are created. If the block raises, the temporary file is deleted. With
    `overwrite=False` an existing `target` is never replaced, even one another process
    creates meanwhile: FileExistsError.
    """
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, _FILE_MODE)
        if overwrite:
            os.replace(tmp, target)
        else:  # a hard link takes the final name only if it is free (a rename would replace)
            os.link(tmp, target)
    finally:
        # After a successful replace the temporary name no longer exists.
        tmp.unlink(missing_ok=True)


def atomic_write_bytes(target: Path, data: bytes, *, overwrite: bool = True) -> Path:
    """Write `data` to `target` atomically (flushed to disk before the rename)."""
    with atomic_path(target, overwrite=overwrite) as tmp, open(tmp, "wb") as stream:
        stream.write(data)
        stream.flush()
        os.fsync(stream.fileno())
    return Path(target)


def atomic_write_text(
    target: Path, text: str, *, encoding: str = "utf-8", overwrite: bool = True
) -> Path:
    """Write `text` to `target` atomically, with `\\n` line ends on every platform."""
    return atomic_write_bytes(target, text.encode(encoding), overwrite=overwrite)
