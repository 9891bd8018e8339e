"""A prescribed step grid: the step ends a generalized-alpha run follows instead of choosing
its steps by its error estimate (the accuracy companion on another run's own steps,
loadcases.run.companion)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["SAME_TIME", "StepGrid"]

SAME_TIME = 1e-12  # relative: a stop this close to a step end is that end


@dataclass(frozen=True, eq=False)
class StepGrid:
    """Step ends (s) to follow: `ends` (n,) increasing, the last the analysis's end;
    `middles` (n,): the end of the first of the two steps that each end's step merges
    (NaN where it is a single step). A step goes from t to the first end after t; where
    Newton cannot take it, to its middle, then on to its end (the split: the two steps of
    the run the grid was made from); `most_splits`: the splits allowed (None: any), one
    more fails the run. No error test: the grid is the step size's rule
    (mechlib.solvers.genalpha.rules.on_grid)."""

    ends: np.ndarray
    middles: np.ndarray
    most_splits: int | None = None

    @classmethod
    def paired(
        cls,
        step_ends: Sequence[float] | np.ndarray,
        stops: Sequence[float] | np.ndarray = (),
        most_splits: int | None = None,
    ) -> StepGrid:
        """Every two consecutive steps of a run merged into one (its accepted steps' end
        times `step_ends`, s, increasing), within each stretch between the `stops` (s:
        its event times), which stay step ends as the last end does; a stretch of an odd
        number of steps ends with a single one."""
        t = np.asarray(step_ends, dtype=float)
        ends, middles = [], []
        for stretch in np.split(t, _stop_indices(t, stops)):
            pairs = len(stretch) // 2
            ends.append(stretch[1 : 2 * pairs : 2])
            middles.append(stretch[0 : 2 * pairs : 2])
            if len(stretch) % 2:
                ends.append(stretch[-1:])
                middles.append(np.array([np.nan]))
        if not ends:
            return cls(np.zeros(0), np.zeros(0), most_splits)
        return cls(np.concatenate(ends), np.concatenate(middles), most_splits)

    @property
    def steps(self) -> int:
        """The grid's steps (without splits)."""
        return len(self.ends)

    # what a stepper asks of any grid it follows (this one, or a GrowingGrid:
    # mechlib.model.step_feed, whose answers wait for the run it is made from)

    def covering(self, t: float) -> tuple[np.ndarray, np.ndarray, float]:
        """The ends and middles (s) to step along from t (s), all of them, and how far (s)
        the steps may go: to the analysis's end (inf)."""
        return self.ends, self.middles, math.inf

    def allows_split(self, splits: int) -> bool:
        """Whether one more split may follow `splits` already made (`most_splits`)."""
        return self.most_splits is None or splits < self.most_splits

    def dropped_rows(self) -> np.ndarray | None:
        """Output times (s) whose rows the run leaves out of its results: none."""
        return None


def _stop_indices(t: np.ndarray, stops: Sequence[float] | np.ndarray) -> list[int]:
    """The positions after which `t` is cut: just after each step end that is a stop."""
    cuts = []
    for stop in stops:
        k = int(np.searchsorted(t, stop))
        for j in (k - 1, k):
            if 0 <= j < len(t) - 1 and abs(t[j] - stop) <= SAME_TIME * max(1.0, abs(stop)):
                cuts.append(j + 1)
    return sorted(set(cuts))
