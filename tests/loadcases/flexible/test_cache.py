"""The reduction cache: a hit returns the stored arrays without computing; a change of the
matrices' content, of another key part or of the engine computes again; a damaged entry is
computed again with a warning; entries are written whole."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from loadcases.flexible import cache
from loadcases.flexible.cache import CacheWarning, cache_folder, cache_key, cached


class Counter:
    """A compute() that counts its calls and returns arrays derived from its matrix."""

    def __init__(self, matrix: sp.csr_matrix) -> None:
        self.matrix, self.calls = matrix, 0

    def __call__(self) -> dict[str, np.ndarray]:
        self.calls += 1
        return {"frequencies": np.sqrt(self.matrix.diagonal()), "shape": np.eye(2)}


def _parts(matrix: sp.csr_matrix, modes: int = 4) -> dict[str, object]:
    return {"stiffness": matrix, "interface": [1, 7], "modes": modes, "damping": 0.01}


@pytest.fixture
def matrix() -> sp.csr_matrix:
    return sp.csr_matrix(np.diag([4.0, 9.0, 16.0]))


def test_hit_does_not_compute(tmp_path: Path, matrix: sp.csr_matrix) -> None:
    compute = Counter(matrix)
    first = cached(_parts(matrix), compute, folder=tmp_path)
    second = cached(_parts(matrix.copy()), compute, folder=tmp_path)
    assert compute.calls == 1
    assert np.array_equal(second["frequencies"], [2.0, 3.0, 4.0])
    assert set(first) == set(second) == {"frequencies", "shape"}
    assert [p.suffix for p in tmp_path.iterdir()] == [".npz"]  # no temporary file left


def test_storage_does_not_change_the_key(matrix: sp.csr_matrix) -> None:
    """The same terms stored as COO with duplicates and explicit zeros hash alike."""
    coo = sp.coo_matrix(([4.0, 4.5, 4.5, 16.0, 0.0], ([0, 1, 1, 2, 0], [0, 1, 1, 2, 2])), (3, 3))
    assert cache_key(_parts(matrix)) == cache_key(_parts(coo))


def test_miss_after_a_content_change(tmp_path: Path, matrix: sp.csr_matrix) -> None:
    compute = Counter(matrix)
    cached(_parts(matrix), compute, folder=tmp_path)
    changed = matrix.copy()
    changed[1, 1] = 9.000000001
    compute.matrix = changed
    result = cached(_parts(changed), compute, folder=tmp_path)
    assert compute.calls == 2
    assert result["frequencies"][1] == pytest.approx(np.sqrt(9.000000001), rel=1e-15)
    cached(_parts(matrix, modes=5), compute, folder=tmp_path)
    assert compute.calls == 3


def test_miss_after_an_engine_change(
    tmp_path: Path, matrix: sp.csr_matrix, monkeypatch: pytest.MonkeyPatch
) -> None:
    compute = Counter(matrix)
    cached(_parts(matrix), compute, folder=tmp_path)
    monkeypatch.setattr(cache, "engine_sha256", lambda: "another engine")
    cached(_parts(matrix), compute, folder=tmp_path)
    assert compute.calls == 2
    monkeypatch.setattr(cache.np, "__version__", "0.0")
    cached(_parts(matrix), compute, folder=tmp_path)
    assert compute.calls == 3


@pytest.mark.parametrize("damage", [b"not a zip file", b""])
def test_damaged_entry_is_computed_again(
    tmp_path: Path, matrix: sp.csr_matrix, damage: bytes
) -> None:
    compute = Counter(matrix)
    cached(_parts(matrix), compute, folder=tmp_path)
    (entry,) = tmp_path.iterdir()
    entry.write_bytes(damage)
    with pytest.warns(CacheWarning, match="unreadable"):
        result = cached(_parts(matrix), compute, folder=tmp_path)
    assert compute.calls == 2 and np.array_equal(result["frequencies"], [2.0, 3.0, 4.0])
    cached(_parts(matrix), compute, folder=tmp_path)  # the entry was replaced: a hit
    assert compute.calls == 2


def test_entry_under_another_name_is_refused(tmp_path: Path, matrix: sp.csr_matrix) -> None:
    compute = Counter(matrix)
    cached(_parts(matrix), compute, folder=tmp_path)
    (entry,) = tmp_path.iterdir()
    entry.rename(tmp_path / f"{cache_key(_parts(matrix, modes=9))}.npz")
    with pytest.warns(CacheWarning, match="key does not match"):
        cached(_parts(matrix, modes=9), compute, folder=tmp_path)
    assert compute.calls == 2


def test_unwritable_cache_only_warns(tmp_path: Path, matrix: sp.csr_matrix) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("a file where the cache folder should be")
    messages: list[str] = []
    result = cached(
        _parts(matrix), Counter(matrix), folder=blocker / "flexible", warn=messages.append
    )
    assert np.array_equal(result["shape"], np.eye(2))
    assert len(messages) == 1 and "not written" in messages[0]


def test_bad_results_and_keys(tmp_path: Path) -> None:
    with pytest.raises(TypeError, match="leading __"):
        cached({"a": 1}, lambda: {"__key__": np.zeros(1)}, folder=tmp_path)
    with pytest.raises(TypeError, match="cannot be part of a cache key"):
        cache_key({"a": object()})


def test_cache_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("LOADS_CACHE_DIR", raising=False)
    assert cache_folder(tmp_path) == tmp_path / ".cache" / "flexible"
    monkeypatch.setenv("LOADS_CACHE_DIR", str(tmp_path / "shared"))
    assert cache_folder(tmp_path / "out") == tmp_path / "shared" / "flexible"


def _rewrite(entry: Path, change) -> None:
    """Write `entry` again with `change` applied to its arrays, its key and digest kept."""
    with np.load(entry, allow_pickle=False) as stored:
        arrays = {name: stored[name] for name in stored.files}
    with open(entry, "wb") as stream:
        np.savez(stream, **change(arrays))


@pytest.mark.parametrize(
    "change",
    [
        lambda a: {**a, "frequencies": a["frequencies"] * 10.0},  # an array scaled
        lambda a: {**a, "shape": a["shape"].T[:, :1]},  # another shape
        lambda a: {k: v for k, v in a.items() if k != "shape"},  # an array dropped
        lambda a: {k: v for k, v in a.items() if k != "__digest__"},  # the digest dropped
    ],
    ids=["scaled", "reshaped", "dropped", "no-digest"],
)
def test_changed_entry_is_not_used(tmp_path: Path, matrix: sp.csr_matrix, change) -> None:
    """Issue 39 item 7: an entry whose arrays were changed in the folder, its key and
    digest left as they were, is computed again with a warning and replaced."""
    compute = Counter(matrix)
    cached(_parts(matrix), compute, folder=tmp_path)
    (entry,) = tmp_path.iterdir()
    _rewrite(entry, change)
    with pytest.warns(CacheWarning, match="digest"):
        result = cached(_parts(matrix), compute, folder=tmp_path)
    assert compute.calls == 2
    assert np.array_equal(result["frequencies"], [2.0, 3.0, 4.0])
    assert np.array_equal(result["shape"], np.eye(2))
    again = cached(_parts(matrix), compute, folder=tmp_path)  # replaced: a hit
    assert compute.calls == 2 and np.array_equal(again["frequencies"], [2.0, 3.0, 4.0])


def test_reading_only_reads_an_entry_but_stores_none(tmp_path: Path) -> None:
    matrix = sp.csr_matrix(np.diag([4.0, 9.0]))
    counter = Counter(matrix)
    with cache.reading_only():
        cached(_parts(matrix), counter, folder=tmp_path)
    assert counter.calls == 1 and not list(tmp_path.iterdir())
    cached(_parts(matrix), counter, folder=tmp_path)  # stored outside the block
    assert counter.calls == 2 and len(list(tmp_path.iterdir())) == 1
    with cache.reading_only():
        cached(_parts(matrix), counter, folder=tmp_path)
    assert counter.calls == 2  # read, not computed


def test_loads_validate_of_a_flexible_case_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 36: `loads validate` wrote a reduction into `.cache/` of the working folder."""
    from typer.testing import CliRunner

    from cli.app import app

    case = Path(__file__).resolve().parents[3] / "loadcases/library/examples/flexible"
    monkeypatch.delenv("LOADS_CACHE_DIR", raising=False)
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(app, ["validate", str(case / "flexible_pendulum.case.yaml")])
    assert result.exit_code == 0, result.output
    assert not list(tmp_path.iterdir())
