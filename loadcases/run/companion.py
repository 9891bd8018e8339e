"""The accuracy companion of a dynamic run: a run of steps twice as long, and the factor
that turns the difference of the two into the run's error (Richardson).

The companion takes every step twice as long as the run. For a method of order p its
error is 2^p times the run's, so the run's is the difference / (2^p - 1)
(generalized-alpha: p = 2, the difference / 3). Two kinds (the summary's accuracy block
says which was used, `companion`, and the compared run's steps over the run's,
`step_ratio`):
- `grid` (`on_grid`): the run's own accepted steps two at a time (t0 -> t2 -> t4 ...
  within each stretch between events, an event's time and the end staying step ends:
  mechlib.model.step_grid.StepGrid.paired), with no error test and no rejected attempts:
  Richardson on a fixed mesh pair of ratio exactly 2, the classical global extrapolation
  (Hairer, Norsett & Wanner I, II.9). A doubled step Newton cannot take is split back into
  the run's two steps there (the companion's rejected steps count them; the estimate's
  note says how many); past SPLIT_SHARE of its steps it stops, and the adaptive one is
  used. Its Newton iterations stop at the adaptive companion's tolerance
  (x 2^(p+1)). Where the run's steps are not known (Radau, steps landing on the output
  times, a whole-run kernel that keeps no record of them: the modal one) or the grid
  companion fails, the adaptive one.
- `adaptive` (`coarser`): an independent error-controlled run at tolerance x 2^(p+1) (the
  local error goes as h^(p+1)), largest step and output interval x 2.

Its rows are thinned: with dense output a row costs about half a step (its projection onto
the constraints and its reactions: the bench slider-crank's 1001 rows are 2/3 of its run),
and the run's rows may far outnumber the companion's steps. The companion's output interval
is doubled further until its rows are at most its expected steps (the run's accepted steps
/ 2): the difference of the two runs varies no faster than the motion the companion's
steps resolve, so a row per step samples it. Its rows still fall on the run's own output
times (every k-th), where the two are compared; the continuous peaks (the parabola's
vertex through a crest's rows, loadcases.run.peak_error) are found on the thinner rows as
on the run's. Measured on the estimate/true table (benchmarks/error_table.py) the ratios
stay within a few per cent of those with every second row, and the companion of the bench
slider-crank costs 0.31 of its run instead of 0.52 (docs/performance.md).

The grid companion's error is the run's Richardson multiple only where it merged two of
the run's steps: `grid_divisor` counts, of each step the companion took, the run's steps it
merged (m), and divides the difference by the mean over the run's steps of m^p - 1: a
stretch's odd last step taken alone, or a split pair, counts 0 (the companion made the
run's error there), so a companion with splits no longer leans low by their share (the
oscillator's divisor 2.967 and 2.992 for 3).

The run's steps four at a time (Richardson's 4^p - 1 = 15) were measured on 2026-11-30
(docs/performance.md, "Four at a time"): they cost 0.16-0.27 of a run against 0.26-0.66
two at a time and hold the estimate/true table on the smooth cases, but read the flap
latches' latch and hinge forces' peaks 2.8-9.2 times the true error (two at a time
1.1-2.7) and no test the run itself allows separated that case from the good ones: not
used.

A run that passed a near-singular position (a warning of its own: the constraints close to
losing rank, mechlib.checks.singularity) gets a third run, of steps half as long (`finer`),
and its error is estimated from that finer pair: (fine - run) / (2^-p - 1), the difference
x 4/3. At a singular crossing the error is made where the chain leaves the crossing and
need not fall with the step: on IFToMM A02 (N = 40, 3-D, 20 s; measured at main 35ebc77)
the crank angle's largest error is 1.13 rad at the default tolerance, 1.27 at the
companion's and 0.35 at the finer run's, so the companion differs from the run by 0.32 rad
(Richardson's 0.11: a tenth of the error) and the finer run by 0.79 (x 4/3: 1.05). The
observed order of the three, log2(|run - companion| / |fine - run|), is p where
Richardson's asymptotics hold (both pairs then agree) and -1.3 there; the finer pair is the
nearer to that range whichever way the observed order departs from p, so it is used
whenever it exists, and the observed order is reported. It costs one more run of twice
the steps, only where a run passed a singular position; a tightening to meet a target
starts from it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

import mechlib as ml
from loadcases.foundation.noise_floor import NOISE_FLOOR
from loadcases.run.peak_error import (
    END,
    SPIKE,
    Extremes,
    extremes_of,
    row_peaks,
    standing_out,
)
from mechlib.checks.singularity import NEAR_SINGULAR

__all__ = [
    "CREST_ROWS",
    "FINER_RATIO",
    "NOT_LOADS",
    "SPIKE_ROWS",
    "SPLIT_SHARE",
    "STEP_RATIO",
    "coarser",
    "crest_rows",
    "divisor",
    "finer",
    "grid_divisor",
    "grid_eligible",
    "largest_step",
    "on_grid",
    "order",
    "output_interval",
    "passed_singular",
    "request_of",
    "request_peaks",
    "run_extremes",
    "significant",
    "sparser",
    "spikes",
    "thinning",
]

STEP_RATIO = 2  # the companion's steps over the run's
NOT_LOADS = ("abscissa",)  # requests of no error to estimate: a set's abscissa column
_ORDER = {"generalized-alpha": 2, "radau": 3}  # global order assumed (Radau's index-1 parts: 3)


def order(integrator: str) -> int:
    """The global order p assumed for `integrator`."""
    return _ORDER.get(integrator, 2)


def _local_factor(integrator: str, ratio: float) -> float:
    """Tolerance factor that makes the steps `ratio` times as long: the local error goes
    as h^(p+1)."""
    return float(ratio) ** (order(integrator) + 1)


def largest_step(analysis: ml.Dynamic) -> float:
    """The largest step the analysis sets (s); with dense output and no max_step, 0: its
    default, the mechanism's natural time, bounds the steps (mechlib.solvers.dense), the
    same in the companion and finer runs (the run's own value: `Solution.max_step`)."""
    if analysis.dense:
        return analysis.max_step or 0.0
    return min(analysis.max_step or analysis.step, analysis.step)


def coarser(analysis: ml.Dynamic) -> ml.Dynamic:
    """The companion: every step `STEP_RATIO` times as long (output interval too)."""
    return dataclasses.replace(
        analysis,
        tolerance=analysis.tolerance * _local_factor(analysis.integrator, STEP_RATIO),
        max_step=STEP_RATIO * largest_step(analysis) or None,
        step=STEP_RATIO * analysis.step,
    )


def sparser(
    companion: ml.Dynamic, run: ml.Solution, found: dict[str, Extremes] | None = None
) -> ml.Dynamic:
    """The companion with dense output and its output interval doubled until its rows are
    at most its expected steps (the run's accepted steps / STEP_RATIO: `thinning`), rows at
    each of the run's `spikes` and the run's rows about its columns' extreme crests
    (`crest_rows`; `found`: the run's `run_extremes`, when known); with steps ending on the
    outputs (`output: steps`) the interval bounds the steps: unchanged."""
    if not companion.dense or len(run.time) < 2:
        return companion
    found = run_extremes(run) if found is None else found
    rows = sorted(set(spikes(run, found) + crest_rows(run, found)))
    return dataclasses.replace(
        companion, step=companion.step * 2 ** thinning(run), rows=tuple(rows)
    )


def output_interval(analysis: ml.Dynamic, run: ml.Solution) -> float | None:
    """The companion's output interval (s) for `run` solved with `analysis` (`sparser`: its
    rows beside the run's crests and spikes aside, which the estimate does not count as
    its interval); None without dense output (its rows are its steps')."""
    return coarser(analysis).step * 2 ** thinning(run) if analysis.dense else None


def thinning(run: ml.Solution) -> int:
    """The doublings of a dense companion's output interval (`sparser`): until its rows
    are at most its expected steps (the run's accepted steps / STEP_RATIO)."""
    steps = max(run.stats.steps / STEP_RATIO, 1.0)
    rows = (len(run.time) - 1) / STEP_RATIO
    return max(0, math.ceil(math.log2(rows / steps))) if rows > steps else 0


CREST_ROWS = 3  # the run's rows either side of a column's extreme crest a thinned companion keeps


def run_extremes(run: ml.Solution) -> dict[str, Extremes]:
    """The extremes (loadcases.run.peak_error) of each of the run's columns above round-off
    (`significant`), by column: what the companion's rows and the estimate read of the
    run, found once."""
    peaks = request_peaks(run.channels)
    names = [
        c
        for c, v in run.channels.items()
        if request_of(c) not in NOT_LOADS
        and v.shape == run.time.shape
        and significant(v, peaks[request_of(c)])
    ]
    if len(run.time) < 3 or not names:
        return {}
    table = np.column_stack([run.channels[c] for c in names])
    return dict(zip(names, extremes_of(run.time, table, [e.time for e in run.events])))


def crest_rows(run: ml.Solution, found: dict[str, Extremes]) -> list[float]:
    """The times (s) of the rows a companion keeps at the run's envelope crests: per column
    (above round-off), where its largest or its smallest value is a smooth crest's vertex
    between rows, the crest's row and CREST_ROWS of the run's rows either side (none where
    an event lies among them). A companion's crest read through rows 2 to 8 times as far
    apart misses a sharp crest by far more than the integrator's error (a free
    slider-crank's rod force at its dead centres: 124.8 N through 4 ms rows against the
    run's 127.7 N through 2 ms, an estimate 3.6 times the true error; 24.85 N against 26.63
    N with 16 ms rows, 12 times); through the run's own rows it is read as the run's is, and
    the two vertices compared (loadcases.run.peak_error, `dense_beside`). A peak at a row
    (a kink, a contact's onset) has no vertex whose fit the two share: the companion's other
    rows are kept there (the door let go's handle torque, a row at 0.27 s 3.6 N below its
    true peak: read on the run's rows the two runs agree within 0.8 N, an estimate of 0.08
    of the true error; through the companion's own rows 0.35). `found`: the run's
    `run_extremes`."""
    events = np.array([event.time for event in run.events])
    times: set[float] = set()
    for column in found.values():
        for candidates, sign in ((column.tops, 1.0), (column.bottoms, -1.0)):
            if not len(candidates):
                continue
            at, value, kind = candidates[np.argmax(sign * candidates[:, 1])]
            if kind == END:  # an end row's peak is compared on the end rows both runs have
                continue
            i = int(np.searchsorted(run.time, at))
            near = run.time[max(i - CREST_ROWS, 0) : i + CREST_ROWS + 1]
            if (
                sign * (value - column.values[i]) > 0.0
                and not ((events >= near[0]) & (events <= near[-1])).any()
            ):
                times.update(near.tolist())
    return sorted(times)


SPIKE_ROWS = (0.25, 0.5, 0.75)  # the companion's rows either side of a spike's, of the run's
# row intervals there: a contact pulse about a row interval long (the door let go's guide,
# 10 ms rows) is read to within a few per cent of its crest


def request_of(column: str) -> str:
    """`pivot_force.fx` -> `pivot_force`."""
    return column.rsplit(".", 1)[0]


def request_peaks(channels: dict[str, np.ndarray]) -> dict[str, float]:
    """Per request: the largest finite |value| of any of its columns."""
    peaks: dict[str, float] = {}
    for column, values in channels.items():
        finite = np.abs(values[np.isfinite(values)])
        name = request_of(column)
        peaks[name] = max(peaks.get(name, 0.0), float(finite.max(initial=0.0)))
    return peaks


def significant(values: np.ndarray, peak: float) -> bool:
    """Whether a column's finite `values` exceed NOISE_FLOOR of its request's `peak` (the
    largest finite |value| of any of the request's columns, whatever their units; not a
    set's `report.noise_floor`): at or below, its rows are round-off (a planar
    slider-crank's out-of-plane reactions, 1e-50 N beside tens of newtons; the door
    jettison's out-of-plane velocity, 1e-15 of the in-plane one), with a crest or a
    "spike" at almost every row and no error of the integrator's to estimate. False
    where the peak is 0."""
    largest = float(np.abs(values[np.isfinite(values)]).max(initial=0.0))
    return peak > 0.0 and largest > NOISE_FLOOR * peak


def _standing_out(table: np.ndarray) -> np.ndarray:
    """Per column of `table` (rows, columns): whether a row stands out from both its
    neighbours, above or below, by more than peak_error.SPIKE of the column's range (the
    columns `row_peaks` may find a spike in)."""
    with np.errstate(invalid="ignore"):
        spread = np.nanmax(table, axis=0) - np.nanmin(table, axis=0)
    return np.asarray(standing_out(table, SPIKE * spread).any(axis=0))


def spikes(run: ml.Solution, found: dict[str, Extremes]) -> list[float]:
    """The times (s) of the companion's rows at the run's one-row spikes: each row where a
    column's largest or smallest value is a row with no crest between rows
    (`peak_error.row_peaks`: a spike, a jump's corner), and rows at SPIKE_ROWS of the
    run's row intervals either side of it (none across an event); its end rows and events'
    rows left out (the companion has its own there). The companion's thinned rows would
    step over such a row, and Richardson compare the run's peak with another place's (the
    door let go's contact spike, 3834 N at 0.05 s, 0 at 0.04 and 0.06 s, the companion's
    rows 0.02 s apart: 14 times its true error); the rows beside it read what the run's
    rows miss of the spike (loadcases.run.peak_error._at_row_peak). A smooth crest's peak
    is its vertex between rows: its rows are `crest_rows`'. `found`: the run's
    `run_extremes` (its columns above round-off)."""
    if not found:
        return []
    table = np.column_stack([run.channels[c] for c in found])
    # the only columns that may hold one: cheap
    kept = {
        t
        for column, standing in zip(found.values(), _standing_out(table))
        if standing
        for t in row_peaks(column)
    }
    events = np.array([event.time for event in run.events])
    times = []
    for t in sorted(kept):
        i = int(np.searchsorted(run.time, t))
        if not 0 < i < len(run.time) - 1 or np.isin(t, events):
            continue
        times.append(t)
        for side in (run.time[i - 1], run.time[i + 1]):
            if not ((events > min(t, side)) & (events < max(t, side))).any():
                times.extend(t + f * (side - t) for f in SPIKE_ROWS)
    return [float(t) for t in sorted(set(times))]


# the grid companion's splits allowed, of its steps: a split pair is two steps of the run's
# own size, where the companion's error is the run's, not 2^p times it, so each split
# takes its part out of the difference; past this share the estimate would lean low and
# the adaptive companion is used (IFToMM A05: 361 of 1678 steps split, its history
# estimates 0.43-0.60 of the true error on the motions, against 1.3-2.8 adaptive; its cost
# 0.75 of the run against 0.44)
SPLIT_SHARE = 0.02


def on_grid(
    analysis: ml.Dynamic, run: ml.Solution, found: dict[str, Extremes] | None = None
) -> ml.Dynamic | None:
    """The grid companion of `run` (solved with `analysis`): its accepted steps two at a
    time, its events' times kept as step ends, rows and Newton tolerance as the adaptive
    companion's (`sparser(coarser(...))`); None where the run's steps are not all known
    (then the adaptive companion)."""
    ends = run.stats.step_ends
    if not grid_eligible(analysis) or not ends:
        return None
    last = run.events[-1].time if run.events else analysis.end
    if (
        len(ends) != run.stats.steps
        or not np.isclose(ends[-1], [analysis.end, last], 0.0, 1e-9).any()
    ):
        return None  # its steps not all recorded, or it ended neither at the end nor an event
    most = math.ceil(SPLIT_SHARE * len(ends) / STEP_RATIO)
    grid = ml.StepGrid.paired(ends, [event.time for event in run.events], most)
    return dataclasses.replace(sparser(coarser(analysis), run, found), grid=grid)


def grid_eligible(analysis: ml.Dynamic) -> bool:
    """Whether a run solved with `analysis` may have a grid companion (`on_grid` checks
    the rest on the run): generalized-alpha's dense steps, of its own error control."""
    return (
        analysis.dense
        and analysis.integrator == "generalized-alpha"
        and not analysis.fixed_step
        and analysis.grid is None
    )


def grid_divisor(
    integrator: str, run_ends: Sequence[float], companion_ends: Sequence[float]
) -> float:
    """Richardson's divisor for a grid companion that took the steps ending at
    `companion_ends` (s) on a run of steps ending at `run_ends` (s): the mean over the
    run's steps of m^p - 1, m the run's steps within the companion's step that holds it.
    A companion step of m of the run's steps makes m^(p+1) times their local error where
    the run makes m times it: their difference m (m^p - 1) of one step's, so a merged
    pair counts 3 a run's step (p = 2), a single one (a stretch's odd last step, a split
    half) 0; on a grid of pairs only, 2^p - 1; 0 where either has no step."""
    run_t, comp_t = np.asarray(run_ends, float), np.asarray(companion_ends, float)
    if not len(run_t) or not len(comp_t):
        return 0.0
    tiny = 1e-12 * max(1.0, float(np.abs(run_t).max()))
    counts = np.diff(np.searchsorted(run_t, comp_t + tiny), prepend=0)
    p = order(integrator)
    return float(np.sum(counts * (counts.astype(float) ** p - 1.0)) / max(counts.sum(), 1))


STEP_MARGIN = 2.0  # a tighter run's step limit: this many times the steps it is expected to take


def finer(analysis: ml.Dynamic, last_steps: int = 0) -> ml.Dynamic:
    """Every step half as long; the output interval unchanged; the step limit the larger
    of the analysis's and STEP_MARGIN times the steps expected (twice the `last_steps` of
    the run it halves): a long run is limited by the budget, not by a fixed max_steps."""
    return dataclasses.replace(
        analysis,
        tolerance=analysis.tolerance / _local_factor(analysis.integrator, 2),
        max_step=0.5 * largest_step(analysis) or None,
        max_steps=max(analysis.max_steps, math.ceil(STEP_MARGIN * 2 * last_steps)),
    )


def divisor(integrator: str, ratio: float = STEP_RATIO) -> float:
    """Richardson's r^p - 1 for another run of steps `ratio` times as long (a finer one:
    ratio 1/2, negative): the run's error is (other - run) / divisor."""
    return float(ratio) ** order(integrator) - 1.0


FINER_RATIO = 0.5  # the third run's steps over the run's, at a singular position


def passed_singular(run: ml.Solution) -> bool:
    """Whether the run's rows passed a near-singular position (a warning of its own)."""
    return any(warning.startswith(NEAR_SINGULAR) for warning in run.warnings)
