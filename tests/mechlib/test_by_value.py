"""Results kept per process by value (mechlib.core.by_value) and the rank check kept so
(mechlib.linalg.rank.find_redundant): the same values give the kept result, any other value
(one bit of one entry, a name, the tolerance) its own."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from mechlib.core.by_value import ByValue, value_key
from mechlib.linalg import rank
from mechlib.linalg.rank import find_redundant


def test_value_key_tells_values_apart_not_identities() -> None:
    a = np.array([1.0, 2.0])
    assert value_key(a, ["x"]) == value_key(a.copy(), ["x"])
    assert value_key(a) != value_key(np.nextafter(a, 3.0))  # one ulp of each entry
    assert value_key(a) != value_key(a.astype(np.float32))
    assert value_key(a) != value_key(a.reshape(2, 1))
    assert value_key({"a": 1}) != value_key({"a": 2})
    assert value_key(0.0) != value_key(-0.0)  # equal numbers, other bits: atan2 differs
    assert value_key(1) != value_key(1.0) != value_key(np.float64(1.0))
    assert value_key(np.float64(-0.0)) != value_key(np.float64(0.0))
    assert value_key(frozenset({"b", "a"})) == value_key({"a", "b"})
    with pytest.raises(TypeError, match="not keyed by value"):
        value_key(object())  # no identity-keyed values: a miss never hides behind an id
    looped: list = [1.0]
    looped.append(looped)
    with pytest.raises(TypeError, match="inside itself"):
        value_key(looped)  # no finite key (and no RecursionError)
    shared = [1.0]
    assert value_key([shared, shared]) == value_key([[1.0], [1.0]])  # shared is no cycle


def test_by_value_keeps_the_last_few() -> None:
    memo: ByValue[int] = ByValue(size=2)
    calls: list[int] = []

    def compute(n: int) -> int:
        calls.append(n)
        return n * n

    for n in (1, 2, 1, 3, 2):  # 3 pushes out 2 (1 was used after 2): 2 computed again
        assert memo.get(value_key(n), functools.partial(compute, n)) == n * n
    assert calls == [1, 2, 3, 2]
    assert memo.hits == 1 and len(memo) == 2


def _names(rows: int) -> tuple[list[str], list[str]]:
    return [f"row {i}" for i in range(rows)], ["A", "B", "C"][:rows]


def test_the_rank_check_is_kept_only_for_the_same_jacobian() -> None:
    rank._FOUND.clear()
    labels, owners = _names(3)
    dependent = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]])
    first = find_redundant(dependent, labels, owners)
    assert [(r.row, r.depends_on) for r in first] == [(2, ("A", "B"))]
    assert find_redundant(dependent.copy(), labels, owners) == first
    assert rank._FOUND.hits == 1
    # the third row off the plane of the others by 1e-3: independent, not the kept answer
    moved = dependent.copy()
    moved[2, 2] = 1e-3
    assert find_redundant(moved, labels, owners) == []
    # the same matrix under other names or another tolerance: found again, not reused
    renamed = find_redundant(dependent, labels, ["A", "B", "D"])
    assert [(r.owner, r.depends_on) for r in renamed] == [("D", ("A", "B"))]
    assert find_redundant(moved, labels, owners, tol=1e-2) != []
    assert rank._FOUND.hits == 1
    # a caller changing the returned list never changes the kept result
    find_redundant(dependent, labels, owners).clear()
    assert find_redundant(dependent, labels, owners) == first
