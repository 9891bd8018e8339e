"""Envelopes across runs: per result column, the max and min over all runs and where they occur.

An envelope table has one row per result column (except `time`), with the columns
`column, max, max_run, max_time, min, min_run, min_time` (SPEC section 3), then:
`unit` (SI), `max_abscissa`, `min_abscissa` (the run's `abscissa.value` at that row),
`abs_max` (max(|max|, |min|)), the factor and ultimate loads, allowables and margins (see
`loadcases.report.margins`), `max_concurrent`, `min_concurrent`: the other components of the
same request at that instant of that run, as `fy=...; fz=...`; then `noise` (`~0` for a
component that is numerical noise: `loadcases.report.noise`), `factor_min` (the factor of the
min side; `factor` is the max side's), `ultimate_max_run`, `ultimate_min_run` (the runs whose
factored loads govern: differ from max_run/min_run only with `case_factors`), the limit
allowables and their margins `limit_allowable_max`, `limit_allowable_min`, `ms_limit_max`,
`ms_limit_min`; `max_level`, `min_level`: the level (limit or ultimate) at which the case of
max_run / min_run gives its loads (a set's envelope is at limit level: an ultimate-level
run's loads are divided by the ultimate factor, `loadcases.report.levels`).

Rules: NaN and infinite values are skipped (a failed run's missing rows never govern);
ties keep the first run in the given order and, within a run, the earliest row. Runs whose
status is not `ok` are left out by the callers (`loadcases.sets.campaign`, `loads envelope`):
values just before a solver failure are often numerical, not loads.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import astuple, dataclass, fields
from pathlib import Path

import numpy as np

from loadcases.build.requests import ABSCISSA_COLUMN
from loadcases.foundation.atomic import atomic_path, atomic_write_text
from loadcases.report.csv_rows import rows_csv_text
from loadcases.results.saved import SavedRun, find_result_files, load_saved_run
from loadcases.results.xlsx_text import text_cells

__all__ = [
    "ENVELOPE_COLUMNS",
    "EnvelopeRow",
    "envelope_csv_text",
    "extract_envelope",
    "extreme_row",
    "extreme_rows",
    "find_result_files",
    "load_saved_runs",
    "write_envelope_csv",
    "write_envelope_xlsx",
]

Run = tuple[str, np.ndarray, dict[str, np.ndarray]]


@dataclass
class EnvelopeRow:
    """Extremes of one column over all runs (values SI; `None` when there is none)."""

    column: str
    max: float | None = None
    max_run: str | None = None
    max_time: float | None = None
    min: float | None = None
    min_run: str | None = None
    min_time: float | None = None
    unit: str | None = None
    max_abscissa: float | None = None
    min_abscissa: float | None = None
    abs_max: float | None = None
    factor: float | None = None
    ultimate_max: float | None = None
    ultimate_min: float | None = None
    allowable_max: float | None = None
    allowable_min: float | None = None
    ms_max: float | None = None
    ms_min: float | None = None
    max_concurrent: str | None = None
    min_concurrent: str | None = None
    noise: str | None = None
    factor_min: float | None = None
    ultimate_max_run: str | None = None
    ultimate_min_run: str | None = None
    limit_allowable_max: float | None = None
    limit_allowable_min: float | None = None
    ms_limit_max: float | None = None
    ms_limit_min: float | None = None
    max_level: str | None = None
    min_level: str | None = None


ENVELOPE_COLUMNS = tuple(f.name for f in fields(EnvelopeRow))


def _as_saved(run: SavedRun | Run) -> SavedRun:
    if isinstance(run, SavedRun):
        return run
    name, time, channels = run
    return SavedRun(name, np.asarray(time, dtype=float), dict(channels))


def extreme_row(values: np.ndarray, sign: float) -> int | None:
    """Row of the first largest (`sign` 1) or smallest (-1) finite value, None if none."""
    finite = np.isfinite(values)
    if not finite.any():
        return None
    return int(np.argmax(np.where(finite, sign * values, -np.inf)))


def extreme_rows(channels: dict[str, np.ndarray]) -> dict[str, tuple[int | None, int | None]]:
    """{column: (row of its first largest, row of its first smallest finite value)}, None
    for a column without any: `extreme_row` of every column, in one pass over a run's
    columns stacked when they are of one length (a set of 1000 runs called it 22,000 times)."""
    arrays = {name: np.asarray(values, dtype=float) for name, values in channels.items()}
    lengths = {a.shape for a in arrays.values()}
    if len(lengths) != 1 or next(iter(lengths)) in ((0,), ()):
        return {n: (extreme_row(a, 1.0), extreme_row(a, -1.0)) for n, a in arrays.items()}
    matrix = np.column_stack(list(arrays.values()))
    finite = np.isfinite(matrix)
    some = finite.any(axis=0).tolist()
    highs = np.argmax(np.where(finite, matrix, -np.inf), axis=0).tolist()
    lows = np.argmax(np.where(finite, -matrix, -np.inf), axis=0).tolist()
    return {
        name: (high, low) if any_ else (None, None)
        for name, any_, high, low in zip(arrays, some, highs, lows)
    }


def _concurrent(run: SavedRun, column: str, row: int) -> str:
    """`fy=...; fz=...`: the other components of `column`'s request at `row`."""
    request = column.rsplit(".", 1)[0]
    parts = [
        f"{name[len(request) + 1 :]}={float(values[row])!r}"
        for name, values in run.channels.items()
        if name != column and name.rsplit(".", 1)[0] == request
    ]
    return "; ".join(parts)


