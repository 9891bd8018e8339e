"""The loads matrix: one row per request component, one column group per run (or per
family): each run's peak max and min of the component with where it occurs (the abscissa
when the run has one, else the time), and the run (family) whose peak is critical.

It is the table a stress office builds by hand from the runs' files: its numbers are the
runs' own peaks (`loadcases.report.peaks`), SI in `loads-matrix.csv`, report units in the
workbook. With `by="families"` a family's cell is the peak over its runs (first run on a
tie). Rows of numerical noise (`loadcases.report.noise`) are kept and marked `~0`.

Peaks are limit loads (`loadcases.report.levels`: an ultimate-level run's loads divided by
the ultimate factor); `levels` says at which level each head's case gives its loads, and a
row's `factors` (ultimate x fitting x case factor of each cell; None: not a load) give
the ultimate loads, written after every head's limit columns in `loads-matrix.csv`.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Mapping, Sequence
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
    factors: list[float | None] = field(default_factory=list)  # per cell; None: not a load

    def ultimate(self, k: int, side: str) -> float | None:
        """The ultimate load of cell `k` on `side` (factor x limit peak), None if none."""
        cell = self.cells[k]
        factor = self.factors[k] if k < len(self.factors) and not self.noise else None
        value = None if cell is None else getattr(cell, side)
        return None if factor is None or value is None else factor * value


@dataclass
class LoadsMatrix:
    """`heads`: run (or family) names; `at`: per head (name, unit) of where peaks are."""

    heads: list[str]
    at: list[tuple[str, str]]
    rows: list[MatrixRow]
    by: str = "runs"
    levels: list[str] = field(default_factory=list)  # per head: limit or ultimate


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
    levels: Mapping[str, str] | None = None,
    factor: Callable[[str, RunPeak], float | None] | None = None,
) -> LoadsMatrix:
    """The matrix of `peaks` ({column: [RunPeak]}) over `runs` [(run, family)] in order;
    `units` {column: unit}; `at` {family: (abscissa name, unit)}, time for others;
    `levels` {run: level} of the loads its case gives (default limit); `factor(column,
    peak)`: the ultimate factor of a cell (None: not a load; default: no ultimate loads)."""
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
        factors = [None if c is None or factor is None else factor(column, c) for c in cells]
        row = MatrixRow(column, units.get(column, ""), column in noise, cells, critical, factors)
        rows.append(row)
    first_run: dict[str, str] = {}
    for run in runs:
        first_run.setdefault(run[key], run[0])
    head_levels = [(levels or {}).get(first_run[h], "limit") for h in heads]
    return LoadsMatrix(heads, where, rows, by, head_levels)


def matrix_csv_text(matrix: LoadsMatrix) -> str:
    """CSV: `column, unit, noise, critical_max, critical_min`, then per head `HEAD max`,
    `HEAD max at`, `HEAD min`, `HEAD min at` (at: abscissa if the run has one, else time),
    all limit loads; then per head `HEAD level` (of its case's loads), `HEAD ultimate max`,
    `HEAD ultimate min` (empty for a column that is not a load)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    header = ["column", "unit", "noise", "critical_max", "critical_min"]
    for head in matrix.heads:
        header += [f"{head} max", f"{head} max at", f"{head} min", f"{head} min at"]
    for head in matrix.heads:
        header += [f"{head} level", f"{head} ultimate max", f"{head} ultimate min"]
    writer.writerow(visible_fields(header))
    for row in matrix.rows:
        line: list[object] = [row.column, row.unit, NOISE_MARK if row.noise else ""]
        line += [matrix.heads[k] if k is not None else "" for k in map(row.critical.get, SIDES)]
        for cell in row.cells:
            for side in SIDES:
                values = (None, None) if cell is None else (getattr(cell, side), cell.at(side))
                line += ["" if v is None else v for v in values]
        for k, level in enumerate(matrix.levels):
            ultimate = [row.ultimate(k, side) for side in SIDES]
            line += [level, *("" if v is None else v for v in ultimate)]
        writer.writerow(visible_fields(line))
    return buffer.getvalue()


def write_matrix_csv(matrix: LoadsMatrix, path: Path) -> Path:
    """Write `loads-matrix.csv` atomically."""
    return atomic_write_text(path, matrix_csv_text(matrix))
