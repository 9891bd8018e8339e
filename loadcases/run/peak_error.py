"""The error of an envelope peak: the integrator's part (Richardson on the continuous peaks of
the run and its companion) plus the sampling part (the peak between output rows).

An envelope takes a request's largest and smallest value over the output rows, so its error
has two parts: the error of the solution at the peak, and the peak missed between two rows
(for a smooth signal up to |v''| dt^2 / 8 at output interval dt, order 2 in dt whatever the
integrator). The continuous peak is the highest vertex of the parabolas through each local
maximum of the rows and its two neighbours (its error is order 3 in dt, one better than the
row's), so

    peak error <= |P_run - P_companion| / (2^p - 1) + (P_run - row peak of the run)

with P the continuous peak of each run: the first term is Richardson's estimate of the
continuous peak's error, on peaks the output interval no longer blurs (the companion's
doubled interval would otherwise add its own, four times larger, sampling error to the
difference), the second the run's own sampling error. Their sum (the triangle inequality,
not their signed sum) bounds the error: the signed sum lets the two cancel, and measured
on IFToMM A01 over 10 s it fell to 0.11-0.43 of the true error (the sum: 0.49-0.92;
docs/performance.md). A peak at the first or last row, or one whose neighbours do not curve down
(a kink, a plateau), has no vertex: its row is its value.

Competing extremes. The envelope's peak is the highest of the run's candidates (each local
crest's vertex, or its row, and the two end rows), and the true one the highest of their
true values: where a lower candidate's true value exceeds the run's top, the envelope's
error is that excess, which Richardson on the top alone cannot see (Andrews' squeezer:
gamma's smallest value at its last row in the run and its companion, 0.040743 and 0.040647,
at an interior trough in the truth, 0.040635; estimate/true 0.30). Each lower candidate's
true value is estimated by Richardson's extrapolation, P + (P - C) / (2^p - 1), with C the
companion's highest candidate within the two runs' row intervals of it; the peak error
is the larger of the top's estimate and the largest excess of an extrapolated candidate
over the top (measured: Andrews 0.30 -> 2.0 on the four requests). Single crests are
compared only where the companion's rows are at most twice as far apart as the run's: a
companion thinned to 8 times the run's interval (the closed-valve servo: 15 rows per
period of its 84 Hz ringing) read each crest up to 4e-3 low by the parabola's vertex,
which the extrapolation took for the integrator's error (the stroke's estimate 12 times
its true error, against 2.3 with the top alone); the quartic reads a smooth crest there
within 2.3e-5, and with element states linear between steps (before mechlib.solvers.
dense_states) the servo's pressures and force in rows sparser than the companion's steps
missed each crest by a different amount, up to (omega h)^2 / 8 = 7.7e-3 of it (the crest
against the same crest there: 5.3 times the true error, the extremes 3.4; IFToMM A04's
rates, thinned 4 times: 3.35 against 1.69). Even at twice
the interval a vertex's difference holds its fit error beside the integrator's: it is
what finds Andrews' trough (the run's vertex 0.040853, the companion's 0.041385, the
truth 0.040635), and it overestimates an error of 2e-6 (Andrews' delta, docs/performance.md).
The run's peak is compared with the companion's candidate at the same crest (or end row),
not with the companion's own peak, which may be another crest with an error of its own
(IFToMM A05's hinge force: the run's lowest trough at 3.56 s, the companion's at 0.48 s,
where a stiff spring's unresolved ringing is 12 times the run's; 3.7 times the true error
against 2.85 matched), under the same rule: the companion's rows at most twice as far
apart as the run's, its extreme otherwise. Crests pair only where the two runs keep their
phase: once the history's difference
reaches 0.9 of the range (loadcases.run.global_error), the extremes alone are compared
(IFToMM A01 over 2000 s paired crests of different swings: 0.28 of the rate's peak for a
true 3.4e-4). Crests are matched by bisection, an end row with an end row only.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from mechlib.outputs.crests import (
    crest_match,
    crest_table,
    crest_tops,
    quartic_rises,
    scaled_groups,
)

__all__ = ["Extremes", "extremes", "extremes_of", "peak_error", "row_peaks", "standing_out"]


END = 1.0  # a candidate's kind: an end row (0: a crest)
_FLIP = np.array([1.0, -1.0, 1.0])  # a minimum's candidates as a maximum's
_BESIDE = [0, 1, 3, 4]  # a crest's five rows but its own
SPARSEST = 2.0 * (1.0 + 1e-6)  # the other run's row interval over the run's, at most,
# for single crests to be compared (competing crests; the run's peak against the same
# crest): the companion's STEP_RATIO, unthinned


@dataclass(frozen=True)
class Extremes:
    """Largest and smallest value of one column: at the rows and continuous (between rows)."""

    row_max: float
    row_min: float
    max: float
    min: float
    tops: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # (time s, value, kind)
    bottoms: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # of the minima
    interval: float = 0.0  # the typical row interval (s): the median one
    time: np.ndarray = field(default_factory=lambda: np.zeros(0))  # the rows' (s)
    values: np.ndarray = field(default_factory=lambda: np.zeros(0))  # the column's rows


def _curvature(time: np.ndarray, values: np.ndarray, k: int) -> tuple[np.ndarray, ...]:
    """Per interior row i (rows k to n-k-1): the parabola through rows i-k, i, i+k, as its
    slope at row i and its curvature coefficient c (v = v_i + slope dt + c dt^2); `values`
    one column (n,) or several (n, columns), each column on its own."""
    n = len(values)
    h1 = time[k : n - k] - time[: n - 2 * k]
    h2 = time[2 * k :] - time[k : n - k]
    if values.ndim == 2:
        h1, h2 = h1[:, None], h2[:, None]
    v0, v1, v2 = values[: n - 2 * k], values[k : n - k], values[2 * k :]
    with np.errstate(divide="ignore", invalid="ignore"):
        d1, d2 = (v1 - v0) / h1, (v2 - v1) / h2
        c = (d2 - d1) / (h1 + h2)
        return d1 + c * h1, c  # NaN at an event's two rows of one time (no crest there)


def _highest(
    time: np.ndarray, values: np.ndarray, events: np.ndarray
) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """Per column of `values` (n, columns), each with a finite row: (largest finite row,
    largest vertex or row, the candidates: (time, value, kind) of each local crest, its
    vertex or its row (kind 0), and of the two end rows (kind END)), the columns at once
    (compiled over the rows and columns: mechlib.outputs.crests; the same values as
    numpy's arrays, tests/loadcases/test_peak_error.py). The vertex
    of the
    parabola through each
    row higher than its two neighbours (a row level with one is a plateau or the corner of
    a step, such as a friction torque switching on: no crest between rows), where the
    three curve down and their times increase (a peak between rows lower than an end row
    counts too). A smooth crest lies at most half a row interval h from its highest row,
    so it rises at most |c| (h / 2)^2 above it; c is taken too from the rows two apart,
    which the rows' own noise (the projections of dense output, 1e-5 of a reaction) sways
    four times less, and the smaller rise kept. The parabolas through the rows beside
    (one row earlier and one later) must curve down as well, by the same rule: a smooth
    crest curves them alike, where a jump does not (the IFToMM A05 flyball's spring
    tension leaps from 0 to 44 N in its first row, and the parabola through that corner read
    a crest 5 N above it: an estimate 4 times its true error). A crest with two rows on
    either side is read by the quartic through those five (`_quartic_rise`; within the same
    bounds): the parabola's vertex is order 4 in the row interval, and a companion thinned
    to 15 rows a period (the closed-valve servo) read its crest up to 7e-4 low, where its
    integrator's error is 1e-5 (the stroke's estimate 3.97 times its true error, 1.42 with
    the quartic, whose miss there is at most 2.3e-5). An end whose four rows hold an event
    (`events`, s) between them is its row (`_ends`)."""
    ends = _ends(time, values, events)
    if len(values) < 3:
        row_max = np.max(np.where(np.isfinite(values), values, -np.inf), axis=0)
        return row_max, row_max.copy(), ends
    table = np.ascontiguousarray(values)
    row_max, rows, columns, rise, bound = crest_table(time, table)
    top, found = crest_tops(
        time, table, rows, columns, _quartic_rises(time, table, rows, columns, rise, bound),
        bound, row_max,
    )  # fmt: skip
    return row_max, top, _with_ends(found, columns, ends, top)


def _with_ends(
    found: np.ndarray, columns: np.ndarray, ends: list[np.ndarray], top: np.ndarray
) -> list[np.ndarray]:
    """Each column's candidates: its crests' (the rows of `found` (k, 3) of that column, by
    `columns`, in order) then its end rows' (`ends`); `top` (columns,) raised in place to
    the end rows' values."""
    bounds = np.cumsum(np.bincount(columns, minlength=len(ends))).tolist()
    candidates = []
    for j, (first, last, end) in enumerate(zip([0, *bounds[:-1]], bounds, ends)):
        if len(end):
            top[j] = max(top[j], end[:, 1].max())
        candidates.append(np.concatenate((found[first:last], end)))
    return candidates


