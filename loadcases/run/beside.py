"""The grid companion solved beside its run, in a second thread: the estimate in the run's time.

`loads run CASE` where a second core is free (`beside_by_default`) starts the accuracy
companion on the run's own steps (loadcases.run.companion.on_grid) with the run, not after
it: the run records its steps as it takes them (mechlib.model.step_feed.StepFeed) and the
companion, in another thread, takes them two at a time as they come, waiting for the run
where it catches up (the compiled kernels release the GIL). When the run ends the
companion's grid is completed with the one `on_grid` makes of the whole run. The companion
records a row at each of the run's output times (which rows the estimate reads is known
only from the whole run: its crests, its thinning), and its results leave out, before its
requests are evaluated, the output rows the companion after the run would not have had
(its events' rows stay; row-integrated columns such as `energy.dissipated` then sum the
same rows). It is then the companion solved after the run, step for step and row for row,
and its estimate is the same to the last bit (tests/loadcases/test_companion_beside.py).
A run whose one-row spikes ask for companion rows between its own (loadcases.run.companion.
spikes: the door let go's contact, a block on its stop) cannot be served so: its companion
beside is dropped when the run ends and solved again after it (the CPU of both spent).

Its CPU is the same as after the run, and more by its extra rows; what it saves is wall
time, on a core the run leaves idle: a set's runs already fill the cores, so a set solves
its companions after their runs. It follows only a run worth following (FOLLOW_AFTER,
FOLLOW_SECONDS). Where the run cannot have a grid companion (its steps not all recorded,
a failed run, or pairs that are not the whole run's) the companion beside it is withdrawn
and the estimate is made as before, after the run.
"""

from __future__ import annotations

import dataclasses
import os
import threading
import time

import numpy as np

import mechlib as ml
from loadcases.run.companion import coarser
from mechlib.model.analysis import row_times, same_times
from mechlib.model.step_feed import GridWithdrawn, GrowingGrid, StepFeed

__all__ = ["CompanionBeside", "beside_by_default"]

JOIN_SECONDS = 0.05  # how often the wait for the companion lets a signal through
GRACE_SECONDS = 1.0  # a signal's wait for the companion to stop
FREE_CORES = 1.0  # cores less the load average that `beside_by_default` asks for
ENVIRONMENT = "LOADS_COMPANION_BESIDE"  # 1: beside, 0: after the run, whatever the load
# The companion follows a run whose steps so far were mostly taken by the compiled
# whole-run kernel (which releases the GIL: steps taken in Python hold it, and the two
# threads would take turns) and whose FOLLOW_AFTER steps after its first ones (its setup
# and its kernels' loading before them) came at a pace that takes the run from there at
# least FOLLOW_SECONDS of wall time (below, the thread and the companion's extra rows cost
# about what they save: docs/performance.md). Else it is solved after the run.
FOLLOW_AFTER = 64
FOLLOW_SECONDS = 0.1


def beside_by_default() -> bool:
    """Whether a single run's companion is solved beside it: as the environment's
    `LOADS_COMPANION_BESIDE` says (1 or 0), else where there are two cores or more that
    this process may use and the machine's load (its 1-minute average) leaves FREE_CORES
    of them free (a test suite's or a script's other solves keep it after the run)."""
    said = os.environ.get(ENVIRONMENT, "").strip()
    if said in ("0", "1"):
        return said == "1"
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cores = os.cpu_count() or 1
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):  # not a Unix: the cores alone
        load = 0.0
    return cores >= 2 and cores - load >= FREE_CORES


