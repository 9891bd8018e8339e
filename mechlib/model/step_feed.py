"""A step grid made while the run it comes from is solved: an accuracy companion beside its run.

A run given a `StepFeed` (`Dynamic.feed`) records its accepted steps' end times and its
events in the feed's lists as it takes them (they are its SolverStats.step_ends and its
event log). A companion given a `GrowingGrid` of that feed (`Dynamic.grid`), solved in
another thread, steps along the run's steps two at a time as they come: a step that needs
an end the run has not reached waits for it (`covering`), until the grid is `complete`d
with the StepGrid the whole run makes (loadcases.run.companion.on_grid) or `withdraw`n (the
companion's solve then raises GridWithdrawn).

The pairs made as the steps come are those of the whole run's grid (StepGrid.paired):
within each stretch between the run's events, from its first step. A step end is paired
once the next one is recorded, by when its event, if any, is logged (mechlib.solvers.march
settles an event's step and fires the event before it steps on); a stretch's odd last step
waits for the end of its stretch. `complete` checks that the pairs handed out are the whole
run's first ones: where they are not, it refuses, and the caller withdraws the grid.
"""

from __future__ import annotations

import math
import threading
from bisect import bisect_right

import numpy as np

from mechlib.model.step_grid import SAME_TIME, StepGrid

__all__ = ["GridWithdrawn", "GrowingGrid", "StepFeed"]

WAIT_SECONDS = 0.05  # a step waiting for the run looks again at least this often


class StepFeed:
    """What a run records for a companion beside it, as it goes: its accepted steps' end
    times (s, in order) and its events (mechlib EventRecord, with their `time`, s);
    `changed` is notified at each record of step ends; `compiled_steps`: how many of them
    the whole-run kernel took (mechlib.solvers.genalpha.run), the others Python;
    `followed`: a companion still follows them (the run hands them on sooner while it
    does: mechlib.solvers.genalpha.call_rows)."""

    def __init__(self) -> None:
        self.changed = threading.Condition()
        self.ends: list[float] = _Notifying(self.changed)
        self.events: list = []
        self.compiled_steps = 0
        self.followed = True  # False once the grid that follows it is withdrawn


class _Notifying(list):
    """A list that notifies a condition after each append and extend (of step ends)."""

    def __init__(self, changed: threading.Condition) -> None:
        super().__init__()
        self._changed = changed

    def append(self, value) -> None:
        super().append(value)
        self._notify()

    def extend(self, values) -> None:
        super().extend(values)
        self._notify()

    def _notify(self) -> None:
        with self._changed:
            self._changed.notify_all()


class GridWithdrawn(Exception):
    """The grid a companion follows will not be completed (its run failed, was interrupted,
    or its steps make no grid): the companion stops."""