def _quartic_rises(
    time: np.ndarray,
    values: np.ndarray,
    rows: np.ndarray,
    columns: np.ndarray,
    rise: np.ndarray,
    bound: np.ndarray,
) -> np.ndarray:
    """The crests' rises (crest rows `rows` of columns `columns` of values (n, columns), with
    their parabola's `rise` and `bound`: mechlib.outputs.crests.crest_table): the quartic's
    (`_quartic_rise`) where a crest has a finite rise and bound and two rows either side and
    the quartic a maximum between its neighbours, the parabola's elsewhere."""
    inner = np.isfinite(rise) & np.isfinite(bound) & (rows >= 2) & (rows <= len(values) - 3)
    if not inner.any():
        return rise
    fine = _quartic_rise(time, values, rows[inner], columns[inner])
    out = rise.copy()
    out[inner] = np.where(np.isfinite(fine), fine, rise[inner])
    return out


def _ends(time: np.ndarray, values: np.ndarray, events: np.ndarray) -> list[np.ndarray]:
    """Per column of `values` (n, columns): its end rows' candidates (time, value with the
    rise of `_end_rises`, END), (k, 3): its finite end rows; no rise where an event lies
    between an end's first and fourth rows: the cubic through them would span the change
    an event makes (a kink, or a jump of the accelerations and reactions) and read a crest
    that is not there (the door jettison's hinge rate, 0 until its rod is disconnected at
    1 ms and rising after it: a trough 3.3e-3 rad/s below its first row, its envelope's
    estimate 8.6 times the true error, 1.0 without; a stop at the last row ends a smooth
    stretch and keeps its rise). Crests near an event keep their fit: read by their row,
    a companion's thinned rows missed the flaps' latch torques by up to 0.7 % (their
    estimate 1.5 -> 5.3 times the true error; benchmarks/error_table_events.py)."""
    rises = {
        end: _end_rises(time, values, end)
        if not _inside(time[:4] if end == 0 else time[-4:], events)
        else np.zeros(values.shape[1])
        for end in (0, -1)
    }
    after = _after_events(time, values, events)
    # every column's candidates side by side (columns, 2 + events, 3), then each its own
    rows = [(time[end], values[end] + rises[end], np.isfinite(values[end])) for end in (0, -1)]
    rows += [(t, start, np.isfinite(start)) for t, start in after]
    table = np.empty((values.shape[1], len(rows), 3))
    for k, (t, value, _) in enumerate(rows):
        table[:, k] = t, 0.0, END
        table[:, k, 1] = value
    kept = np.column_stack([finite for _, _, finite in rows])
    return [table[j][kept[j]] for j in range(values.shape[1])]