class CompanionBeside:
    """The grid companion of one run, solved in a thread as the run is: `run_analysis`
    is the run's (it records its steps), `finish` completes the companion's grid once the
    run is done and waits for it, `withdraw` stops it."""

    def __init__(self, solve, analysis: ml.Dynamic) -> None:
        self.feed = feed = StepFeed()
        self.run_analysis = dataclasses.replace(analysis, feed=feed)
        self.grid = GrowingGrid(feed)
        # every row of the run's: those it does not read are left out at the end (`finish`)
        self.analysis = dataclasses.replace(
            coarser(analysis), step=analysis.step, rows=(), grid=self.grid
        )
        self.solution: ml.Solution | None = None
        self.cpu_seconds = 0.0
        self.used = False  # `finish` gave its solution
        self.failure = ""  # what stopped it where it failed (the estimate's note says)
        self._thread = threading.Thread(
            target=self._solve, args=(solve,), name="accuracy companion", daemon=True
        )
        self._thread.start()

    def _solve(self, solve) -> None:
        started = time.thread_time()
        try:
            # the run's first steps: its setup done (the memo the two share filled:
            # mechlib.solvers.solve_memo) and its kernels loaded; then its pace
            first = self._await_steps(1)
            paced = time.perf_counter()
            self._await_steps(first + FOLLOW_AFTER)
            if not self._worth_following(first, time.perf_counter() - paced):
                self.grid.withdraw("not worth following")
                return
            self.solution = solve(self.analysis, checks=False, quiet=True)
        except GridWithdrawn:
            self.solution = None
        except Exception as error:  # noqa: BLE001 - the estimate falls back to the companion after the run
            self.failure = f"{type(error).__name__}: {error}"
            self.grid.withdraw(f"failed: {self.failure}")
            self.solution = None
        finally:
            self.cpu_seconds = time.thread_time() - started

    def _await_steps(self, count: int) -> int:
        """Wait until the run has recorded `count` step ends, or is done; how many it has
        recorded (GridWithdrawn where the grid is withdrawn)."""
        feed = self.feed
        with feed.changed:
            while len(feed.ends) < count and not self.grid.completed:
                if self.grid.withdrawn:
                    raise GridWithdrawn(self.grid.withdrawn)
                feed.changed.wait(JOIN_SECONDS)
            return len(feed.ends)

    def _worth_following(self, first: int, took: float) -> bool:
        """Whether the run's steps so far were mostly compiled and those after its first
        `first` ones, which took `took` s of wall time, came at a pace that takes the run
        from there at least FOLLOW_SECONDS (False: the run ended first)."""
        feed, end = self.feed, self.analysis.end
        ends = feed.ends[first - 1 :]
        if self.grid.completed or 2 * feed.compiled_steps < len(feed.ends) or len(ends) < 2:
            return False
        return took * (end - ends[0]) >= (ends[-1] - ends[0]) * FOLLOW_SECONDS

    def finish(self, grid_analysis: ml.Dynamic | None) -> ml.Solution | None:
        """The companion on the grid of `grid_analysis` (`on_grid`'s for the run: None
        where the run has none), its rows those `grid_analysis` asks for; None where it
        cannot be (withdrawn: the caller solves one after the run). A signal while it is
        awaited withdraws it and is raised."""
        if self.grid.withdrawn:  # it did not follow the run
            self._thread.join()
            return None
        if grid_analysis is None or grid_analysis.grid is None:
            self.withdraw("the run has no grid companion")
            return None
        recorded, kept = row_times(self.analysis), row_times(grid_analysis)
        if len(_dropped(kept, recorded)):  # a row the run's output times do not hold
            self.withdraw("the companion's rows are not among the run's")
            return None
        assert isinstance(grid_analysis.grid, ml.StepGrid), "on_grid's"
        if not self.grid.complete(grid_analysis.grid, _dropped(recorded, kept)):
            self.withdraw("its pairs are not the run's grid")
            return None
        try:
            while self._thread.is_alive():
                self._thread.join(JOIN_SECONDS)
        except KeyboardInterrupt:
            self.withdraw("interrupted", GRACE_SECONDS)
            raise
        self.used = self.solution is not None
        return self.solution

    def close(self) -> None:
        """Withdraw it if it is still solved (the estimate goes on without it)."""
        if self._thread.is_alive():
            self.withdraw("the estimate goes on without it", GRACE_SECONDS)

    def withdraw(self, why: str, within: float | None = None) -> None:
        """Stop the companion (a step waiting for the run, or its next) and wait for it
        (at most `within` s: a signal's exit does not wait on its requests; the thread, a
        daemon, stops at its next step or ends with the process)."""
        self.grid.withdraw(why)
        self._thread.join(within)


def _dropped(recorded: np.ndarray, kept: np.ndarray) -> np.ndarray:
    """The output times (s) among `recorded` that are not `kept` (sorted)."""
    recorded = np.asarray(recorded, dtype=float)
    return recorded[~same_times(recorded, np.asarray(kept, dtype=float))]
