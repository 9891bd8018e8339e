"""Envelopes across runs: per result column, the max and min over all runs and where they occur.

Used by `loads envelope DIR...` on saved results (`NAME.csv` files, see `loadcases.results`).
An envelope table has one row per result column (except `time`), with the columns
`column, max, max_run, max_time, min, min_run, min_time` (SPEC section 3). NaN and infinite
values are skipped; ties keep the first run in the given order and the earliest time.
"""
from __future__ import annotations

import csv
import io
import json
from collections.abc import Iterable
from dataclasses import astuple, dataclass, fields
from pathlib import Path

import numpy as np

from loadcases.atomic import atomic_path, atomic_write_text
from loadcases.results import SUMMARY_SUFFIX, TIME_COLUMN, column_extremes, read_results

__all__ = [
    "EnvelopeRow", "ENVELOPE_COLUMNS", "extract_envelope", "find_result_files",
    "load_saved_runs", "envelope_csv_text", "write_envelope_csv", "write_envelope_xlsx",
]

Run = tuple[str, np.ndarray, dict[str, np.ndarray]]


@dataclass
class EnvelopeRow:
    """Extremes of one column over all runs (values SI; `None` when no finite value)."""

    column: str
    max: float | None = None
    max_run: str | None = None
    max_time: float | None = None
    min: float | None = None
    min_run: str | None = None
    min_time: float | None = None


ENVELOPE_COLUMNS = tuple(f.name for f in fields(EnvelopeRow))


def extract_envelope(runs: Iterable[Run]) -> list[EnvelopeRow]:
    """Envelope of `(run_name, time, channels)` runs; rows in first-seen column order."""
    rows: dict[str, EnvelopeRow] = {}
    for run, time, channels in runs:
        for column, values in channels.items():
            row = rows.setdefault(column, EnvelopeRow(column))
            ext = column_extremes(time, values)
            if ext["max"] is not None and (row.max is None or ext["max"] > row.max):
                row.max, row.max_run, row.max_time = ext["max"], run, ext["time_of_max"]
            if ext["min"] is not None and (row.min is None or ext["min"] < row.min):
                row.min, row.min_run, row.min_time = ext["min"], run, ext["time_of_min"]
    return list(rows.values())


def find_result_files(directories: Iterable[Path]) -> list[tuple[Path, Path]]:
    """`(directory, csv_path)` of every results CSV below the directories (recursive, sorted).

    A results CSV is one whose first header cell is `time`; others (such as an
    `envelope.csv`) are not results and are left out.
    """
    found = []
    for directory in directories:
        for path in sorted(Path(directory).rglob("*.csv")):
            if path.is_file() and _first_header_cell(path) == TIME_COLUMN:
                found.append((Path(directory), path))
    return found


def load_saved_runs(files: Iterable[tuple[Path, Path]]) -> list[Run]:
    """Read result files; each run is named by its summary's `case`, else its relative path."""
    runs = []
    for directory, path in files:
        time, channels = read_results(path)
        runs.append((_run_name(directory, path), time, channels))
    return runs


def envelope_csv_text(rows: list[EnvelopeRow]) -> str:
    """The envelope as CSV text (floats at full precision, missing values empty)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(ENVELOPE_COLUMNS)
    writer.writerows(["" if value is None else value for value in astuple(row)] for row in rows)
    return buffer.getvalue()


def write_envelope_csv(rows: list[EnvelopeRow], path: Path) -> Path:
    """Write `envelope.csv` atomically."""
    return atomic_write_text(path, envelope_csv_text(rows))


def write_envelope_xlsx(rows: list[EnvelopeRow], path: Path, *, sources: Iterable[str] = ()) -> Path:
    """Write a workbook with sheet `Envelope` (frozen header) and sheet `Runs` (the sources)."""
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


def _first_header_cell(path: Path) -> str | None:
    with open(path, newline="", encoding="utf-8", errors="replace") as stream:
        header = next(csv.reader(stream), None)
    return header[0] if header else None


def _run_name(directory: Path, csv_path: Path) -> str:
    summary = csv_path.with_name(csv_path.name[: -len(".csv")] + SUMMARY_SUFFIX)
    if summary.is_file():
        case = json.loads(summary.read_text(encoding="utf-8")).get("case")
        if isinstance(case, str) and case:
            return case
    return csv_path.relative_to(directory).as_posix()[: -len(".csv")]