def _after_events(
    time: np.ndarray, values: np.ndarray, events: np.ndarray
) -> list[tuple[float, np.ndarray]]:
    """Per event between two output times (its one row the state before its actions): the
    event's time (s) and, per column of `values` (n, columns), the highest value of the
    stretch after it before its first row, where that is above the row (else nan). An event
    jumps the accelerations and reactions at its instant, and the rows see the jump's top
    only one row later, when it has fallen: the door jettison's top acceleration jumps from
    0 to 19.168 m/s^2 at its rod's disconnection (1 ms), its row at 2 ms reads 19.140 (the
    envelope's error 0.028, which Richardson on the rows cannot see). Read by the parabola
    through the first three rows after the event, between the event and the first of them;
    its rise above that row at most the change over the next row interval (the event is
    less than a row interval before it), and only where the value jumps at the event by
    more than that rise (a position or a velocity, continuous there, has its top at the
    event's row: the parabola's value there is its fit error, which read the jettison's
    hinge angle 5000 times its true error of 3e-9)."""
    out = []
    for t in np.unique(events):
        at = np.flatnonzero(time == t)
        if len(at) != 1 or at[0] + 3 >= len(time):
            continue
        t1, t2, t3 = time[at[0] + 1 : at[0] + 4]
        if not (t < t1 < t2 < t3) or _inside(np.array([t, t3]), events):
            continue
        v1, v2, v3 = values[at[0] + 1 : at[0] + 4]
        d1, d2 = (v2 - v1) / (t2 - t1), (v3 - v2) / (t3 - t2)
        c = (d2 - d1) / (t3 - t1)
        slope = d1 - c * (t2 - t1)  # of the parabola at t1: v = v1 + slope s + c s^2
        start = np.maximum(v1 + slope * (t - t1) + c * (t - t1) ** 2, v1)
        with np.errstate(divide="ignore", invalid="ignore"):
            vertex = -slope / (2.0 * c)
            inside = (c < 0.0) & (vertex > t - t1) & (vertex < 0.0)
            start = np.where(inside, np.maximum(start, v1 - slope**2 / (4.0 * c)), start)
        rise = np.minimum(start - v1, np.abs(v2 - v1))
        jump = np.abs(v1 + rise - values[at[0]])  # from the state before the actions
        out.append((float(t), np.where((rise > 0.0) & (jump > rise), v1 + rise, np.nan)))
    return out


