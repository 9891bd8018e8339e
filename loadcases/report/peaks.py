"""Peaks of every result column in every run: the numbers of the loads matrix, and of
factors that differ per run (`case_factors`).

A run's peak of a column is its largest and smallest finite value with the time and, when
the run has one, the abscissa (`abscissa.value`) at that row; ties keep the earliest row,
as the envelope does (`loadcases.report.envelope`). Values are SI.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from loadcases.build.requests import ABSCISSA_COLUMN
from loadcases.report.envelope import extreme_rows
from loadcases.results.saved import SavedRun

__all__ = ["RunPeak", "run_peaks"]


@dataclass(frozen=True)
class RunPeak:
    """One column's extremes in one run (SI; `None` when the run has no finite value)."""

    run: str
    family: str
    max: float | None
    max_time: float | None
    max_abscissa: float | None
    min: float | None
    min_time: float | None
    min_abscissa: float | None

    def at(self, side: str) -> float | None:
        """Where the `side` ("max" or "min") peak is: the abscissa, else the time."""
        abscissa = getattr(self, f"{side}_abscissa")
        return abscissa if abscissa is not None else getattr(self, f"{side}_time")


def _side(run: SavedRun, column: str, row: int | None) -> tuple[float | None, ...]:
    """(value, time, abscissa) of `column` at `row` (its largest or smallest value)."""
    values = run.channels[column]
    if row is None:
        return None, None, None
    abscissa = run.channels.get(ABSCISSA_COLUMN)
    at = None if abscissa is None or not math.isfinite(abscissa[row]) else float(abscissa[row])
    return float(values[row]), float(run.time[row]), at


def run_peaks(runs: Iterable[SavedRun]) -> dict[str, list[RunPeak]]:
    """{column: [RunPeak of each run that has the column, in run order]}; the abscissa
    column is the runs' x axis, not a result, and is left out."""
    peaks: dict[str, list[RunPeak]] = {}
    for run in runs:
        extremes = extreme_rows(run.channels)
        for column in run.channels:
            if column == ABSCISSA_COLUMN:
                continue
            high, low = extremes[column]
            high_side, low_side = _side(run, column, high), _side(run, column, low)
            peak = RunPeak(run.name, run.family, *high_side, *low_side)
            peaks.setdefault(column, []).append(peak)
    return peaks
