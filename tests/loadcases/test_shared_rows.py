"""The rows two runs share (loadcases.run.global_error.shared_rows): by bisection, the same
pairs as every time's rounded key."""

from __future__ import annotations

import numpy as np

from loadcases.run.global_error import _shared_by_keys, shared_rows


def _times(rng: np.random.Generator, step: float, rows: int) -> np.ndarray:
    """Output times as runs make them: i * step summed or multiplied (last bits apart), an
    event's row repeated, a time off the grid."""
    times = np.arange(rows) * step if rng.random() < 0.5 else np.cumsum(np.full(rows, step)) - step
    times = np.insert(times, rng.integers(1, rows), times[rng.integers(1, rows)])  # an event
    off = rng.integers(1, rows)
    return np.sort(np.insert(times, off, times[off] + rng.uniform(-3e-9, 3e-9)))


def test_shared_rows_are_the_rounded_keys_pairs() -> None:
    """Runs with rows every dt and every 2^k dt (the companion's), uneven last bits, a
    repeated event time and times 1e-9 s off: the pairs of `shared_rows` are those of the
    rounded keys (`_shared_by_keys`) exactly, on 300 random pairs; times out of order
    go to the keys as they are."""
    rng = np.random.default_rng(3)
    found = 0
    for _ in range(300):
        step = rng.choice([1e-3, 1e-4, 0.01, 1.0 / 3.0]) * rng.uniform(0.5, 2.0)
        rows = int(rng.integers(20, 400))
        a = _times(rng, step, rows)
        b = _times(rng, step * 2 ** int(rng.integers(0, 4)), rows // 2)
        expected = _shared_by_keys(a, b)
        got = shared_rows(a, b)
        assert np.array_equal(got[0], expected[0]) and np.array_equal(got[1], expected[1])
        found += len(got[0])
    assert found > 10_000
    shuffled = np.array([0.2, 0.1, 0.3])
    assert [r.tolist() for r in shared_rows(np.array([0.1, 0.3]), shuffled)] == [[0, 1], [1, 2]]


def test_a_companion_at_the_run_s_own_times_pairs_its_last_row_of_a_time() -> None:
    """A companion's rows at the run's very times (every other one, as `sparser` thins
    them) with an event's time twice in both: each pairs with the same time of the other,
    an event's twice with the companion's later row (the last, as the rounded keys'), the
    same pairs as `_shared_by_keys`."""
    a = np.insert(np.arange(40) * 0.0025, 11, 10 * 0.0025)  # rows 10 and 11: an event's
    b = a[::2][:-1]
    b = np.insert(b, 6, b[5])  # the companion's event row: b[5] and b[6] are 0.025 s
    rows, rows_b = shared_rows(a, b)
    expected = _shared_by_keys(a, b)
    assert np.array_equal(rows, expected[0]) and np.array_equal(rows_b, expected[1])
    assert np.array_equal(a[rows], b[rows_b]) and rows_b[rows.tolist().index(10)] == 6