def _inside(rows: np.ndarray, events: np.ndarray) -> bool:
    """Whether an event lies strictly between the first and last of `rows` (s)."""
    return bool(len(rows) and ((events > rows[0]) & (events < rows[-1])).any())


def _quartic_rise(
    time: np.ndarray, values: np.ndarray, rows: np.ndarray, columns: np.ndarray | None = None
) -> np.ndarray:
    """Per crest row (indices into `values`, two rows at least from either end; of column
    `columns` of values (n, columns), or of values (n,)): the rise
    above it of the highest point of the quartic through it and the two rows either side,
    between its neighbours; nan where that quartic has no maximum there, or the five times
    do not increase (an event's row repeats a time)."""
    table = np.ascontiguousarray(values.reshape(len(values), -1))
    columns = np.zeros(len(rows), dtype=np.int64) if columns is None else columns
    rise = np.full(len(rows), np.nan)
    fitted, scaled, which = scaled_groups(time, rows.astype(np.int64))
    rise[fitted] = quartic_rises(
        table, rows[fitted], columns[fitted], _distinct_powers(scaled), scaled, which
    )
    return rise


def _distinct_powers(scaled: np.ndarray) -> np.ndarray:
    """scaled[:, :, None] ** np.arange(5) of five scaled times a crest (n, 5), the crest's
    own (the middle) exactly 0: powers 0 and 1 and the middle's are exact and set (x ** 0
    = 1, x ** 1 = x, +0 ** k = +0), the others taken as numpy's power takes them, the same
    values to the last bit (tests/loadcases/test_peak_error.py) in half the calls of
    libm's pow. `_quartic_rise` takes them once a distinct row (mechlib.outputs.crests.
    scaled_groups: a run's even rows, 32 distinct ones among the campaign's 973; 0.35 ->
    0.08 ms)."""
    powers = np.empty((*scaled.shape, 5))
    powers[:, :, 0] = 1.0
    powers[:, :, 1] = scaled
    powers[:, 2, 2:] = 0.0
    powers[:, _BESIDE, 2:] = scaled[:, _BESIDE, None] ** np.arange(2, 5)
    return powers


