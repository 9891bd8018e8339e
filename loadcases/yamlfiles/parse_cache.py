"""Parsed YAML trees kept in the user cache folder, so that a command reading a file that
has not changed (a mechanism file beside the case being edited) does not parse it again:
PyYAML's pure-Python composer takes about 75 ms for the door's mechanism file, reading its
stored tree back about 3 ms (2-core VM, 2026-11-28).

An entry is named by the SHA-256 of the file's name and text, of the parser's identity (its
own source, its limits and PyYAML's version: `loadcases.yamlfiles.source`) and of Python's version:
change any of them and another entry is made, so a stored tree is always the one the
parser would give. It is written with `marshal`, which holds only Python's built-in
values: reading an entry rebuilds no class of ours or anyone's, and runs no code. Trees
with diagnostics (duplicate keys) and texts over `MAX_TEXT` characters are not stored.

An entry is checked, never trusted: it holds the SHA-256 of the text it was parsed from and
the SHA-256 of its payload (the marshalled tree), and it is used only when the payload
still has its digest and the text digest is that of the file's current text. An entry
rewritten in the folder (a number changed in its tree), left from another text or put
under another entry's name is a miss: the file is parsed again and the entry overwritten,
so a tree read from the cache is the tree of the file as it is now. The digests are sealed
with the user's own key (`loadcases.foundation.cache_seal`, kept outside the cache folder):
a tree rewritten with its digests recomputed, or an entry written by another account into a
shared `LOADS_CACHE_DIR`, does not verify and is a miss too. A missing, unreadable,
foreign, mismatched or unsealed entry is parsed again. Entries are written whole (a new
file, then an atomic rename); the folder keeps the `MAX_ENTRIES` written last. Nothing
here is an error: a cache that cannot be read or written only costs the parse.
"""

from __future__ import annotations

import hashlib
import marshal
import sys
from contextlib import suppress
from pathlib import Path
from typing import Any

from loadcases.foundation import cache_seal
from loadcases.foundation.atomic import atomic_path
from loadcases.foundation.cache_env import shared_cache_folder

__all__ = ["MAX_ENTRIES", "MAX_TEXT", "cache_folder", "recall", "store"]

FORMAT = 4  # the layout of an entry; another layout is a foreign entry
MAX_ENTRIES = 256  # entries kept (each edit of a file makes one)
MAX_TEXT = 4 * 2**20  # characters of the largest text whose tree is stored
_SUFFIX = ".tree"


def cache_folder() -> Path:
    """`$LOADS_CACHE_DIR/yaml` when set, else `loads/yaml` in the user's cache folder (on
    Linux `$XDG_CACHE_HOME`, else `~/.cache`)."""
    shared = shared_cache_folder("yaml")
    if shared is not None:
        return shared
    import platformdirs

    return platformdirs.user_cache_path("loads", appauthor=False) / "yaml"


def _entry(file: str, text: str, parser: bytes) -> Path:
    digest = hashlib.sha256(parser)
    digest.update(f"{sys.version} {marshal.version} {FORMAT}".encode())
    digest.update(file.encode("utf-8", "surrogatepass") + b"\0")
    digest.update(text.encode("utf-8", "surrogatepass"))
    return cache_folder() / f"{digest.hexdigest()}{_SUFFIX}"


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _text_sha256(text: str) -> str:
    return _sha256(text.encode("utf-8", "surrogatepass"))


def _sealed(file: str, text_sha256: str, tree_sha256: str, parser: bytes) -> tuple[str, ...]:
    """What an entry's seal covers: its layout, file name, digests and parser identity."""
    return (str(FORMAT), file, text_sha256, tree_sha256, _sha256(parser))


def recall(file: str, text: str, parser: bytes) -> tuple[Any, dict, dict, dict] | None:
    """(data, keys, values, plain_booleans) of the tree stored for `text` read as `file`
    by the parser whose identity is `parser`, or None: also when the entry's payload does
    not have the digest stored with it, the entry was parsed from another text or its seal
    does not verify under the user's key."""
    if len(text) > MAX_TEXT:
        return None
    try:
        stored = marshal.loads(_entry(file, text, parser).read_bytes())
        if (
            not isinstance(stored, tuple)
            or len(stored) != 6
            or stored[0] != FORMAT
            or stored[1] != file
            or not isinstance(stored[4], bytes)
            or stored[2] != _text_sha256(text)
            or stored[3] != _sha256(stored[4])
            or not cache_seal.verified(stored[5], *_sealed(file, stored[2], stored[3], parser))
        ):
            return None
        tree = marshal.loads(stored[4])
    except (OSError, EOFError, ValueError, TypeError):
        return None
    if (
        not isinstance(tree, tuple)
        or len(tree) != 4
        or not all(isinstance(part, dict) for part in tree[1:])
    ):
        return None
    return tree[0], tree[1], tree[2], tree[3]


def store(
    file: str,
    text: str,
    parser: bytes,
    data: Any,
    keys: dict,
    values: dict,
    plain_booleans: dict | None = None,
) -> None:
    """Keep the tree parsed from `text` read as `file` by the parser whose identity is
    `parser`, with the digests of `text` and of the stored tree, sealed; drop the oldest entries
    beyond `MAX_ENTRIES`."""
    if len(text) > MAX_TEXT:
        return
    try:
        tree = marshal.dumps((data, keys, values, plain_booleans or {}))
        digests = (_text_sha256(text), _sha256(tree))
        seal = cache_seal.seal(*_sealed(file, *digests, parser))
        if seal is None:  # no key: an entry could not be told from a forged one
            return
        payload = marshal.dumps((FORMAT, file, *digests, tree, seal))
        target = _entry(file, text, parser)
        with atomic_path(target) as temporary:  # no fsync: a lost entry is parsed again
            temporary.write_bytes(payload)
        _prune(target.parent)
    except (OSError, ValueError):  # ValueError: a value marshal cannot hold
        return


def _prune(folder: Path) -> None:
    """Remove the entries written before the last `MAX_ENTRIES`."""
    entries = []
    for entry in folder.glob(f"*{_SUFFIX}"):
        with suppress(OSError):
            entries.append((entry.stat().st_mtime_ns, entry))
    if len(entries) <= MAX_ENTRIES:
        return
    entries.sort()
    for _, entry in entries[: len(entries) - MAX_ENTRIES]:
        with suppress(OSError):
            entry.unlink()
