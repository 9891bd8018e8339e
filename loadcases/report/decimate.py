"""Fewer rows for the workbook's charts, the peaks kept exactly.

A chart of a few hundred points looks like one of thousands at the size of a chart, but
a workbook holding every output row of every run weighs megabytes. `chart_rows` picks
evenly spaced rows (at most `CHART_ROWS`) and adds, for every column, the row of its
largest and of its smallest finite value, plus the first and the last row: the max and min
of each column read from the decimated table are those of the full one. The full rows stay
in the runs' CSV files.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Collection, Iterable

import numpy as np

from loadcases.report.curves import EnvelopeCurve
from loadcases.report.envelope import extreme_row
from loadcases.results.saved import SavedRun

__all__ = ["CHART_ROWS", "chart_rows", "decimate_curve", "decimate_run"]

CHART_ROWS = 150  # evenly spaced rows per run or curve, before the peak rows are added


def chart_rows(size: int, columns: Iterable[np.ndarray], limit: int = CHART_ROWS) -> np.ndarray:
    """Sorted row indices (of `size` rows): evenly spaced ones, first, last, and the
    rows of the max and min of every column in `columns`."""
    if size <= limit:
        return np.arange(size)
    keep = set(np.linspace(0, size - 1, limit).round().astype(int).tolist())
    for values in columns:
        for sign in (1.0, -1.0):
            row = extreme_row(values, sign)
            if row is not None:
                keep.add(row)
    return np.array(sorted(keep), dtype=int)


def decimate_run(run: SavedRun, limit: int = CHART_ROWS, skip: Collection[str] = ()) -> SavedRun:
    """`run` with the rows of `chart_rows` only, without the columns in `skip`."""
    channels = {c: v for c, v in run.channels.items() if c not in skip}
    rows = chart_rows(run.time.size, channels.values(), limit)
    return dataclasses.replace(
        run, time=run.time[rows], channels={c: v[rows] for c, v in channels.items()}
    )


def decimate_curve(curve: EnvelopeCurve, limit: int = CHART_ROWS) -> EnvelopeCurve:
    """`curve` on the grid points of `chart_rows` (upper max and lower min kept)."""
    rows = chart_rows(curve.x.size, [*curve.upper.values(), *curve.lower.values()], limit)
    if rows.size == curve.x.size:
        return curve
    return dataclasses.replace(
        curve,
        x=curve.x[rows],
        upper={c: v[rows] for c, v in curve.upper.items()},
        lower={c: v[rows] for c, v in curve.lower.items()},
    )
