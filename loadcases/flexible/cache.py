"""A cache of computed arrays (Craig-Bampton reductions of imported components), keyed by a
SHA-256 of everything they are computed from.

The key covers the caller's `key_parts` (matrices by content, interface, mode selection,
damping ...) and the engine's identity: the hash of its source (`engine_sha256`, the rule
that keeps saved runs from being reused across engine changes) and the numpy and scipy
versions. An entry is one `KEY.npz` file, written whole or not at all (temporary file, then
rename); an unreadable entry is computed again with a warning.

An entry is checked, never trusted: it holds its key and a SHA-256 of its arrays (names,
types, shapes and values, in the canonical form of the key); it is used only when both
match, so an entry whose arrays were changed in the folder (a matrix scaled), or one put
under another key's name, is computed again with a warning and replaced. Key and digest are
sealed with the user's own key (`loadcases.foundation.cache_seal`, kept outside every cache
folder): an entry whose arrays were changed and their digest recomputed, or one written by
another account (a results folder on a shared drive), does not verify and is computed
again too. Nothing is ever evicted: delete the folder to clear it.
"""

from __future__ import annotations

import dataclasses
import hashlib
import warnings
import zipfile
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import Any

import numpy as np
import scipy
import scipy.sparse as sp

from loadcases.foundation import cache_seal
from loadcases.foundation.atomic import atomic_path
from loadcases.foundation.cache_env import CACHE_ENV, reading_only, shared_cache_folder, storing
from loadcases.foundation.engine_hash import engine_sha256

__all__ = [
    "CACHE_ENV",
    "CacheWarning",
    "cache_folder",
    "cache_key",
    "cached",
    "caching_under",
    "reading_only",
]

_KEY_ARRAY = "__key__"
_DIGEST_ARRAY = "__digest__"  # SHA-256 of the entry's other arrays (`_digest`)
_SEAL_ARRAY = "__seal__"  # HMAC of key and digest under the user's key (cache_seal)
_OUTPUT: ContextVar[Path | None] = ContextVar("loads_cache_output", default=None)


class CacheWarning(UserWarning):
    """A cache entry could not be read or written (the result is computed anyway)."""


@contextmanager
def caching_under(output_folder: Path | str) -> Iterator[None]:
    """Within the block, `cache_folder()` defaults to `output_folder` (the runs' results
    folder); worker processes of a set that do not share this context use their own."""
    token = _OUTPUT.set(Path(output_folder))
    try:
        yield
    finally:
        _OUTPUT.reset(token)


def cache_folder(output_folder: Path | None = None) -> Path:
    """`$LOADS_CACHE_DIR/flexible` when set, else `<output folder>/.cache/flexible`: the
    folder given, else the one `caching_under` set, else the working folder."""
    shared = shared_cache_folder("flexible")
    if shared is not None:
        return shared
    return Path(output_folder or _OUTPUT.get() or ".") / ".cache" / "flexible"


def _feed(digest: Any, value: Any) -> None:
    """Add `value` to the hash in a canonical, type-tagged form (so 1 and 1.0 and "1"
    differ, a sparse matrix hashes by its terms, not by how it is stored)."""
    if isinstance(value, np.generic):  # numpy scalars hash as the Python numbers they equal
        value = value.item()
    if value is None or isinstance(value, (bool, int, float, str)):
        digest.update(f"{type(value).__name__}:{value!r};".encode())
    elif isinstance(value, Path):
        _feed(digest, str(value))
    elif sp.issparse(value):
        csr = sp.csr_matrix(value, copy=True)
        csr.sum_duplicates()
        csr.eliminate_zeros()
        csr.sort_indices()
        digest.update(b"sparse;")
        for part in (np.asarray(csr.shape), csr.data, csr.indices, csr.indptr):
            _feed(digest, np.asarray(part))
    elif isinstance(value, np.ndarray):
        array = np.ascontiguousarray(value)
        if array.dtype.kind == "O":
            raise TypeError("object arrays cannot be part of a cache key")
        digest.update(f"array:{array.dtype.str}:{array.shape};".encode())
        digest.update(array.tobytes())
    elif isinstance(value, Mapping):
        digest.update(f"map:{len(value)};".encode())
        for key in sorted(value, key=str):
            _feed(digest, str(key))
            _feed(digest, value[key])
    elif isinstance(value, (list, tuple)):
        digest.update(f"list:{len(value)};".encode())
        for item in value:
            _feed(digest, item)
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        digest.update(f"{type(value).__qualname__};".encode())
        _feed(digest, {f.name: getattr(value, f.name) for f in dataclasses.fields(value)})
    else:
        raise TypeError(f"{type(value).__name__} cannot be part of a cache key")


