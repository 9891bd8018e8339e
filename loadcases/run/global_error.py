"""The global error of a dynamic run, estimated, and the tolerance that meets a target.

The integrator controls the local error of each step; what a sizing engineer needs is the
error of the results (each request, over the whole run, relative to its peak). It is
estimated the way Richardson did for whole solutions: the run is compared with a companion
run whose every step is twice as long (the run's own steps two at a time where they are
known, else an error-controlled run at tolerance x 2^(p+1), largest step and output
interval x 2; its rows thinned further to about one per step: loadcases.run.companion), at
their shared output times. For a method of order p the companion's error
is 2^p times the run's, so the run's error is about |run - companion| / (2^p - 1)
(generalized-alpha: p = 2, the difference / 3); a run that passed a near-singular position
is compared with a third, finer run instead (steps half as long, the difference x 4/3:
loadcases.run.companion), whose observed order the summary gives (of the two pairs' largest
history estimates, as differences). On smooth runs the estimate is within 10 %
of the true error (pendulum, heavy top, latch: tests/verification/test_global_error.py);
through impacts and chaotic motion it is an order of magnitude at best, and said to be.

Two errors per request: `history`, the largest difference over the run (a time shift of a
peak counts in full; the column's range once the companion has lost the phase), and
`peak`, the error of its envelope (loadcases.run.peak_error: the crest's error and the
rows' miss of it), the quantity sizing uses. When the case sets `accuracy` and leaves the
tolerance to the engine, a run whose envelope misses the target is solved again with every
step halved (tolerance / 2^(p+1), largest step / 2), the previous run becoming the
companion, until it meets the target, the next halving would go over the budget (`Budget`:
CPU, steps, refinements) or the output interval alone misses the target by more than the
integrator's part of the estimate (no step helps: `_between_rows`); the summary's
`outcome` says which. A tighter run's step limit grows with it (STEP_MARGIN
times the steps it is expected to take, at least the analysis's `max_steps`): the budget,
not a fixed `max_steps`, bounds a long run's tightening. Without `accuracy` the default
target is only estimated against and warned about: each halving costs twice the last run,
which a case asks for, not every case.

A signal (SIGINT, SIGTERM) that stops the companion or a tighter run leaves the run written
with status `interrupted` (a set never reuses it as good): its rows are those of the last
run that finished, and its accuracy block claims nothing it did not compute (`met` null
and no estimate when the companion was stopped).
"""

from __future__ import annotations

import dataclasses
import math
import time as clock
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

import mechlib as ml
from loadcases.foundation import interrupts
from loadcases.foundation.accuracy_target import DEFAULT_ACCURACY
from loadcases.run.beside import CompanionBeside
from loadcases.run.companion import (
    FINER_RATIO,
    NOT_LOADS,
    STEP_RATIO,
    coarser,
    divisor,
    finer,
    grid_divisor,
    grid_eligible,
    largest_step,
    on_grid,
    order,
    output_interval,
    passed_singular,
    request_of,
    request_peaks,
    run_extremes,
    significant,
    sparser,
)
from loadcases.run.peak_error import Extremes, extremes_of, peak_error
from loadcases.schema.case import AccuracyBudget, AccuracyTarget
from mechlib.checks.singularity import NAMED_AT_MOST
from mechlib.core.jit import compile_seconds
from mechlib.core.outcome import interrupt_of

__all__ = [
    "COMPANION_STAGE",
    "DEFAULT_ACCURACY",
    "FINER_STAGE",
    "MAX_TIGHTENINGS",
    "AccuracyEstimate",
    "Aim",
    "Budget",
    "RequestError",
    "accuracy_aim",
    "request_errors",
    "request_of",
    "request_peaks",
    "shared_rows",
    "solve_to_accuracy",
    "tighter_stage",
]

MAX_TIGHTENINGS = 8  # default refinements: each halves every step and costs twice the last
DEFAULT_CPU_BUDGET = 600.0  # s of CPU for the companion and the tighter runs, by default
PHASE_LOST = 0.9  # of a column's range: the companion's difference past it, phase lost
# why a run is not tightened to its target (the summary's outcome says it)
_NO_TARGET = "no accuracy target in the case: the default one is estimated against only"
_TOLERANCE_SET = (
    "the case sets a tolerance, which fixes the steps: drop `tolerance` to let the engine "
    "tighten them"
)


@dataclass(frozen=True)
class Budget:
    """What meeting a target may cost: the companion and the tighter runs together (CPU
    s, integrator steps accepted and rejected, tighter runs); None: no limit."""

    cpu_seconds: float | None = DEFAULT_CPU_BUDGET
    steps: int | None = None
    refinements: int = MAX_TIGHTENINGS

    def summary(self) -> dict:
        """The summary's `accuracy.budget`."""
        return {"cpu": self.cpu_seconds, "steps": self.steps, "refinements": self.refinements}


