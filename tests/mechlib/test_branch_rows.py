"""Snap-throughs between recorded rows (mechlib.solvers.branches.row_changes): a joint angle
that jumps far more than in the rows beside it, against smooth motion and model changes."""

from __future__ import annotations

import math

import numpy as np

from mechlib.model.analysis import BranchCheck
from mechlib.solvers.branches import row_changes

TIMES = np.linspace(0.0, 1.0, 11)


def test_a_jump_between_two_rows_is_named_with_its_time_and_values() -> None:
    """A knee creeping 0.5 deg per row jumps from +5 to -5 deg between 0.5 and 0.6 s."""
    knee = np.radians(np.r_[np.linspace(2.5, 5.0, 6), np.linspace(-5.0, -3.0, 5)])
    (change,) = row_changes(TIMES, {"knee": knee, "strut": TIMES}, BranchCheck())
    assert change.time == TIMES[6]
    assert [
        (j, round(math.degrees(a), 6), round(math.degrees(b), 6)) for j, a, b in change.joints
    ] == [("knee", 5.0, -5.0)]


def test_smooth_fast_motion_and_a_jump_at_an_event_are_silent() -> None:
    """A joint turning 60 deg per row (fast, even) is no jump; a jump in the interval that
    starts at an event (a release or a lock changes the model there) is left out."""
    fast = np.radians(60.0 * np.arange(11))
    step = np.where(TIMES > 0.55, 1.0, 0.0)
    assert row_changes(TIMES, {"fast": fast}, BranchCheck()) == []
    assert row_changes(TIMES, {"released": step}, BranchCheck(), event_times=[0.5]) == []
    assert len(row_changes(TIMES, {"released": step}, BranchCheck())) == 1
