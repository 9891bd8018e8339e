"""The loads matrix: one row per request component, one column group per run (or per
family): each run's peak max and min of the component with where it occurs (the abscissa
when the run has one, else the time), and the run (family) whose peak is critical.

It is the table a stress office builds by hand from the runs' files: its numbers are the
runs' own peaks (`loadcases.report.peaks`), SI in `loads-matrix.csv`, report units in the
workbook. With `by="families"` a family's cell is the peak over its runs (first run on a
tie). Rows of numerical noise (`loadcases.report.noise`) are kept and marked `~0`.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from loadcases.foundation.atomic import atomic_write_text
from loadcases.foundation.clip import visible_fields
from loadcases.report.noise import NOISE_MARK
from loadcases.report.peaks import RunPeak

__all__ = ["LoadsMatrix", "MatrixRow", "loads_matrix", "matrix_csv_text", "write_matrix_csv"]

SIDES = ("max", "min")


@dataclass
class MatrixRow:
    """One component: a peak (or None) per head; `critical` {side: head index or None}."""

    column: str
    unit: str
    noise: bool
    cells: list[RunPeak | None]
    critical: dict[str, int | None] = field(default_factory=dict)


@dataclass
class LoadsMatrix:
    """`heads`: run (or family) names; `at`: per head (name, unit) of where peaks are."""

    heads: list[str]
    at: list[tuple[str, str]]
    rows: list[MatrixRow]
    by: str = "runs"


def _best(cells: Sequence[RunPeak | None], side: str) -> int | None:
    """Index of the cell with the largest max (smallest min); the first on a tie."""
    sign = 1.0 if side == "max" else -1.0
    best: int | None = None
    for k, cell in enumerate(cells):
        value = None if cell is None else getattr(cell, side)
        if value is not None and (best is None or sign * value > sign * getattr(cells[best], side)):
            best = k
    return best


def _family_cell(cells: list[RunPeak]) -> RunPeak | None:
    """A family's peak: the max of its runs' max (with its place), likewise the min."""
    if not cells:
        return None
    i_max, i_min = _best(cells, "max"), _best(cells, "min")
    hi = cells[i_max if i_max is not None else 0]
    lo = cells[i_min if i_min is not None else 0]
    return RunPeak(hi.run, hi.family, hi.max, hi.max_time, hi.max_abscissa, *_min_of(lo))


def _min_of(peak: RunPeak) -> tuple[float | None, float | None, float | None]:
    return peak.min, peak.min_time, peak.min_abscissa


def loads_matrix(
    peaks: Mapping[str, Sequence[RunPeak]],
    runs: Sequence[tuple[str, str]],
    *,
    units: Mapping[str, str],
    at: Mapping[str, tuple[str, str]],
    noise: set[str] | frozenset[str] = frozenset(),
    by: str = "runs",
) -> LoadsMatrix:
    """The matrix of `peaks` ({column: [RunPeak]}) over `runs` [(run, family)] in order;
    `units` {column: unit}; `at` {family: (abscissa name, unit)}, time for others."""
    key = 1 if by == "families" else 0
    heads = list(dict.fromkeys(run[key] for run in runs))
    family_of = {run[key]: run[1] for run in runs}
    where = [at.get(family_of[h], ("time", "s")) for h in heads]
    rows = []
    for column, column_peaks in peaks.items():
        groups: dict[str, list[RunPeak]] = {h: [] for h in heads}
        for peak in column_peaks:
            groups[peak.family if key else peak.run].append(peak)
        cells = [_family_cell(groups[h]) if key else next(iter(groups[h]), None) for h in heads]
        critical = {side: _best(cells, side) for side in SIDES}
        rows.append(MatrixRow(column, units.get(column, ""), column in noise, cells, critical))
    return LoadsMatrix(heads, where, rows, by)


def matrix_csv_text(matrix: LoadsMatrix) -> str:
    """CSV: `column, unit, noise, critical_max, critical_min`, then per head `HEAD max`,
    `HEAD max at`, `HEAD min`, `HEAD min at` (at: abscissa if the run has one, else time)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    header = ["column", "unit", "noise", "critical_max", "critical_min"]
    for head in matrix.heads:
        header += [f"{head} max", f"{head} max at", f"{head} min", f"{head} min at"]
    writer.writerow(visible_fields(header))
    for row in matrix.rows:
        line: list[object] = [row.column, row.unit, NOISE_MARK if row.noise else ""]
        line += [matrix.heads[k] if k is not None else "" for k in map(row.critical.get, SIDES)]
        for cell in row.cells:
            for side in SIDES:
                values = (None, None) if cell is None else (getattr(cell, side), cell.at(side))
                line += ["" if v is None else v for v in values]
        writer.writerow(visible_fields(line))
    return buffer.getvalue()


def write_matrix_csv(matrix: LoadsMatrix, path: Path) -> Path:
    """Write `loads-matrix.csv` atomically."""
    return atomic_write_text(path, matrix_csv_text(matrix))