@dataclass
class Spent:
    """What the estimate and the tightening have cost so far, and the last run's cost."""

    cpu_seconds: float = 0.0
    steps: int = 0
    last_cpu: float = 0.0
    last_steps: int = 0

    def add(self, run: ml.Solution, cpu: float, *, counted: bool, last: bool) -> None:
        """A run solved in `cpu` s: counted unless it is the first run, the `last` run
        (whose cost the next halving doubles) unless it is the companion."""
        steps = run.stats.steps + run.stats.rejected_steps
        if last:
            self.last_cpu, self.last_steps = cpu, steps
        if counted:
            self.cpu_seconds += cpu
            self.steps += steps

    def exhausts(self, budget: Budget, refinements: int) -> str:
        """Why a tighter run (twice the last one's cost) would go over `budget`; ''."""
        if refinements >= budget.refinements:
            return f"budget exhausted: refinements ({budget.refinements})"
        cpu, steps = self.cpu_seconds + 2.0 * self.last_cpu, self.steps + 2 * self.last_steps
        if budget.cpu_seconds is not None and cpu > budget.cpu_seconds:
            return (
                f"budget exhausted: cpu ({budget.cpu_seconds:g} s; {self.cpu_seconds:.3g} s "
                f"spent, the next halving would take about {2.0 * self.last_cpu:.3g} s)"
            )
        if budget.steps is not None and steps > budget.steps:
            return (
                f"budget exhausted: steps ({budget.steps}; {self.steps} spent, the next "
                f"halving would take about {2 * self.last_steps})"
            )
        return ""


@dataclass(frozen=True)
class RequestError:
    """Estimated global error of one request, relative to its peak |value|."""

    history: float  # the largest difference over the run
    peak: float  # of its envelope: max and min
    sampling: float = 0.0  # the part of `peak` the output interval misses between rows


@dataclass
class AccuracyEstimate:
    """What the summary says of a dynamic run's accuracy."""

    target: float
    integrator: str
    tolerance: float
    max_step: float  # the largest step in force (s): analysis.max_step or its default
    max_steps: int  # the run's step limit: analysis.max_steps, or a tighter run's (finer)
    tightenings: int
    requests: dict[str, RequestError]
    cpu_seconds: float  # of the companion and tightened runs
    note: str = ""
    warnings: list[str] = field(default_factory=list)
    estimated: bool = True  # False: no companion finished, `requests` is empty
    budget: Budget | None = None  # None: not tightened, `untightened` says why
    untightened: str = ""  # why not: no target in the case, or its tolerance
    stopped_by: str = ""  # why the tightening stopped short of the target
    measure: str = "peaks"  # what must meet the target: envelope peaks or time histories
    finer: bool = False  # estimated from a finer run (the run passed a singular position)
    observed_order: float | None = None  # of the run, its companion and the finer run
    companion: str = "adaptive"  # on the run's own steps (`grid`) or error-controlled
    splits: int = 0  # the grid companion's doubled steps split where Newton failed
    richardson: float = 3.0  # the divisor of the companion's difference (a grid's: its steps')
    beside: bool = False  # the companion was solved beside the run (loadcases.run.beside)

    @property
    def outcome(self) -> str:
        """`met`, or `not met: ` and why (the budget, which; not tightened; a failure)."""
        if self.met is None:
            return self.note or "not estimated"
        if self.met:
            return "met"
        if self.budget is None:
            why = f" ({self.untightened})" if self.untightened else ""
            return f"not met: not tightened{why}"
        return f"not met: {self.stopped_by or self.note}"

    @property
    def met(self) -> bool | None:
        """Every envelope peak (or time history, as `measure` says) within the target; None
        when nothing was estimated."""
        if not self.estimated:
            return None
        return bool(_worst(self.requests, self.measure) <= self.target)

    @property
    def step_ratio(self) -> float:
        """The steps of the run the estimate compares this one with, over this one's: a
        finer run's (1/2), else the companion's or, after a tightening, the previous
        run's (2)."""
        return FINER_RATIO if self.finer and not self.tightenings else STEP_RATIO

    @property
    def method(self) -> str:
        """How the estimate was made, as the summary says it."""
        if self.finer and self.tightenings == 0:
            pair = (
                "the run passed a near-singular position, where its error need not fall "
                "with the step: this run against a finer one with every step half as long, "
                f"difference x {-1.0 / divisor(self.integrator, FINER_RATIO):.4g}"
            )
        elif self.companion == "grid" and self.tightenings == 0:
            pair = (
                "this run against a companion on the run's own steps two at a time (no "
                f"error test; {self.splits} split back where Newton failed), difference / "
                f"{self.richardson:.4g} (per run step, {divisor(self.integrator):g} in a "
                "companion step of two of the run's, 0 in one of one)"
            )
        else:
            pair = (
                "this run against a companion run with every step twice as long, "
                f"difference / {divisor(self.integrator):g}"
            )
        return (
            f"estimated (Richardson): {pair} (a history whose difference reaches 0.9 of its "
            "range: the range); envelope peaks: of the peaks between rows, or a competing "
            "peak's extrapolated excess, plus the rows' miss of them"
        )

    def summary(self) -> dict:
        """The summary's `accuracy` block."""
        return {
            "target": self.target,
            "met": self.met,
            "integrator": self.integrator,
            "tolerance": self.tolerance,
            "max_step": self.max_step,
            "max_steps": self.max_steps,
            "tightenings": self.tightenings,
            "outcome": self.outcome,
            "measure": self.measure,
            "budget": None if self.budget is None else self.budget.summary(),
            "estimate": {
                name: {"history": e.history, "peak": e.peak, "sampling": e.sampling}
                for name, e in self.requests.items()
            },
            "method": self.method,
            "companion": self.companion,
            "beside": self.beside,
            "step_ratio": self.step_ratio,
            **({} if self.observed_order is None else {"observed_order": self.observed_order}),
            "cpu_seconds": self.cpu_seconds,
            **({"note": self.note} if self.note else {}),
        }