def _end_rises(time: np.ndarray, values: np.ndarray, end: int) -> np.ndarray:
    """Per column of `values` (n, columns): the rise above an end row (`end` 0 or -1) of a
    crest between it and the row beside
    it, 0 where none. The rows end before the crest is reached on both sides, so no row
    is higher than its two neighbours (Andrews' squeezer: Theta_rate's trough at 0.02997 s,
    0.76 below the last row at 0.03 s, 0.3 ms rows), and the parabola through the three
    end rows puts its vertex past the end (its third derivative is large there): the
    cubic through the four end rows places it. A crest there: the end row higher than
    the row beside it, the parabola through the three end rows curving down (a leap, such
    as the IFToMM A05 flyball's spring tension in its first row, curves it the other way),
    the cubic's highest point strictly between the two end rows, its rise at most the
    parabola's curvature over a whole row interval (|c| h^2)."""
    rises = np.zeros(values.shape[1])
    order = slice(None, 4) if end == 0 else slice(-4, None)
    t, v = time[order], values[order]
    if end == 0:
        t, v = -t[::-1], v[::-1]  # the first rows as the last, in time mirrored
    if len(v) < 4 or not (np.diff(t) > 0.0).all():
        return rises
    _, c = _curvature(t[1:], v[1:], 1)
    crest = np.flatnonzero(np.isfinite(v).all(axis=0) & (v[-1] > v[-2]) & (c[0] < 0.0))
    if len(crest):  # one solve for every column's cubic: the four times are the same
        h = float(t[-1] - t[-2])
        found = zip(_cubics(t, v[:, crest]).T.tolist(), v[-1, crest].tolist(), -c[0, crest])
        for j, (a, last, down) in zip(crest.tolist(), found):
            rises[j] = _cubic_top(a, last, float(down), h)
    return rises