def cache_key(key_parts: Mapping[str, Any]) -> str:
    """The SHA-256 (hex) of `key_parts` and of the engine's identity (source hash, numpy
    and scipy versions). Values: numbers, text, None, lists, mappings, numpy arrays,
    scipy sparse matrices, dataclasses of those (an `FEModel`)."""
    digest = hashlib.sha256()
    _feed(
        digest,
        {
            "parts": dict(key_parts),
            "engine": engine_sha256(),
            "numpy": np.__version__,
            "scipy": scipy.__version__,
        },
    )
    return digest.hexdigest()


def _warn(message: str) -> None:
    warnings.warn(message, CacheWarning, stacklevel=3)


def _digest(arrays: Mapping[str, np.ndarray]) -> str:
    """The SHA-256 (hex) of named arrays: names, dtypes, shapes and values."""
    digest = hashlib.sha256()
    _feed(digest, dict(arrays))
    return digest.hexdigest()


def _load(path: Path, key: str) -> dict[str, np.ndarray]:
    """The arrays of a cache entry; ValueError (or the reader's error) if it is damaged or
    its arrays do not have the digest stored with them."""
    with np.load(path, allow_pickle=False) as entry:
        if _KEY_ARRAY not in entry.files or str(entry[_KEY_ARRAY]) != key:
            raise ValueError("its key does not match its name")
        if _DIGEST_ARRAY not in entry.files:
            raise ValueError("it holds no digest of its arrays")
        stored = str(entry[_DIGEST_ARRAY])
        seal = str(entry[_SEAL_ARRAY]) if _SEAL_ARRAY in entry.files else None
        skip = (_KEY_ARRAY, _DIGEST_ARRAY, _SEAL_ARRAY)
        arrays = {name: entry[name] for name in entry.files if name not in skip}
    if _digest(arrays) != stored:
        raise ValueError("its arrays do not match their digest")
    if not cache_seal.verified(seal, key, stored):
        raise ValueError("its seal does not verify: not written by this user's loads")
    return arrays


def _checked(result: Any) -> dict[str, np.ndarray]:
    """The computed result as name -> array; TypeError if it is not one."""
    if not isinstance(result, Mapping):
        raise TypeError(f"compute() must return a mapping of arrays, got {type(result).__name__}")
    arrays = {}
    for name, value in result.items():
        if not isinstance(name, str) or not name.isidentifier() or name.startswith("__"):
            raise TypeError(f"cache entry names are identifiers without a leading __: {name!r}")
        arrays[name] = np.asarray(value)
        if arrays[name].dtype.kind == "O":
            raise TypeError(f"{name}: object arrays cannot be cached")
    return arrays


def cached(
    key_parts: Mapping[str, Any],
    compute: Callable[[], Mapping[str, np.ndarray]],
    *,
    folder: Path | None = None,
    warn: Callable[[str], None] = _warn,
) -> dict[str, np.ndarray]:
    """The arrays `compute()` returns for `key_parts`, read from the cache when an entry
    exists and its key and the digest of its arrays match, else computed and stored
    (`folder`, default `cache_folder()`; not stored within `reading_only`). A damaged or
    changed entry is computed again and replaced; a cache that cannot be written only warns
    (`warn`, default a `CacheWarning`)."""
    key = cache_key(key_parts)
    path = Path(folder if folder is not None else cache_folder()) / f"{key}.npz"
    if path.is_file():
        try:
            return _load(path, key)
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as error:
            warn(f"cache entry {path} unreadable ({error}): computed again")
    result = _checked(compute())
    if not storing():  # `loads validate`: computed, used and forgotten
        return result
    digest = _digest(result)
    seal = cache_seal.seal(key, digest)
    if seal is None:  # no key: an entry could not be told from a forged one
        return result
    try:
        with atomic_path(path) as tmp, open(tmp, "wb") as stream:
            entry: dict[str, Any] = {
                _KEY_ARRAY: np.array(key),
                _DIGEST_ARRAY: np.array(digest),
                _SEAL_ARRAY: np.array(seal),
                **result,
            }
            np.savez(stream, **entry)
    except OSError as error:
        warn(f"cache entry {path} not written ({error})")
    return result