class GrowingGrid:
    """The step grid of a `StepFeed`'s run, paired as its steps come (module docstring);
    the interface of StepGrid that a stepper uses, each answer waiting for the run as
    needed."""

    def __init__(self, feed: StepFeed) -> None:
        self.feed = feed
        self._ends: list[float] = []  # the pairs made so far: their ends and middles (s)
        self._middles: list[float] = []
        self._start = 0  # the first of the run's step ends not in a pair yet
        self._final: StepGrid | None = None
        self._dropped: np.ndarray | None = None
        self._withdrawn = ""

    # what the one who solves the run does

    def complete(self, grid: StepGrid, dropped_rows: np.ndarray | None = None) -> bool:
        """The run is done and `grid` is its whole grid; `dropped_rows`: output times (s)
        whose rows the companion leaves out of its results (`dropped_rows`). False, and
        nothing done, when the pairs handed out so far are not the grid's first ones."""
        with self.feed.changed:  # not while `_grow` extends the pairs
            n = len(self._ends)
            made = np.array(self._ends), np.array(self._middles)
            if n > len(grid.ends) or not (
                np.array_equal(grid.ends[:n], made[0])
                and np.array_equal(grid.middles[:n], made[1], equal_nan=True)
            ):
                return False
            self._dropped = dropped_rows
            self._final = grid
            self.feed.changed.notify_all()
        return True

    @property
    def completed(self) -> bool:
        """Whether the grid is complete (its run done)."""
        return self._final is not None

    @property
    def withdrawn(self) -> str:
        """Why the grid was withdrawn ('' while it is not)."""
        return self._withdrawn

    def withdraw(self, why: str = "withdrawn") -> None:
        """The grid will not be completed: a step waiting for it, or the next, stops."""
        self._withdrawn = why
        self.feed.followed = False
        self._notify()

    # what a stepper asks of it

    @property
    def most_splits(self) -> int | None:
        """The whole grid's splits allowed (None until it is complete)."""
        return None if self._final is None else self._final.most_splits

    def covering(self, t: float) -> tuple[np.ndarray, np.ndarray, float]:
        """The ends and middles (s) to step along from t (s), from two ends before the
        first after t (rules.on_grid reads the same step there), and how far (s) the steps
        may go: the last end made, or inf once the grid is complete. Waits until an end
        after t is made or the grid is complete."""
        tiny = 1e-12 * max(1.0, abs(t))
        while True:
            self._check()
            final = self._final
            if final is not None:
                k = max(0, int(np.searchsorted(final.ends, t + tiny)) - 2)
                return final.ends[k:], final.middles[k:], math.inf
            if self._ends and self._ends[-1] > t + tiny:
                k = max(0, bisect_right(self._ends, t + tiny) - 2)
                return np.array(self._ends[k:]), np.array(self._middles[k:]), self._ends[-1]
            self._grow_or_wait()

    def allows_split(self, splits: int) -> bool:
        """Whether one more split may follow `splits`: the whole grid's limit, waited
        for (the run's last steps set it)."""
        while self._final is None:
            self._check()
            self._wait()
        return self._final.allows_split(splits)

    def dropped_rows(self) -> np.ndarray | None:
        """Output times (s) whose rows the companion leaves out of its results (`complete`)."""
        return self._dropped

    def _check(self) -> None:
        if self._withdrawn:
            raise GridWithdrawn(self._withdrawn)

    def _grow_or_wait(self) -> None:
        """Pair what the run recorded; where nothing is left to pair, wait for it."""
        with self.feed.changed:  # held from the look to the wait: no record is missed
            if not self._grow():
                self._wait()

    def _wait(self) -> None:
        with self.feed.changed:
            if self._final is None and not self._withdrawn:
                self.feed.changed.wait(WAIT_SECONDS)

    def _notify(self) -> None:
        with self.feed.changed:
            self.feed.changed.notify_all()

    def _grow(self) -> bool:
        """Pair the run's step ends recorded since the last call, each once the next one
        is (module docstring); whether a pair was made."""
        n = len(self.feed.ends) - 1  # read before the events: all of theirs are logged
        if n <= self._start:
            return False
        stops = np.array([event.time for event in self.feed.events], dtype=float)
        ends = np.array(self.feed.ends[self._start : n])
        grid = StepGrid.paired(ends, stops)
        made_ends, made_middles = grid.ends, grid.middles
        if len(made_ends) and np.isnan(made_middles[-1]) and not _is_stop(ends[-1], stops):
            made_ends, made_middles = made_ends[:-1], made_middles[:-1]  # may pair on
        if not len(made_ends):
            return False
        self._start += int(np.searchsorted(ends, made_ends[-1])) + 1
        self._ends.extend(made_ends.tolist())
        self._middles.extend(made_middles.tolist())
        return True


def _is_stop(t: float, stops: np.ndarray) -> bool:
    """Whether step end t (s) is one of the events' times `stops` (s)."""
    return bool(np.any(np.abs(stops - t) <= SAME_TIME * np.maximum(1.0, np.abs(stops))))