_SAME_TIME = 4e-9  # s: two times that round alike to 1e-9 s are at most 2e-9 s apart


def shared_rows(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row indices of the times `a` and `b` share (output times are rounded alike, to 1e-9
    s; an event's row, at each run's own event time, is shared only where the times agree;
    a time of `a` shared by several rows of `b` pairs with the last). Times of `b` in
    order are looked up by bisection, only those within _SAME_TIME of a time of `a`
    rounded (the same pairs as `_shared_by_keys`, which takes others)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if not bool(np.all(np.diff(b) >= 0.0)):
        return _shared_by_keys(a, b)
    low = np.searchsorted(b, a - _SAME_TIME, side="left")
    high = np.searchsorted(b, a + _SAME_TIME, side="right")
    found = np.flatnonzero(high > low)
    # the last candidate is looked at first: where it is the very time, it is the pair
    # (equal times round alike); the companion's rows are at the run's own times
    exact = b[high[found] - 1] == a[found]
    pairs = list(zip(found[exact].tolist(), (high[found[exact]] - 1).tolist()))
    for i in found[~exact].tolist():
        key = round(float(a[i]), 9)
        near = range(int(high[i]) - 1, int(low[i]) - 1, -1)  # the last first
        last = next((j for j in near if round(float(b[j]), 9) == key), None)
        if last is not None:
            pairs.append((i, last))
    if not pairs:
        return np.zeros(0, int), np.zeros(0, int)
    rows_a, rows_b = np.array(sorted(pairs)).T
    return rows_a, rows_b


def _shared_by_keys(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """`shared_rows` by every time's rounded key (times of `b` in any order)."""
    of_b = {round(t, 9): j for j, t in enumerate(np.asarray(b, dtype=float).tolist())}
    pairs = [
        (i, of_b[key])
        for i, t in enumerate(np.asarray(a, dtype=float).tolist())
        if (key := round(t, 9)) in of_b
    ]
    if not pairs:
        return np.zeros(0, int), np.zeros(0, int)
    rows_a, rows_b = np.array(pairs).T
    return rows_a, rows_b


def request_errors(
    run: ml.Solution,
    companion: ml.Solution,
    order: int,
    ratio: float = STEP_RATIO,
    *,
    richardson: float | None = None,
    interval: float | None = None,
    known: dict[str, Extremes] | None = None,
) -> dict[str, RequestError]:
    """Estimated error of each request of `run` from another run of steps `ratio` times as
    long (a companion, its rows at some of the run's output times; or a finer run, ratio
    1/2), Richardson's (other - run) / (ratio^p - 1), or / `richardson` where given (a
    grid companion's: loadcases.run.companion.grid_divisor). A column of round-off beside
    its request's peak in both runs (`significant` in neither) has no error of its own: it
    is left out (a planar run's out-of-plane columns: docs/performance.md). `interval`: the
    companion's output interval (s), its rows beside the run's crests aside (loadcases.run.
    companion.crest_rows); None: the median of its rows'. `known`: the run's extremes
    found already (loadcases.run.companion.run_extremes)."""
    rows, rows_c = shared_rows(run.time, companion.time)
    scale = 1.0 / (float(ratio) ** order - 1.0 if richardson is None else richardson)
    peaks = request_peaks(run.channels)
    columns = [
        column
        for column in run.channels
        if request_of(column) not in NOT_LOADS
        and column in companion.channels
        and (
            significant(run.channels[column], peaks[request_of(column)])
            or significant(companion.channels[column], peaks[request_of(column)])
        )
        and len(rows)
    ]
    known = known or {}
    missing = [c for c in columns if c not in known]
    table = _table(run.channels, missing, len(run.time))
    computed = dict(zip(missing, extremes_of(run.time, table, _times(run)))) if missing else {}
    mine = [known[c] if c in known else computed[c] for c in columns]
    theirs = extremes_of(
        companion.time,
        _table(companion.channels, columns, len(companion.time)),
        _times(companion),
        interval,
    )
    out: dict[str, RequestError] = {}
    for column, found, other in zip(columns, mine, theirs):
        name, values = request_of(column), run.channels[column]
        history, lost = _history_error(values[rows], companion.channels[column][rows_c], abs(scale))
        peak, sampling = peak_error(found, other, scale, crests=not lost, bound=history)
        before = out.get(name, RequestError(0.0, 0.0))
        out[name] = RequestError(
            max(before.history, history / peaks[name]),
            max(before.peak, peak / peaks[name]),
            max(before.sampling, sampling / peaks[name]),
        )
    return out


def _times(solution: ml.Solution) -> list[float]:
    """The times (s) of the events that fired in `solution`."""
    return [event.time for event in solution.events]


def _table(channels: dict[str, np.ndarray], columns: list[str], rows: int) -> np.ndarray:
    """The `columns` of `channels` side by side, (rows, columns)."""
    table = np.empty((rows, len(columns)))
    for j, column in enumerate(columns):
        table[:, j] = channels[column]
    return table


def _history_error(run: np.ndarray, companion: np.ndarray, scale: float) -> tuple[float, bool]:
    """The run's largest error over its rows (the column's unit) and whether the phase is
    lost (then no crest of the two runs pairs with another: loadcases.run.peak_error
    compares their extremes only; IFToMM A01 over 2000 s paired crests of different
    swings, an estimate of 0.28 of the rate's peak for a true 3.4e-4): Richardson's
    |run - companion| / (2^p - 1) while that difference stays below `PHASE_LOST` of the
    column's range; beyond, the range. Richardson's premise (the companion's error 2^p
    times the run's) holds for a phase error while it is small: for an oscillation of
    amplitude A whose phase errors are f and 4 f, the difference is 2 A |sin(3 f / 2)| and
    the error 2 A |sin(f / 2)|. When the difference reaches 0.9 of the range 2 A (3 f / 2 =
    1.12 rad), Richardson reads 0.82 of the error and the range 2.7 times it; past that the
    difference folds back (the companion a whole period off reads no error at all), and
    the run's phase, hence its error, is known only to within the range (a steady offset
    between the two on a column that hardly moves keeps Richardson's value: the larger)."""
    difference = float(np.nanmax(np.abs(run - companion), initial=0.0))
    finite = run[np.isfinite(run)]
    spread = float(finite.max() - finite.min()) if len(finite) else 0.0
    lost = difference >= PHASE_LOST * spread
    return max(scale * difference, spread if lost else 0.0), lost


class Solver(Protocol):
    """Solves the run with an analysis; `checks` False: without the position checks after
    the run (their warnings), for a companion whose warnings are not kept; `stage`: what a
    solve after the run's own is for (COMPANION_STAGE, FINER_STAGE, `tighter_stage`),
    which a progress bar shows ("" for the run itself); `quiet`: no progress at all (a
    companion solved beside the run, in another thread)."""

    def __call__(
        self, analysis: ml.Dynamic, checks: bool = True, stage: str = "", quiet: bool = False
    ) -> ml.Solution: ...


COMPANION_STAGE = "accuracy: companion run"
FINER_STAGE = "accuracy: finer run at a singular position"


def tighter_stage(n: int) -> str:
    """The stage of the n-th (1, 2, ...) run tightened to meet the accuracy target."""
    return f"accuracy: tighter run {n}"


def solve_to_accuracy(
    solve: Solver,
    analysis: ml.Dynamic,
    target: float,
    *,
    budget: Budget | None,
    measure: str = "peaks",
    untightened: str = "",
    beside: bool = False,
) -> tuple[ml.Solution, AccuracyEstimate | None]:
    """The run (with a `budget`: the first whose envelope peaks, or time histories as
    `measure` says, meet `target`, or the last the budget allowed) and its error estimate
    (None when the run itself failed: a failure says its own where and why; without a
    budget, its outcome says why by `untightened`). A signal during the companion or a
    tighter run: the last run that finished, as `interrupted`. `beside`: the grid
    companion solved beside the run, in another thread (loadcases.run.beside)."""
    spent = Spent()
    run, twin = _first_run(solve, analysis, spent, beside)
    if run.status != "ok":
        return run, None
    started = _cpu()
    aim = Aim(target, budget, measure, untightened)
    try:
        return _estimated(solve, analysis, run, twin, spent, aim, started)
    except (KeyboardInterrupt, SystemError) as stop:  # a signal in the estimate's own work
        if interrupt_of(stop) is None:
            raise
        if twin is not None:
            twin.close()
        estimate = _estimate(analysis, run, target, {}, 0, started)
        estimate.estimated = False
        estimate.note = f"not estimated: interrupted{_by()} while its error was estimated"
        return _interrupted(run, "its error was estimated", estimated=False), estimate


def _estimated(
    solve: Solver,
    analysis: ml.Dynamic,
    run: ml.Solution,
    twin: CompanionBeside | None,
    spent: Spent,
    aim: Aim,
    started: float,
) -> tuple[ml.Solution, AccuracyEstimate]:
    """`solve_to_accuracy` after the run: its companion (the one beside it, `twin`, where
    it followed), the finer pair, the tightening, the estimate."""
    target, budget, measure, untightened = aim.target, aim.budget, aim.measure, aim.untightened
    p = order(analysis.integrator)
    try:
        found = run_extremes(run)
        companion, kind, fallback = _companion(solve, analysis, run, spent, found, twin)
    finally:
        started -= _settled(twin, spent)
    if companion.status != "ok":
        estimate = _estimate(analysis, run, target, {}, 0, started)
        estimate.estimated, estimate.companion = False, kind
        if companion.status == "interrupted":
            estimate.note = f"not estimated: interrupted{_by()} while the companion run was solved"
            return _interrupted(run, "its accuracy companion was solved", estimated=False), estimate
        estimate.note = f"not estimated: the companion run failed ({companion.message})"
        return run, estimate
    coarse = _coarse(analysis, run, companion, kind, found)
    errors = coarse.errors
    pair = _finer_pair(solve, analysis, run, coarse, spent) if passed_singular(run) else None
    if pair is not None:
        errors = pair.errors
    pending = pair.solved if pair is not None else None
    note, tightenings, stopped_by = fallback, 0, ""
    if twin is not None and twin.failure:
        note = _joined(
            f"the companion beside the run failed ({twin.failure}): solved after it", note
        )
    stopped = pair is not None and pair.interrupted
    during = "a finer run at a singular position was solved for its error estimate"
    while budget is not None and not stopped and _worst(errors, measure) > target:
        stopped_by = spent.exhausts(budget, tightenings)
        if measure == "peaks":
            stopped_by = stopped_by or _between_rows(errors, target)
        if stopped_by:
            break
        finer_analysis, finer_run = pending or _solved_finer(
            solve, analysis, spent, tighter_stage(tightenings + 1)
        )
        pending = None
        if finer_run.status == "interrupted":
            why = f"tightening interrupted{_by()}: the estimate is of the run written"
            note = _joined(note, why)
            stopped, during = True, "a tighter run was solved to meet the accuracy target"
            break
        if finer_run.status != "ok":
            why = f"a tighter run failed ({finer_run.message}): the estimate is of this one"
            note = _joined(note, why)
            break
        errors = request_errors(finer_run, run, p)
        run, analysis, tightenings = finer_run, finer_analysis, tightenings + 1
    estimate = _estimate(analysis, run, target, errors, tightenings, started)
    estimate.note, estimate.budget, estimate.stopped_by = note, budget, stopped_by
    estimate.untightened = untightened
    estimate.measure, estimate.companion = measure, kind
    estimate.beside = twin is not None and twin.used and kind == "grid"
    estimate.richardson = coarse.divisor
    estimate.splits = companion.stats.rejected_steps if kind == "grid" else 0
    if estimate.splits:
        estimate.note = _joined(
            f"{estimate.splits} of the grid companion's doubled steps split back into the "
            "run's two (Newton failed on them)",
            estimate.note,
        )
    if pair is not None:
        estimate.finer, estimate.note = not pair.note, _joined(pair.note, estimate.note)
        estimate.observed_order = pair.observed_order if tightenings == 0 else None
    estimate.warnings = _warnings(estimate, budget is not None)
    if stopped:
        run = _interrupted(run, during)
    return run, estimate


def _coarse(
    analysis: ml.Dynamic,
    run: ml.Solution,
    companion: ml.Solution,
    kind: str,
    extremes: dict[str, Extremes] | None = None,
) -> Coarse:
    """The companion's estimate: a grid companion's Richardson divisor from the steps it
    took (a stretch's odd last step and its splits merging fewer of the run's:
    loadcases.run.companion.grid_divisor), the adaptive one's 2^p - 1."""
    p = order(analysis.integrator)
    found = 0.0
    if kind == "grid":
        found = grid_divisor(analysis.integrator, run.stats.step_ends, companion.stats.step_ends)
    richardson = found if found > 0.0 else divisor(analysis.integrator)
    errors = request_errors(
        run,
        companion,
        p,
        richardson=richardson,
        interval=output_interval(analysis, run),
        known=extremes,
    )
    return Coarse(errors, richardson)


def _companion(
    solve: Solver,
    analysis: ml.Dynamic,
    run: ml.Solution,
    spent: Spent,
    found: dict[str, Extremes] | None = None,
    twin: CompanionBeside | None = None,
) -> tuple[ml.Solution, str, str]:
    """The run's companion solved: on the run's own steps (`grid`) where they are known
    (`twin`: the one solved beside the run, where it could be), else, or where that one
    fails, the adaptive one (a note says why); with its kind (`found`: the run's
    extremes, loadcases.run.companion.run_extremes)."""
    grid = on_grid(analysis, run, found)
    note = ""
    companion = _followed(twin, grid, spent) if twin is not None else None
    if grid is not None:
        if companion is None:
            companion = _timed(solve, grid, spent, companion=True, stage=COMPANION_STAGE)
        if companion.status in ("ok", "interrupted"):
            return companion, "grid", ""
        note = (
            f"the companion on the run's own steps failed ({companion.message}): "
            "estimated with an error-controlled companion"
        )
    adaptive = _timed(
        solve, sparser(coarser(analysis), run, found), spent, companion=True, stage=COMPANION_STAGE
    )
    return adaptive, "adaptive", note


def _first_run(
    solve: Solver, analysis: ml.Dynamic, spent: Spent, beside: bool
) -> tuple[ml.Solution, CompanionBeside | None]:
    """The run solved, with its grid companion beside it (`beside`, where it may have
    one); the companion withdrawn where the run did not finish."""
    twin = CompanionBeside(solve, analysis) if beside and grid_eligible(analysis) else None
    try:
        run = _timed(solve, analysis if twin is None else twin.run_analysis, spent, counted=False)
    except BaseException:
        if twin is not None:
            twin.withdraw("the run stopped")
        raise
    if run.status != "ok" and twin is not None:
        twin.withdraw("the run did not finish")
    return run, twin


def _settled(twin: CompanionBeside | None, spent: Spent) -> float:
    """The companion beside the run stopped, however the estimate got here (a signal
    while the run's extremes were read too); its CPU (s, in its own thread), which the
    estimate's includes, counted in `spent` where the estimate was not made from it."""
    if twin is None:
        return 0.0
    twin.close()
    if not twin.used:
        spent.cpu_seconds += twin.cpu_seconds
    return twin.cpu_seconds


def _followed(twin: CompanionBeside, grid: ml.Dynamic | None, spent: Spent) -> ml.Solution | None:
    """The companion solved beside the run, on `grid` (`on_grid`'s), counted; None where
    it could not be (withdrawn, as where the run has no grid: the caller solves one now);
    a signal while it is awaited: an interrupted companion (`_interrupted_solve`)."""
    try:
        companion = twin.finish(grid)
    except KeyboardInterrupt as stop:
        return _interrupted_solve(stop)
    if companion is not None:
        spent.add(companion, twin.cpu_seconds, counted=True, last=False)
    return companion


def _timed(
    solve: Solver,
    analysis: ml.Dynamic,
    spent: Spent,
    *,
    counted: bool = True,
    companion: bool = False,
    stage: str = "",
) -> ml.Solution:
    """A run solved and its cost (`_cpu`) added to `spent` (the first run's not `counted`);
    the companion without the position checks after the run (only its channels are
    used); `stage`: what a further run is for (`Solver`)."""
    started = _cpu()
    if counted:
        run = _further(solve, analysis, checks=not companion, stage=stage)
    else:
        run = solve(analysis)
    spent.add(run, _cpu() - started, counted=counted, last=not companion)
    return run


def _cpu() -> float:
    """This thread's CPU time (s: a companion beside the run counts its own) but what the
    process spent making kernels (mechlib.core.jit.compile_seconds): the first run of a
    process loads or compiles them, once; a tighter run would not, and the estimate's own
    cost is not theirs."""
    return clock.thread_time() - compile_seconds()


@dataclass
class FinerPair:
    """The estimate of a run that passed a singular position, from a third run of steps half
    as long (loadcases.run.companion): the finer run (`solved`, with its analysis: the first
    tightening's, when a target asks for one), the errors from that pair, the observed
    order of the three runs (None: not measured) and what went wrong."""

    errors: dict[str, RequestError]
    solved: tuple[ml.Dynamic, ml.Solution] | None = None
    observed_order: float | None = None
    note: str = ""
    interrupted: bool = False


def _finer_pair(
    solve: Solver,
    analysis: ml.Dynamic,
    run: ml.Solution,
    coarse: Coarse,
    spent: Spent,
) -> FinerPair:
    """The finer pair's estimate; the companion's (`coarse`) with a note when the finer
    run failed or was interrupted."""
    finer_analysis, fine = _solved_finer(solve, analysis, spent, FINER_STAGE)
    if fine.status != "ok":
        why = "interrupted" + _by() if fine.status == "interrupted" else fine.message
        note = f"the finer run at a singular position did not finish ({why}): estimated "
        return FinerPair(
            coarse.errors,
            note=note + "from the companion only",
            interrupted=fine.status == "interrupted",
        )
    errors = request_errors(run, fine, order(analysis.integrator), FINER_RATIO)
    coarse_diff = _worst(coarse.errors, "history") * coarse.divisor
    fine_diff = _worst(errors, "history") * -divisor(analysis.integrator, FINER_RATIO)
    observed = math.log2(coarse_diff / fine_diff) if coarse_diff > 0 < fine_diff else None
    return FinerPair(errors, (finer_analysis, fine), observed)


@dataclass(frozen=True)
class Coarse:
    """The companion's estimate: its errors and the Richardson divisor they were made with."""

    errors: dict[str, RequestError]
    divisor: float


def _solved_finer(
    solve: Solver, analysis: ml.Dynamic, spent: Spent, stage: str
) -> tuple[ml.Dynamic, ml.Solution]:
    """The run with every step half as long (`companion.finer`), solved (as `stage`) and
    counted."""
    finer_analysis = finer(analysis, spent.last_steps)
    return finer_analysis, _timed(solve, finer_analysis, spent, stage=stage)


@dataclass(frozen=True)
class Aim:
    """What a dynamic run's estimate is judged against, and what meeting it may cost."""

    target: float  # of each request's peak
    budget: Budget | None  # None: the steps are not tightened; `untightened` says why
    measure: str = "peaks"  # what must meet the target: envelope peaks or time histories
    untightened: str = ""


def accuracy_aim(accuracy: float | AccuracyTarget | None, tolerance: float | None) -> Aim:
    """The case's `analysis.accuracy` (and `tolerance`) as an aim: absent, the default
    target estimated against, not tightened; a number, that target of the envelope peaks
    within the default budget; a mapping, its target, budget (keys not given: the
    default's) and measure. A tolerance fixes the steps: then nothing is tightened."""
    if accuracy is None:
        return Aim(DEFAULT_ACCURACY, None, untightened=_NO_TARGET)
    if not isinstance(accuracy, AccuracyTarget):
        accuracy = AccuracyTarget.model_validate({"target": accuracy})  # the number's mapping
    if tolerance is not None:
        return Aim(accuracy.target, None, accuracy.measure, _TOLERANCE_SET)
    return Aim(accuracy.target, _budget(accuracy.budget), accuracy.measure)


def _budget(given: AccuracyBudget | None) -> Budget:
    """The budget a case gives (`accuracy.budget`), keys not given the default's."""
    default = Budget()
    if given is None:
        return default
    return Budget(
        default.cpu_seconds if given.cpu is None else given.cpu,
        given.steps,
        default.refinements if given.refinements is None else given.refinements,
    )


def _further(
    solve: Solver, analysis: ml.Dynamic, checks: bool = True, stage: str = ""
) -> ml.Solution:
    """A companion or tighter run (`stage`: which, `Solver`); a signal met outside mechlib's
    solve loop (while the system is built) stops it the same way: an interrupted run
    without rows."""
    try:
        return solve(analysis, checks=checks, stage=stage)
    except KeyboardInterrupt as stop:
        return _interrupted_solve(stop)


def _interrupted_solve(stop: KeyboardInterrupt) -> ml.Solution:
    """A further run a signal stopped before mechlib's solve loop could keep its rows."""
    return ml.Solution(
        "interrupted", str(stop), "dynamic", np.zeros(0), {}, result=ml.Status.INTERRUPTED
    )


def _joined(*notes: str) -> str:
    """The notes given, in order, those not empty."""
    return "; ".join(filter(None, notes))


def _by() -> str:
    """` by SIGTERM`: the signal that stopped this process ("" for another interrupt)."""
    signum = interrupts.received()
    return "" if signum is None else f" by {interrupts.signal_name(signum)}"


def _interrupted(run: ml.Solution, during: str, *, estimated: bool = True) -> ml.Solution:
    """`run`, finished, saved as interrupted: a signal stopped the work on its accuracy."""
    error = "with their estimated error" if estimated else "their error is not estimated"
    return dataclasses.replace(
        run,
        status="interrupted",
        result=ml.Status.INTERRUPTED,
        message=f"{run.message}; then interrupted{_by()} while {during}: the run's "
        f"{len(run.time)} rows are kept, {error}",
    )


def _between_rows(errors: dict[str, RequestError], target: float) -> str:
    """Why shorter steps cannot meet `target`: the output interval alone misses a peak by
    more, and by at least the rest of that peak's estimate (''  when no request does).

    The rest, the peak's estimate less the rows' miss, bounds the integrator's part of it
    (of the column the miss is of, whichever column the peak's estimate is of). The rows
    carry the integrator's error too (between its steps they are interpolated:
    mechlib.solvers.dense), and the crest read through them is off by about that error, so
    a miss estimated below the integrator's part may be that error, which shorter steps
    reduce: the pendulum's rows every 4 ms read the reaction's crest 1.26e-5 of its peak
    above them (1.3 times the closed form's 9.5e-6, its integrator's part 7.9e-5), every
    0.5 ms 1.5e-6 (14 times the closed form's 1.0e-7; 1.1e-7 at tolerance 1e-9). A
    target of 1e-5 at 4 ms was given up on before a halving; met after four, the rows'
    miss read 9.46e-6 as the closed form's (docs/performance.md)."""
    missed = [
        (name, e.sampling)
        for name, e in errors.items()
        if e.sampling > target and e.sampling >= e.peak - e.sampling
    ]
    if not missed:
        return ""
    name, sampling = max(missed, key=lambda item: item[1])
    return (
        f"the output interval misses {name}'s peak between rows by about "
        f"{sampling:.2g} of the peak, more than the target: shorter steps do not "
        "reduce that, a shorter analysis.step does"
    )


def _worst(errors: dict[str, RequestError], measure: str) -> float:
    """The largest estimated error of the envelope peaks (`peaks`) or time histories."""
    return max((e.peak if measure == "peaks" else e.history for e in errors.values()), default=0)


def _estimate(
    analysis: ml.Dynamic,
    run: ml.Solution,
    target: float,
    errors: dict[str, RequestError],
    tightenings: int,
    started: float,
) -> AccuracyEstimate:
    """The estimate of `run`, solved with `analysis`: its largest step the one in force,
    the default's value when the analysis sets none."""
    return AccuracyEstimate(
        target,
        analysis.integrator,
        analysis.tolerance,
        largest_step(analysis) if run.max_step is None else run.max_step,
        analysis.max_steps,
        tightenings,
        errors,
        _cpu() - started,
    )


def _warnings(estimate: AccuracyEstimate, tightened: bool) -> list[str]:
    """A warning when the envelope peaks miss the target, another when time histories do:
    the worst requests named with their estimates, at most NAMED_AT_MOST, the others
    counted."""
    out = []
    how = (
        f"after {estimate.tightenings} tightenings (tolerance {estimate.tolerance:.3g}"
        f"{'; ' + estimate.stopped_by if estimate.stopped_by else ''})"
        if tightened
        else f"at tolerance {estimate.tolerance:.3g} (not tightened)"
    )
    for measure, text in (
        ("peak", "envelope peaks"),
        ("history", "time histories (a peak shifted in time counts in full)"),
    ):
        values = {n: float(getattr(e, measure)) for n, e in estimate.requests.items()}
        missed = sorted(((v, n) for n, v in values.items() if v > estimate.target), reverse=True)
        if missed:
            listed = ", ".join(f"{n} {value:.2g}" for value, n in missed[:NAMED_AT_MOST])
            if len(missed) > NAMED_AT_MOST:
                others = len(missed) - NAMED_AT_MOST
                listed += f" and {others} other request{'s' if others > 1 else ''}"
            out.append(
                f"accuracy: estimated error of the {text} above the target {estimate.target:g} "
                f"of the peak {how}: {listed}"
            )
    return out
