"""Cache entries sealed with a key of the user's own, so that an entry is used only when
this user's `loads` wrote it as it is.

A cache entry holds digests of what it was made from and of what it holds; they find damage
and edits, but whoever rewrites an entry can recompute them (a tree with a force x10 and
its digest made anew). The seal is an HMAC-SHA256 of those digests under a secret key kept
outside every cache folder: an entry written or rewritten without the key (by another
account in a cache folder shared through `LOADS_CACHE_DIR`, in a results folder on a
shared drive, or copied from another machine) does not verify and is a miss.

The key: 32 random bytes in `$LOADS_SEAL_KEY` if set, else `cache-seal.key` in the user's
data folder (on Linux `$XDG_DATA_HOME/loads`, else `~/.local/share/loads`), readable by its
owner alone (0600), made whole on first use. Whoever can read it can forge an entry, as
they could change the engine itself: it guards against other accounts and copied folders,
not against the user's own. Without a key (a folder that refuses it) nothing is sealed and
every entry is a miss: each result is computed again.
"""

from __future__ import annotations

import functools
import hashlib
import hmac
import os
import secrets
import tempfile
from contextlib import suppress
from pathlib import Path

__all__ = ["KEY_ENV", "key_file", "seal", "verified"]

KEY_ENV = "LOADS_SEAL_KEY"
_KEY_BYTES = 32


def key_file() -> Path:
    """Where the key is: `$LOADS_SEAL_KEY`, else the user's data folder's `loads/`."""
    given = os.environ.get(KEY_ENV)
    if given:
        return Path(given)
    import platformdirs

    return platformdirs.user_data_path("loads", appauthor=False) / "cache-seal.key"


def _made(path: Path) -> None:
    """Write a new key to `path` whole (0600), unless another process made one first."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=".key.", dir=path.parent)  # 0600
    try:
        with os.fdopen(fd, "wb") as stream:
            stream.write(secrets.token_bytes(_KEY_BYTES))
            stream.flush()
            os.fsync(stream.fileno())
        with suppress(FileExistsError):  # a link takes the name only if it is free
            os.link(name, path)
    finally:
        with suppress(OSError):
            os.unlink(name)


@functools.lru_cache(maxsize=4)
def _key(path: Path) -> bytes | None:
    """The key in `path` (made if there is none), None if it cannot be had."""
    try:
        if not path.is_file():
            _made(path)
        key = path.read_bytes()
    except OSError:
        return None
    return key if len(key) == _KEY_BYTES else None


def seal(*parts: str) -> str | None:
    """The seal (hex) of `parts` (an entry's digests and names) under the user's key; None
    without a key (then the entry is not stored)."""
    key = _key(key_file())
    if key is None:
        return None
    return hmac.new(
        key, "\0".join(parts).encode("utf-8", "surrogatepass"), hashlib.sha256
    ).hexdigest()


def verified(stored: object, *parts: str) -> bool:
    """Whether `stored` is the seal of `parts` under the user's key (in constant time)."""
    expected = seal(*parts)
    return (
        expected is not None and isinstance(stored, str) and hmac.compare_digest(stored, expected)
    )