def _cubics(t: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The coefficients (4,) or (4, columns), in s = (t - t[-1]) / (t[-1] - t[-2]), of the
    cubic through four rows (t, v) of one column (4,) or several (4, columns)."""
    s = (t - t[-1]) / (t[-1] - t[-2])  # the last row at 0, the one beside it at -1
    return np.linalg.solve(s[:, None] ** np.arange(4), v)


def _cubic_top(a: list[float], last: float, down: float, h: float) -> float:
    """The highest point's rise above the last row's value `last` of the cubic of
    coefficients `a` (`_cubics`), strictly between the last two rows, at most `down` times
    the last row interval `h` (s) squared; 0 where the cubic has no maximum there."""
    rise = 0.0
    for at in _quadratic_roots(3.0 * a[3], 2.0 * a[2], a[1]):  # of the slope
        if -1.0 < at < 0.0 and 2.0 * a[2] + 6.0 * a[3] * at < 0.0:
            rise = max(rise, a[0] + at * (a[1] + at * (a[2] + at * a[3])) - last)
    return min(rise, down * h**2)


def _cubic_rise(t: np.ndarray, v: np.ndarray, down: float) -> float:
    """The highest point's rise above the last of four rows (t, v) of the cubic through
    them, strictly between the last two rows, at most `down` (the parabola's -c) times
    the last row interval squared; 0 where the cubic has no maximum there."""
    return _cubic_top(_cubics(t, v).tolist(), float(v[-1]), down, float(t[-1] - t[-2]))


def _quadratic_roots(a: float, b: float, c: float) -> list[float]:
    """The real roots of a x^2 + b x + c (of b x + c where a is 0; none where both are),
    by the formula that does not subtract nearly equal numbers."""
    if a == 0.0:
        return [-c / b] if b != 0.0 else []
    discriminant = b * b - 4.0 * a * c
    if not discriminant >= 0.0:
        return []
    q = -0.5 * (b + math.copysign(math.sqrt(discriminant), b))
    return [q / a, c / q] if q != 0.0 else [0.0]


def extremes(time: np.ndarray, values: np.ndarray, events: Sequence[float] = ()) -> Extremes:
    """The column's extremes at its rows and between them (rows that are not finite are
    ignored; no fit across the `events`' times, s)."""
    return extremes_of(time, values[:, None], events)[0]


def extremes_of(
    time: np.ndarray,
    table: np.ndarray,
    events: Sequence[float] = (),
    interval: float | None = None,
) -> list[Extremes]:
    """`extremes` of each column of `table` (n, columns), in one pass over the columns;
    their typical row `interval` (s) given, or the median one."""
    table = np.asarray(table, dtype=float)
    finite = np.isfinite(table).any(axis=0)
    columns = np.flatnonzero(finite)
    if interval is None:
        interval = float(np.median(np.diff(time))) if len(time) > 1 else 0.0
    out = [Extremes(0.0, 0.0, 0.0, 0.0)] * table.shape[1]
    if not len(columns):
        return out
    both = table[:, columns]
    row_max, top, tops = _highest(
        time, np.concatenate((both, -both), axis=1), np.asarray(events, dtype=float)
    )
    m = len(columns)
    for k, j in enumerate(columns):
        out[j] = Extremes(
            float(row_max[k]),
            -float(row_max[m + k]),
            float(top[k]),
            -float(top[m + k]),
            tops[k],
            tops[m + k] * _FLIP,
            interval,
            time,
            table[:, j],
        )
    return out


def _single_crests(run: Extremes, companion: Extremes) -> bool:
    """Whether the companion's crests are read well enough to be compared one by one: its
    rows at most SPARSEST times as far apart as the run's (a thinned companion's single
    crests carry a fit error up to k^6 times the run's at k times the interval, the
    closed-valve servo's element states a miss between its steps, which are linear there:
    only its extreme crest is compared)."""
    return companion.interval <= SPARSEST * run.interval


def peak_error(
    run: Extremes,
    companion: Extremes,
    scale: float,
    *,
    crests: bool = True,
    bound: float = math.inf,
) -> tuple[float, float]:
    """Estimated error of the run's envelope (its rows' max and min, the worse), in the
    column's unit: Richardson on the continuous peaks (the run's peak against the other
    run's value at the same crest where single crests are compared, its peak otherwise:
    their difference x |`scale`|, 1 / (r^p - 1) for another run of steps r times the
    run's: negative for a finer one), or the largest excess of a competing candidate's
    extrapolated value over the run's peak where larger (`crests` False: not compared
    crest by crest, the two runs' phases apart), at most `bound`, plus the run's sampling
    error; and that sampling error alone (shorter steps do not reduce it, a shorter output
    interval does).

    `bound`: the column's history estimate (its largest error over the run, the column's
    unit). A peak moves by at most the largest change of the curve, |max f - max g| <=
    max |f - g|, and crests read through rows a sizeable part of a period apart are not
    read to better than that: the vertex the fit finds depends on where the crest falls
    between the rows, and a companion whose phase has drifted against the run's puts its
    crests elsewhere between the same rows (a spring-mass read through rows 20 ms apart,
    10 a period: the integrator's part of its displacement's envelope estimated at 0.048
    of the peak, its history at 0.00155 (true 0.00157), the rows' true error at the
    crests 3.2e-6; tests/loadcases/test_peak_bound.py). The history is read at the rows
    both runs have, which may step over the curve's largest difference between them (a
    thinned companion's): the bound is then somewhat low, as is the history itself."""
    high, low = run.max - run.row_max, run.row_min - run.min
    size = abs(scale)
    over, under = 0.0, 0.0
    top, bottom = companion.max, companion.min
    if crests and _single_crests(run, companion):
        window = run.interval + companion.interval
        over, top = crest_match(run.tops, run.max, companion.tops, window, scale, top)
        under, bottom = crest_match(
            run.bottoms * _FLIP, -run.min, companion.bottoms * _FLIP, window, scale, -bottom
        )
        bottom = -bottom
    elif crests:  # a thinned companion: its crest where it kept the run's rows about it
        window = PARTNER_WINDOW * run.interval
        if dense_beside(run, companion, run.tops, run.max, 1.0):
            top = crest_match(run.tops, run.max, companion.tops, window, scale, top)[1]
        if dense_beside(run, companion, run.bottoms * _FLIP, -run.min, -1.0):
            flipped = (run.bottoms * _FLIP, -run.min, companion.bottoms * _FLIP)
            bottom = -crest_match(*flipped, window, scale, -bottom)[1]
    over, under = min(over, bound), min(under, bound)
    sides = [
        max(min(size * abs(run.max - top), bound), over) + high,
        max(min(size * abs(run.min - bottom), bound), under) + low,
    ]
    if crests:
        at_rows = run.max == run.row_max or run.min == run.row_min
        spikes = row_peaks(run) if at_rows and len(companion.time) else []
        for k, (sign, beside) in enumerate(((1.0, over), (-1.0, under))):
            spike = _at_row_peak(run, companion, sign, size, spikes)
            if spike is not None:
                sides[k], missed = max(spike[0], beside), spike[1]
                high, low = (missed, low) if sign > 0 else (high, missed)
    return max(sides), max(high, low)


PARTNER_WINDOW = 1.5  # of the run's row interval: a companion's crest within it is the run's


def dense_beside(
    run: Extremes, companion: Extremes, candidates: np.ndarray, peak: float, sign: float
) -> bool:
    """Whether the run's `peak` is a crest's vertex above its row among its `candidates`
    ((time, value, kind), higher more extreme; `sign` -1: a minimum's, flipped) whose row
    and the run's two rows either side are rows of the `companion` too (loadcases.run.
    companion.crest_rows keeps them in a thinned one): its crest there is read through the
    rows the run's is, and compared with it (the run's rows, 1e-9 s apart at most), not
    the companion's extreme through its thinned rows."""
    if not len(candidates) or not len(companion.time):
        return False
    best = candidates[np.argmax(candidates[:, 1])]
    i = int(np.searchsorted(run.time, best[0]))
    if best[1] < peak or best[2] == END or not best[1] > sign * run.values[i]:
        return False
    return all(len(_rows_at(companion.time, t)) for t in run.time[max(i - 2, 0) : i + 3])


def _rows_at(time: np.ndarray, t: float) -> np.ndarray:
    """The indices of the rows of `time` at t (s): within 1e-9 of it, relative above 1 s."""
    return np.flatnonzero(np.abs(time - t) <= 1e-9 * max(1.0, abs(t)))


SPIKE = 0.1  # of a column's range: a one-row spike stands out from both its neighbours by more
# a row among ZIGZAG_ROWS or more standing out within ZIGZAG_REACH rows either side: no spike
ZIGZAG_REACH, ZIGZAG_ROWS = 5, 4


def row_peaks(found: Extremes) -> list[float]:
    """The times (s) of the column's largest and smallest value where each is a one-row
    spike: one row with no crest between rows (not smooth: `_smooth`), not an end row nor a
    value other rows have too,
    standing out from both its neighbours by more than SPIKE of the column's range (the
    door let go's contact forces: 3834 N between two rows of 0, its guide's 1241 N between
    631 and 432 N; not a ringing spring's rows, the IFToMM A05 hinge force's 116.92 N
    between 117.21 and 117.27 N, 0.4 % of its range, which the companion's own ringing
    would read as a miss 4 times the true error); not a row among zigzagging rows
    (`_zigzag`)."""
    times: list[float] = []
    spread = found.row_max - found.row_min
    for candidates, peak, row, sign in (
        (found.tops, found.max, found.row_max, 1.0),
        (found.bottoms * _FLIP, -found.min, -found.row_min, -1.0),
    ):
        if (
            not (len(candidates) and peak <= row)
            or np.count_nonzero(sign * found.values == row) > 1
        ):
            continue  # no row peak, or a value held over several rows (a contact's 0 N)
        best = candidates[np.argmax(candidates[:, 1])]
        if best[2] == END or best[1] < row:
            continue
        i = int(np.searchsorted(found.time, best[0]))
        beside = sign * found.values[[i - 1, i + 1]]
        if (
            np.all(row - beside > SPIKE * spread)
            and not _smooth(found, best[0], sign)
            and not _zigzag(found.values, i, SPIKE * spread)
        ):
            times.append(float(best[0]))
    return times


def _zigzag(values: np.ndarray, i: int, margin: float) -> bool:
    """Whether at least ZIGZAG_ROWS of the rows within ZIGZAG_REACH of row i stand out
    from both their neighbours by more than `margin` (the column's unit): the rows zigzag, a
    motion faster than they sample it (modes the steps do not resolve), and row i is one
    swing of many, not a spike. The flexible pendulum's tip deformation (49 of its 101 rows
    standing out) read 5.46 times its true error as a spike, through the companion's own
    ringing beside its row; 1.29 as a crest. A contact pulse stands out alone, or with the
    row after it (the door let go's 3834 N between rows of 0 N, then the next contact's
    483 N: two rows). So a pulse on a column that also rings by more than SPIKE of its
    range between rows is read as a crest, not a spike."""
    window = values[max(i - ZIGZAG_REACH - 1, 0) : i + ZIGZAG_REACH + 2]
    return int(np.count_nonzero(standing_out(window, margin))) >= ZIGZAG_ROWS


def standing_out(values: np.ndarray, margin: np.ndarray | float) -> np.ndarray:
    """Per inner row of `values` (rows, or rows x columns), whether it stands out from both
    its neighbours, above or below, by more than `margin` (per column)."""
    change = np.diff(values, axis=0)
    with np.errstate(invalid="ignore"):
        up = (change[:-1] > margin) & (change[1:] < -margin)
        down = (change[:-1] < -margin) & (change[1:] > margin)
    return np.asarray(up | down)


def _smooth(found: Extremes, t: float, sign: float) -> bool:
    """Whether the column's crest at its row at `t` (s; a trough: `sign` -1) is smooth: the
    parabolas through it and its neighbours, and through the rows one earlier and one later,
    all curve down (`_highest`'s rule; a smooth crest whose vertex is its row rises 0)."""
    i = int(np.searchsorted(found.time, t))
    rows = slice(max(i - 2, 0), i + 3)
    _, c = _curvature(found.time[rows], sign * found.values[rows], 1)
    return bool(len(c) and np.all(c < 0.0))


def _at_row_peak(
    run: Extremes, companion: Extremes, sign: float, scale: float, spikes: list[float]
) -> tuple[float, float] | None:
    """Where the run's largest value (`sign` 1; its smallest: -1) is one row with no crest
    between rows (`row_peaks`: a one-row spike) and the companion has a row at its time
    (loadcases.run.companion.spikes gives it one, and rows at quarters of the run's two
    intervals beside it): the peak's estimated error and the part of it the run's rows
    miss, read on the companion's rows there (its highest within the two intervals, or
    crest, above its value at the row's time). The error: the larger of Richardson at the
    row (the difference x `scale`) plus that miss, and the run's row against the
    companion's highest there in full. The run's rows do not resolve a spike (the door let
    go's guide force: rows 631, 1241 and 432 N at 0.64, 0.65, 0.66 s about a crest of 1335
    N at 0.648 s; the parabola through them rises 3.5 N), another place's value is no
    partner (the companion's rows 20 ms apart read 627 N at 0.64 s: 14 times the true
    error on its stop's contact), and an impact a step resolves only roughly is outside
    Richardson's range (its stop's force at 0.05 s: the run's row 47 N below the
    reference, the companion's 5 N above it, its pulse's onset between its rows: the miss
    read 0 and Richardson 17 N of a true 70 N; the run's row against the companion's
    crest, 52 N). None elsewhere. `spikes`: the run's `row_peaks` (taken once for both
    signs)."""
    row = run.row_max if sign > 0 else run.row_min
    peak = run.max if sign > 0 else run.min
    if peak != row or not len(companion.time):  # a crest between rows: no row peak
        return None
    times = [t for t in spikes if run.values[np.searchsorted(run.time, t)] == row]
    if not times:
        return None
    t = times[0]
    at = _rows_at(companion.time, t)
    if len(at) != 1:
        return None
    i = int(np.searchsorted(run.time, t))
    lo = run.time[max(i - 1, 0)]
    hi = run.time[min(i + 1, len(run.time) - 1)]
    near = sign * companion.values[(companion.time > lo) & (companion.time < hi)]
    candidates = companion.tops if sign > 0 else companion.bottoms * _FLIP
    crests = candidates[(candidates[:, 0] > lo) & (candidates[:, 0] < hi), 1]
    value = sign * float(companion.values[at[0]])
    highest = max(np.max(near[np.isfinite(near)], initial=value), np.max(crests, initial=value))
    missed = highest - value
    return max(scale * abs(sign * row - value) + missed, abs(highest - sign * row)), missed