def _fill(row: EnvelopeRow, side: str, run: SavedRun, index: int) -> None:
    """Set the `side` ("max" or "min") fields of `row` from `run` at row `index`."""
    values = run.channels[row.column]
    abscissa = run.channels.get(ABSCISSA_COLUMN)
    setattr(row, side, float(values[index]))
    setattr(row, f"{side}_run", run.name)
    setattr(row, f"{side}_time", float(run.time[index]))
    if abscissa is not None and np.isfinite(abscissa[index]):
        setattr(row, f"{side}_abscissa", float(abscissa[index]))
    setattr(row, f"{side}_concurrent", _concurrent(run, row.column, index))


def extract_envelope(runs: Iterable[SavedRun | Run]) -> list[EnvelopeRow]:
    """Envelope of runs (`SavedRun` or `(name, time, channels)`), rows in first-seen column
    order; factors and margins are added by `loadcases.report.margins.apply_margins`."""
    rows: dict[str, EnvelopeRow] = {}
    for run in map(_as_saved, runs):
        extremes = extreme_rows(run.channels)
        for column, values in run.channels.items():
            row = rows.setdefault(column, EnvelopeRow(column))
            row.unit = row.unit or run.units.get(column)
            i_max, i_min = extremes[column]
            if i_max is not None and (row.max is None or values[i_max] > row.max):
                _fill(row, "max", run, i_max)
            if i_min is not None and (row.min is None or values[i_min] < row.min):
                _fill(row, "min", run, i_min)
    for row in rows.values():
        if row.max is not None and row.min is not None:  # a run fills both or neither
            row.abs_max = max(abs(row.max), abs(row.min))
    return list(rows.values())


def load_saved_runs(files: Iterable[tuple[Path, Path]]) -> list[SavedRun]:
    """Read result files; each run is named by its summary's `case`, else its relative path."""
    return [load_saved_run(path, directory) for directory, path in files]


def envelope_csv_text(rows: list[EnvelopeRow]) -> str:
    """The envelope as CSV text (floats at full precision, missing values empty)."""
    return rows_csv_text(ENVELOPE_COLUMNS, rows)


def write_envelope_csv(rows: list[EnvelopeRow], path: Path) -> Path:
    """Write `envelope.csv` atomically."""
    return atomic_write_text(path, envelope_csv_text(rows))


@text_cells()  # input text is never a formula
def write_envelope_xlsx(
    rows: list[EnvelopeRow], path: Path, *, sources: Iterable[str] = ()
) -> Path:
    """A bare workbook: sheet `Envelope` (frozen header) and sheet `Runs` (the sources).
    The full sizing workbook is `loadcases.report.workbook.write_workbook`."""
    from openpyxl import Workbook  # only needed for workbooks

    workbook = Workbook(write_only=True)
    sheet = workbook.create_sheet("Envelope")
    sheet.freeze_panes = "A2"
    sheet.append(list(ENVELOPE_COLUMNS))
    for row in rows:
        sheet.append(list(astuple(row)))
    runs = workbook.create_sheet("Runs")
    runs.append(["source"])
    for source in sources:
        runs.append([source])
    with atomic_path(path) as tmp:
        workbook.save(tmp)
    return path
