"""Forged cache entries (issue 39 items 7 and 6): an entry whose content was changed AND
whose digests were recomputed, as whoever rewrites the cache folder can do, is not used:
its seal (HMAC under the user's own key, kept outside every cache folder) does not verify.
An entry sealed under another key (another account sharing `LOADS_CACHE_DIR`) is a miss
too; without a key nothing is stored and everything is computed, as with no cache.
"""

from __future__ import annotations

import hashlib
import marshal
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

import loadcases.yamlfiles.source as source
from loadcases.flexible.cache import CacheWarning, _digest, cached
from loadcases.foundation import cache_seal
from loadcases.yamlfiles import parse_cache
from loadcases.yamlfiles.source import load_yaml


@pytest.fixture()
def folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A fresh cache folder and key, nothing kept in memory."""
    monkeypatch.setenv("LOADS_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv(cache_seal.KEY_ENV, str(tmp_path / "home" / "seal.key"))
    monkeypatch.setattr(source, "_PARSED", source.OrderedDict())
    monkeypatch.setattr(source, "_parsed_size", 0)
    return tmp_path / "cache"


def _fresh_process() -> None:
    source._PARSED.clear()
    source._parsed_size = 0


def _forged_tree(entry: Path, force: float) -> None:
    """Rewrite a parsed-YAML entry with `force` in its tree and every digest recomputed;
    the seal kept (the forger has no key)."""
    fmt, file, text_sha, _, tree, seal = marshal.loads(entry.read_bytes())
    data, keys, values, booleans = marshal.loads(tree)
    forged = marshal.dumps(({**data, "force": force}, keys, values, booleans))
    digest = hashlib.sha256(forged).hexdigest()
    entry.write_bytes(marshal.dumps((fmt, file, text_sha, digest, forged, seal)))


def test_a_tree_forged_with_its_digests_recomputed_is_not_used(folder: Path, tmp_path) -> None:
    path = tmp_path / "a.yaml"
    path.write_text("force: 1.5\n", encoding="utf-8")
    assert load_yaml(path).data == {"force": 1.5}
    (entry,) = (folder / "yaml").glob("*.tree")
    _forged_tree(entry, 15.0)
    _fresh_process()
    assert load_yaml(path).data == {"force": 1.5}  # parsed again, not 15
    _fresh_process()
    assert load_yaml(path).data == {"force": 1.5}  # the entry was overwritten, sealed
    _, file, text_sha, tree_sha, _tree, seal = marshal.loads(entry.read_bytes())
    assert seal == cache_seal.seal(
        *parse_cache._sealed(file, text_sha, tree_sha, source._parser_identity())
    )


def test_an_entry_sealed_under_another_key_is_a_miss(
    folder: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Another account's entry in a shared cache folder: whole, its own digests and seal,
    but not this user's key."""
    path = tmp_path / "a.yaml"
    path.write_text("force: 1.5\n", encoding="utf-8")
    monkeypatch.setenv(cache_seal.KEY_ENV, str(tmp_path / "other" / "seal.key"))
    load_yaml(path)  # stored under the other key
    (entry,) = (folder / "yaml").glob("*.tree")
    _forged_tree(entry, 15.0)  # the other account's own forgery...
    fmt, file, text_sha, tree_sha, tree, _ = marshal.loads(entry.read_bytes())
    seal = cache_seal.seal(
        *parse_cache._sealed(file, text_sha, tree_sha, source._parser_identity())
    )
    entry.write_bytes(marshal.dumps((fmt, file, text_sha, tree_sha, tree, seal)))  # ...sealed
    _fresh_process()
    assert load_yaml(path).data == {"force": 15.0}  # the other account trusts its own
    monkeypatch.setenv(cache_seal.KEY_ENV, str(tmp_path / "home" / "seal.key"))
    _fresh_process()
    assert load_yaml(path).data == {"force": 1.5}  # this user does not


def test_without_a_key_nothing_is_stored(folder: Path, tmp_path: Path, monkeypatch) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(cache_seal.KEY_ENV, str(blocker / "seal.key"))  # cannot be made
    path = tmp_path / "a.yaml"
    path.write_text("force: 1.5\n", encoding="utf-8")
    assert load_yaml(path).data == {"force": 1.5}
    assert not (folder / "yaml").exists() or not list((folder / "yaml").glob("*.tree"))
    assert cache_seal.seal("x") is None and not cache_seal.verified("0" * 64, "x")


def test_the_key_is_its_owners_alone(folder: Path, tmp_path: Path) -> None:
    assert cache_seal.seal("x") is not None
    key = tmp_path / "home" / "seal.key"
    assert key.stat().st_mode & 0o077 == 0 and len(key.read_bytes()) == 32


def test_a_reduction_forged_with_its_digest_recomputed_is_computed_again(
    folder: Path, tmp_path: Path
) -> None:
    """The reduction cache: frequencies x10 and the digest recomputed, the seal kept."""
    matrix = sp.csr_matrix(np.diag([4.0, 9.0]))
    calls = []

    def compute() -> dict[str, np.ndarray]:
        calls.append(1)
        return {"frequencies": np.sqrt(matrix.diagonal())}

    parts = {"stiffness": matrix, "modes": 2}
    cached(parts, compute, folder=tmp_path / "red")
    (entry,) = (tmp_path / "red").iterdir()
    with np.load(entry, allow_pickle=False) as stored:
        arrays = {name: stored[name] for name in stored.files}
    arrays["frequencies"] = arrays["frequencies"] * 10.0
    arrays["__digest__"] = np.array(_digest({"frequencies": arrays["frequencies"]}))
    with open(entry, "wb") as stream:
        np.savez(stream, **arrays)
    with pytest.warns(CacheWarning, match="seal does not verify"):
        result = cached(parts, compute, folder=tmp_path / "red")
    assert len(calls) == 2 and np.array_equal(result["frequencies"], [2.0, 3.0])
    assert np.array_equal(
        cached(parts, compute, folder=tmp_path / "red")["frequencies"], [2.0, 3.0]
    )
    assert len(calls) == 2  # replaced by a sealed entry: a hit
