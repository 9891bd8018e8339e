"""The estimate/true tables' row matching (benchmarks.error_table.matched_rows): a run and
its reference compared at the times both have, an event's rows before and after its
actions each with its own."""

from __future__ import annotations

import numpy as np

from benchmarks.error_table import matched_rows


def test_rows_match_at_shared_times_and_on_both_sides_of_an_event() -> None:
    """The run's rows every 2 ms, its event at 3 ms between them (one row there: the state
    before its actions) and at 4 ms on an output time (two rows); the reference's every
    1 ms, both events with two rows. The 3 ms rows pair before with before only, the 4 ms
    rows both sides; the reference's own output times the run lacks are left out."""
    run = np.array([0.0, 0.002, 0.003, 0.004, 0.004, 0.006])
    reference = np.array([0.0, 0.001, 0.002, 0.003, 0.003, 0.004, 0.004, 0.005, 0.006])
    rows, rows_ref = matched_rows(run, reference)
    pairs = sorted(zip(rows.tolist(), rows_ref.tolist()))
    assert pairs == [(0, 0), (1, 2), (2, 3), (3, 5), (4, 6), (5, 8)]
    np.testing.assert_array_equal(run[rows], reference[rows_ref])
    plain = np.array([0.0, 0.002, 0.004])  # no events: the times alike
    assert sorted(zip(*(a.tolist() for a in matched_rows(plain, reference[[0, 2, 5]])))) == [
        (0, 0),
        (1, 1),
        (2, 2),
    ]
