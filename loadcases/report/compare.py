"""`loads compare OLD NEW`: two envelopes row by row, as a design change or an engine update
is reviewed.

Each side is an `envelope.csv`, a set's result folder holding one, or a folder of saved runs
(its envelope is then computed as `loads envelope` computes it). Per result column: the old
and new max and min (SI, the unit of the envelope's `unit` column) with their governing runs,
the difference new - old and the relative change, difference / the old peak of the column's
request in the same unit (max |value| over its components: a 1 N change of a joint's fy
carrying 100 kN is 1e-5, whatever fy was). A column only in NEW is `new`, only in OLD
`vanished`; one whose max and min moved by no more than `tolerance` of that peak is `same`;
one that moved but is round-off in both envelopes (`loadcases.report.roundoff`: 3e-13 ->
5e-13 N*m beside a kN*m torque) is `noise`, listed after the real changes; else `changed`.
Rows are ranked: changed (largest relative change first), new, vanished, noise, same.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from loadcases.foundation.atomic import atomic_path, atomic_write_text
from loadcases.foundation.clip import describe_character, hidden_character
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.report.csv_rows import rows_csv_text
from loadcases.report.number_format import number_format
from loadcases.report.roundoff import roundoff_columns
from loadcases.results.reading import input_text
from loadcases.results.xlsx_text import text_cells

if TYPE_CHECKING:
    from loadcases.report.units import ReportUnits

__all__ = [
    "COMPARE_COLUMNS",
    "SAME_TOLERANCE",
    "STATUSES",
    "ComparedRow",
    "Peak",
    "compare_csv_text",
    "compare_envelopes",
    "in_report_units",
    "read_envelope",
    "write_compare",
]

Fields = Sequence[str]  # an envelope table's column names, as its header gives them
_ENVELOPE_KEYS = ("column", "max", "max_run", "min", "min_run")
SAME_TOLERANCE = 1e-9  # relative: below it a change is round-off, not a change of the design
_STATUS_ORDER = {"changed": 0, "new": 1, "vanished": 2, "noise": 3, "same": 4}
STATUSES = tuple(_STATUS_ORDER)


@dataclass(frozen=True)
class Peak:
    """The envelope of one column on one side: max and min (SI) and their governing runs."""

    max: float | None
    max_run: str
    min: float | None
    min_run: str
    unit: str = ""

    @property
    def magnitude(self) -> float:
        values = [abs(v) for v in (self.max, self.min) if v is not None]
        return max(values, default=0.0)


@dataclass(frozen=True)
class ComparedRow:
    """One result column in both envelopes; `*_change` are fractions (0.05 = 5 %)."""

    column: str
    unit: str
    status: str
    old_max: float | None
    new_max: float | None
    max_diff: float | None
    max_change: float | None
    old_max_run: str
    new_max_run: str
    old_min: float | None
    new_min: float | None
    min_diff: float | None
    min_change: float | None
    old_min_run: str
    new_min_run: str

    @property
    def largest_change(self) -> float:
        changes = [abs(c) for c in (self.max_change, self.min_change) if c is not None]
        return max(changes, default=0.0)


COMPARE_COLUMNS = tuple(f.name for f in fields(ComparedRow))


def _number(source: Path, line: int, key: str, text: str | None, fields: Fields) -> float | None:
    """A peak of an envelope row: empty (a column without finite values) or a finite
    number; InputError naming the place otherwise (a peak edited to `nan` is no peak)."""
    if text is None or text.strip() == "":
        return None
    try:
        value = float(text)
    except ValueError:
        raise _problem(source, line, key, f"'{text}' is not a number", fields) from None
    if not math.isfinite(value):
        message = f"{text.strip()} is not finite (a peak is a number)"
        raise _problem(source, line, key, message, fields)
    return value


def _problem(source: Path, line: int, key: str, message: str, fields: Fields = ()) -> InputError:
    """The problem at `line` of `source`, in the column of `key` among `fields` (0 if none)."""
    column = list(fields).index(key) + 1 if key in fields else 0
    return InputError([Diagnostic(str(source), line, column, key, message)])


def _peak(source: Path, line: int, row: dict[str | None, Any], fields: Fields) -> Peak:
    """One row of an envelope table, checked."""
    if None in row or any(row[key] is None for key in _ENVELOPE_KEYS):
        raise _problem(source, line, "", "a short or long row (not the header's columns)")
    return Peak(
        _number(source, line, "max", row["max"], fields),
        row["max_run"],
        _number(source, line, "min", row["min"], fields),
        row["min_run"],
        row.get("unit") or "",
    )


def _envelope_table(source: Path) -> dict[str, Peak]:
    """Peaks by column of an envelope CSV (`envelope.csv` of a set or of `loads envelope`),
    every row checked: InputError naming the file, line and column otherwise."""
    reader = csv.DictReader(io.StringIO(input_text(source)))
    peaks: dict[str, Peak] = {}
    try:
        missing = set(_ENVELOPE_KEYS) - set(reader.fieldnames or ())
        if missing:
            raise _problem(
                source, 1, "", f"not an envelope table (no column {', '.join(sorted(missing))})"
            )
        for row in reader:
            peak = _peak(source, reader.line_num, row, reader.fieldnames or ())
            column = row["column"]
            hidden = hidden_character(column)
            if not column.strip() or hidden is not None or column in peaks:
                why = (
                    "empty column name"
                    if not column.strip()
                    else f"contains {describe_character(hidden)}"
                    if hidden is not None
                    else "given twice"
                )
                raise _problem(source, reader.line_num, "column", why, reader.fieldnames or ())
            peaks[column] = peak
    except csv.Error as error:  # a field beyond csv's limit (128 KiB), a NUL
        raise _problem(source, reader.line_num, "", f"not a CSV table: {error}") from None
    return peaks


def _envelope_file(path: Path) -> Path | None:
    """`path` itself if it is a CSV, else the envelope.csv in the folder, else None."""
    if path.is_file():
        return path
    candidate = path / "envelope.csv"
    return candidate if candidate.is_file() else None


def read_envelope(path: Path, warn: Callable[[Diagnostic], None] | None = None) -> dict[str, Peak]:
    """Peaks by column from an envelope CSV, a folder holding `envelope.csv`, or a folder of
    saved runs. Raises ValueError when `path` holds none of these, InputError (file, line,
    column) when a file it reads is not what `loads` writes; `warn` is told the warnings of
    saved runs read (a CSV changed since its summary was written)."""
    source = _envelope_file(path)
    if source is None:
        return _saved_envelope(path, warn)
    return _envelope_table(source)


def _saved_envelope(folder: Path, warn: Callable[[Diagnostic], None] | None) -> dict[str, Peak]:
    from loadcases.report.saved_report import saved_report

    if not folder.is_dir():
        raise ValueError(f"{folder}: no such file or folder")
    report = saved_report([folder])
    if warn is not None:
        for warning in report.warnings:  # a run's CSV changed since its summary was written
            warn(warning)
    if not report.runs:
        raise ValueError(
            f"{folder}: no envelope.csv and no saved results (NAME.csv with a 'time' column)"
        )
    return {
        row.column: Peak(row.max, row.max_run or "", row.min, row.min_run or "", row.unit or "")
        for row in report.rows
    }


def _diff(old: float | None, new: float | None, scale: float) -> tuple[float | None, float | None]:
    if old is None or new is None:
        return None, None
    diff = new - old
    # no relative change of a column that was zero throughout: its difference says it all
    return diff, (diff / scale if scale > 0.0 else None)


def _request_scales(peaks: dict[str, Peak]) -> dict[tuple[str, str], float]:
    """The largest magnitude of each request (`REQUEST` of `REQUEST.COMPONENT`) per unit."""
    scales: dict[tuple[str, str], float] = {}
    for column, peak in peaks.items():
        key = (column.rsplit(".", 1)[0], peak.unit)
        scales[key] = max(scales.get(key, 0.0), peak.magnitude)
    return scales


def _roundoff(peaks: dict[str, Peak]) -> set[str]:
    """The columns of an envelope that are round-off (`roundoff_columns`)."""
    return roundoff_columns(
        {c: (c.rsplit(".", 1)[0], p.unit, p.magnitude) for c, p in peaks.items()}
    )


def _row(
    column: str, old: Peak | None, new: Peak | None, tolerance: float, scale: float, noise: bool
) -> ComparedRow:
    """One column compared; `scale`: the old peak of its request in its unit; `noise`: the
    column is round-off in both envelopes."""
    blank = Peak(None, "", None, "")
    o, n = old or blank, new or blank
    max_diff, max_change = _diff(o.max, n.max, scale)
    min_diff, min_change = _diff(o.min, n.min, scale)
    if old is None or new is None:
        status = "new" if old is None else "vanished"
    else:
        moved = [abs(c) for c in (max_change, min_change) if c is not None]
        from_zero = scale == 0.0 and any(d for d in (max_diff, min_diff))
        changed = from_zero or any(c > tolerance for c in moved)
        status = ("noise" if noise else "changed") if changed else "same"
    return ComparedRow(
        column,
        n.unit or o.unit,
        status,
        o.max,
        n.max,
        max_diff,
        max_change,
        o.max_run,
        n.max_run,
        o.min,
        n.min,
        min_diff,
        min_change,
        o.min_run,
        n.min_run,
    )


def compare_envelopes(
    old: dict[str, Peak], new: dict[str, Peak], *, tolerance: float = SAME_TOLERANCE
) -> list[ComparedRow]:
    """Every column of either envelope: changed rows first (largest change relative to
    their request's peak first), then new, vanished, noise and unchanged rows in the
    envelopes' order."""
    columns = list(old) + [c for c in new if c not in old]
    scales = _request_scales(old)
    noise = _roundoff(old) & _roundoff(new)

    def scale(column: str) -> float:
        peak = old.get(column)
        return scales[(column.rsplit(".", 1)[0], peak.unit)] if peak else 0.0

    rows = [_row(c, old.get(c), new.get(c), tolerance, scale(c), c in noise) for c in columns]
    order = {c: i for i, c in enumerate(columns)}
    return sorted(
        rows,
        key=lambda r: (
            _STATUS_ORDER[r.status],
            -r.largest_change if r.status in ("changed", "noise") else 0.0,
            order[r.column],
        ),
    )


def in_report_units(rows: list[ComparedRow], units: ReportUnits) -> list[ComparedRow]:
    """The rows with their values in report units (relative changes are ratios: kept)."""
    out = []
    for row in rows:
        changes: dict[str, Any] = {
            name: units.value(getattr(row, name), row.unit)
            for name in ("old_max", "new_max", "max_diff", "old_min", "new_min", "min_diff")
        }
        changes["unit"] = units.unit(row.unit) or ""
        out.append(replace(row, **changes))
    return out


def compare_csv_text(rows: list[ComparedRow]) -> str:
    """The comparison as CSV (SI values at full precision, missing values empty)."""
    return rows_csv_text(COMPARE_COLUMNS, rows)


@text_cells()  # names in runs' files are shown as written, never as formulas
def write_compare(rows: list[ComparedRow], path: Path, *, old: str, new: str) -> Path:
    """Write the comparison atomically: `.csv`, or `.xlsx` with a `Compare` sheet (the
    changes as percentages, values with the significant digits of the row's peak, text cells
    always text) and a `Sources` sheet."""
    if path.suffix.lower() == ".csv":
        return atomic_write_text(path, compare_csv_text(rows))
    from openpyxl import Workbook
    from openpyxl.cell import WriteOnlyCell

    workbook = Workbook(write_only=True)
    sheet = workbook.create_sheet("Compare")
    sheet.freeze_panes = "B2"

    def cell(value: object, number: str | None = None) -> WriteOnlyCell:
        out = WriteOnlyCell(sheet, value="" if value is None else value)
        if isinstance(value, str):
            out.data_type = "s"  # a run name is text, never a formula
        elif number is not None and value is not None:
            out.number_format = number
        return out

    sheet.append([cell(name) for name in COMPARE_COLUMNS])
    for row in rows:
        loads = number_format((row.old_max, row.new_max, row.old_min, row.new_min))
        sheet.append(
            [
                cell(getattr(row, name), "0.00%" if name.endswith("_change") else loads)
                for name in COMPARE_COLUMNS
            ]
        )
    sources = workbook.create_sheet("Sources")
    for label, where in (("old", old), ("new", new)):
        sources.append([cell(label), cell(where)])
    with atomic_path(path) as tmp:
        workbook.save(tmp)
    return path
