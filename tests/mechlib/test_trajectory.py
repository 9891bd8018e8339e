"""Trajectory.stacked: the recorded rows of q, qd, qdd or lam as one array, whatever mix
of rows recorded one by one (`record`) and blocks of a compiled run (`extend`) holds them,
equal to stacking the row lists; a view when one block holds them all; right after `trim`
and a new block. Snapshots: each row's, whether recorded as a dict or made from a block's
base and angle references when read; the runs of rows with the same active equations."""

from __future__ import annotations

import numpy as np
import pytest

from mechlib.model.analysis import Trajectory

NQ, M = 3, 2


def _state(t: float) -> np.ndarray:
    """q, qd, qdd, lam stacked (3 NQ + M), each entry distinct: 100 t + column."""
    return 100.0 * t + np.arange(3 * NQ + M, dtype=float)


ACTIVE = np.arange(4)  # the active equations of every row but those given `other`
KEYS = [("hinge", "angle"), ("crank", "angle")]


def _snapshot(t: float, active=ACTIVE) -> dict:
    """A row's snapshot: its angle references are 10 t and 20 t."""
    return {"active": active, "angles": {KEYS[0]: 10.0 * t, KEYS[1]: 20.0 * t, "other": -1.0}}


def _record(trajectory: Trajectory, t: float, active=ACTIVE) -> None:
    s = _state(t)
    snapshot = _snapshot(t, active)
    trajectory.record(t, s[:NQ], s[NQ : 2 * NQ], s[2 * NQ : 3 * NQ], s[3 * NQ :], snapshot)


def _extend(trajectory: Trajectory, times: list[float], active=ACTIVE) -> None:
    refs = np.array([[10.0 * t, 20.0 * t] for t in times])
    base = _snapshot(-5.0, active)  # its own references are overwritten row by row
    trajectory.extend(times, np.array([_state(t) for t in times]), NQ, base, KEYS, refs)


def _mixed() -> Trajectory:
    """Rows 0 (record), 1-4 (a block), 5 (record), 6-8 (a block), 9-10 (a block)."""
    trajectory = Trajectory()
    _record(trajectory, 0.0)
    _extend(trajectory, [1.0, 2.0, 3.0, 4.0])
    _record(trajectory, 5.0)
    _extend(trajectory, [6.0, 7.0, 8.0])
    _extend(trajectory, [9.0, 10.0])
    return trajectory


@pytest.mark.parametrize("name", ["q", "qd", "qdd", "lam"])
@pytest.mark.parametrize("first,end", [(0, 11), (1, 5), (2, 4), (3, 7), (5, 6), (4, 10), (6, 11)])
def test_stacked_equals_the_stacked_rows(name: str, first: int, end: int) -> None:
    trajectory = _mixed()
    rows = np.array(getattr(trajectory, name)[first:end])
    np.testing.assert_array_equal(trajectory.stacked(name, first, end), rows)
    assert trajectory.stacked(name, first, end).shape == (end - first, M if name == "lam" else NQ)


def test_stacked_is_a_view_within_one_block() -> None:
    trajectory = _mixed()
    inside = trajectory.stacked("qd", 6, 9)
    assert inside.base is not None  # a slice of the block, no copy
    np.testing.assert_array_equal(inside[:, 0], [100.0 * t + NQ for t in (6.0, 7.0, 8.0)])
    np.testing.assert_array_equal(trajectory.stacked("q")[:, 0], 100.0 * np.arange(11.0))


def test_stacked_after_trim_and_a_new_block() -> None:
    """A row an interrupt half-appended is trimmed; the block then added holds new rows:
    stacked reads those, not the trimmed block's old ones."""
    trajectory = _mixed()
    trajectory.q.pop()  # row 10 half-appended: only q lost it
    trajectory.trim()
    assert len(trajectory) == 10
    _extend(trajectory, [20.0, 21.0])
    np.testing.assert_array_equal(
        trajectory.stacked("lam")[:, 0], [100.0 * t + 3 * NQ for t in [*range(10), 20, 21]]
    )


def test_stacked_of_no_rows() -> None:
    assert Trajectory().stacked("q").shape[0] == 0
    assert _mixed().stacked("q", 4, 4).shape[0] == 0


def test_each_row_has_its_own_snapshot() -> None:
    """Rows recorded one by one and rows of blocks read back the same snapshots: the
    block's base with the row's angle references (and the base's other entries); a row's
    dict is made once and kept; negative indices count from the end."""
    trajectory = _mixed()
    for i, t in enumerate(trajectory.time):
        assert trajectory.references[i] == _snapshot(t)
        assert trajectory.references[i]["active"] is ACTIVE
    assert trajectory.references[3] is trajectory.references[3]
    assert trajectory.references[-1] == _snapshot(10.0) and len(trajectory.references) == 11
    assert [s["angles"][KEYS[1]] for s in trajectory.references] == [20.0 * t for t in range(11)]


def test_rows_with_the_same_active_equations() -> None:
    """same_active: the end of the run of rows from `first` recorded with the same active
    equations (the same array), at most `most` rows, across blocks and single rows."""
    other = np.arange(3)
    trajectory = Trajectory()
    _extend(trajectory, [0.0, 1.0, 2.0])
    _record(trajectory, 3.0)
    _extend(trajectory, [4.0, 5.0])
    _extend(trajectory, [6.0, 7.0, 8.0], other)  # an event changed the equations
    _record(trajectory, 9.0, other)
    _record(trajectory, 10.0)
    assert trajectory.same_active(0, 100) == 6
    assert trajectory.same_active(1, 3) == 4
    assert trajectory.same_active(4, 100) == 6
    assert trajectory.same_active(6, 100) == 10
    assert trajectory.same_active(7, 2) == 9
    assert trajectory.same_active(10, 100) == 11
    trajectory.references[7]  # a row's dict made: the same answer
    assert trajectory.same_active(6, 100) == 10


def test_snapshots_after_trim() -> None:
    trajectory = _mixed()
    trajectory.q.pop()
    trajectory.trim()
    _extend(trajectory, [20.0])
    assert len(trajectory.references) == 11
    assert trajectory.references[9] == _snapshot(9.0)
    assert trajectory.references[10] == _snapshot(20.0)
