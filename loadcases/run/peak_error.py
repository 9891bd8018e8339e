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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Extremes", "extremes", "peak_error"]


@dataclass(frozen=True)
class Extremes:
    """Largest and smallest value of one column: at the rows and continuous (between rows)."""

    row_max: float
    row_min: float
    max: float
    min: float


def _curvature(time: np.ndarray, values: np.ndarray, k: int) -> tuple[np.ndarray, ...]:
    """Per interior row i (rows k to n-k-1): the parabola through rows i-k, i, i+k, as its
    slope at row i and its curvature coefficient c (v = v_i + slope dt + c dt^2)."""
    n = len(values)
    h1 = time[k : n - k] - time[: n - 2 * k]
    h2 = time[2 * k :] - time[k : n - k]
    v0, v1, v2 = values[: n - 2 * k], values[k : n - k], values[2 * k :]
    with np.errstate(divide="ignore", invalid="ignore"):
        d1, d2 = (v1 - v0) / h1, (v2 - v1) / h2
        c = (d2 - d1) / (h1 + h2)
    return d1 + c * h1, c


def _highest(time: np.ndarray, values: np.ndarray) -> tuple[float, float]:
    """(largest finite row, largest vertex or row): the vertex of the parabola through each
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
    a crest 5 N above it: an estimate 4 times its true error)."""
    row_max = float(np.max(values[np.isfinite(values)]))
    if len(values) < 3:
        return row_max, row_max
    slope, c = _curvature(time, values, 1)
    h = np.maximum(np.diff(time)[:-1], np.diff(time)[1:])
    with np.errstate(divide="ignore", invalid="ignore"):
        rise = -(slope**2) / (4.0 * c)
        bound = -c * (0.5 * h) ** 2
        if len(values) >= 5:
            _, wide = _curvature(time, values, 2)
            bound[1:-1] = np.minimum(bound[1:-1], np.maximum(-wide, 0.0) * (0.5 * h[1:-1]) ** 2)
        if len(values) >= 4:
            bound = np.minimum(bound, _beside(c) * (0.5 * h) ** 2)
        v0, v1, v2 = values[:-2], values[1:-1], values[2:]
        local = (v1 > v0) & (v1 > v2) & (np.diff(time)[:-1] > 0.0) & (np.diff(time)[1:] > 0.0)
    local &= (c < 0.0) & np.isfinite(rise) & np.isfinite(bound)
    rise = np.minimum(rise, bound)
    return row_max, float(np.max(v1[local] + rise[local], initial=row_max))


def _beside(c: np.ndarray) -> np.ndarray:
    """Per interior row: the smaller downward curvature -c (at least 0) of the parabolas
    through the row before and the row after (one of them at the first and last)."""
    down = np.maximum(-c, 0.0)
    out = np.full_like(down, np.inf)
    out[1:] = down[:-1]
    out[:-1] = np.minimum(out[:-1], down[1:])
    return out


def extremes(time: np.ndarray, values: np.ndarray) -> Extremes:
    """The column's extremes at its rows and between them (rows that are not finite are
    ignored)."""
    if not np.isfinite(values).any():
        return Extremes(0.0, 0.0, 0.0, 0.0)
    row_max, top = _highest(time, values)
    row_min, bottom = _highest(time, -values)
    return Extremes(row_max, -row_min, top, -bottom)


def peak_error(run: Extremes, companion: Extremes, scale: float) -> tuple[float, float]:
    """Estimated error of the run's envelope (its rows' max and min, the worse), in the
    column's unit: Richardson on the continuous peaks (their difference x `scale`,
    1 / (r^p - 1)) plus the run's sampling error; and that sampling error alone (shorter
    steps do not reduce it, a shorter output interval does)."""
    high, low = run.max - run.row_max, run.row_min - run.min
    return (
        max(
            scale * abs(run.max - companion.max) + high, scale * abs(run.min - companion.min) + low
        ),
        max(high, low),
    )
