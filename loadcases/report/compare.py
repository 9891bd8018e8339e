"""`loads compare OLD NEW`: two envelopes row by row, as a design change or an engine update
is reviewed.

Each side is an `envelope.csv`, a set's result folder holding one, or a folder of saved runs
(its envelope is then computed as `loads envelope` computes it). Per result column: the old
and new max and min (SI, the unit of the envelope's `unit` column) with their governing runs,
the difference new - old and the relative change, difference / the column's old magnitude
max(|old max|, |old min|), that magnitude floored at NOISE_FLOOR x the largest old magnitude
of the same request in the same unit (so that the round-off components of a planar
mechanism, 1e-37 N*m beside a 1.5 N*m torque, do not show as a 20 % change). A column
only in NEW is `new`, only in OLD `vanished`; one whose max and min moved by no more than
`tolerance` of its old magnitude is `same`, else `changed`.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable, Sequence
from dataclasses import astuple, dataclass, fields
from pathlib import Path
from typing import Any

from loadcases.foundation.atomic import atomic_path, atomic_write_text
from loadcases.foundation.clip import describe_character, hidden_character, visible_fields
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.report.roundoff import NOISE_FLOOR
from loadcases.results.reading import input_text
from loadcases.results.xlsx_text import text_cells

__all__ = [
    "COMPARE_COLUMNS",
    "SAME_TOLERANCE",
    "ComparedRow",
    "Peak",
    "compare_csv_text",
    "compare_envelopes",
    "read_envelope",
    "write_compare",
]

Fields = Sequence[str]  # an envelope table's column names, as its header gives them
_ENVELOPE_KEYS = ("column", "max", "max_run", "min", "min_run")
SAME_TOLERANCE = 1e-9  # relative: below it a change is round-off, not a change of the design
_STATUS_ORDER = {"changed": 0, "new": 1, "vanished": 2, "same": 3}


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


def _row(
    column: str, old: Peak | None, new: Peak | None, tolerance: float, request_scale: float
) -> ComparedRow:
    blank = Peak(None, "", None, "")
    o, n = old or blank, new or blank
    scale = max(o.magnitude, NOISE_FLOOR * request_scale)
    max_diff, max_change = _diff(o.max, n.max, scale)
    min_diff, min_change = _diff(o.min, n.min, scale)
    if old is None or new is None:
        status = "new" if old is None else "vanished"
    else:
        moved = [abs(c) for c in (max_change, min_change) if c is not None]
        from_zero = scale == 0.0 and any(d for d in (max_diff, min_diff))
        status = "changed" if from_zero or any(c > tolerance for c in moved) else "same"
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
    """Every column of either envelope: changed rows first (largest relative change
    first), then new, vanished and unchanged rows in the envelopes' order."""
    columns = list(old) + [c for c in new if c not in old]
    scales = _request_scales(old)

    def scale(column: str) -> float:
        peak = old.get(column)
        return scales[(column.rsplit(".", 1)[0], peak.unit)] if peak else 0.0

    rows = [_row(c, old.get(c), new.get(c), tolerance, scale(c)) for c in columns]
    order = {c: i for i, c in enumerate(columns)}
    return sorted(
        rows,
        key=lambda r: (
            _STATUS_ORDER[r.status],
            -r.largest_change if r.status == "changed" else 0.0,
            order[r.column],
        ),
    )


def _text(value: object) -> object:
    return "" if value is None else value


def compare_csv_text(rows: list[ComparedRow]) -> str:
    """The comparison as CSV (SI values at full precision, missing values empty)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(COMPARE_COLUMNS)
    writer.writerows(visible_fields(_text(v) for v in astuple(row)) for row in rows)
    return buffer.getvalue()


@text_cells()  # names in runs' files are shown as written, never as formulas
def write_compare(rows: list[ComparedRow], path: Path, *, old: str, new: str) -> Path:
    """Write the comparison atomically: `.csv`, or `.xlsx` with a `Compare` sheet (the
    changes as percentages, text cells always text) and a `Sources` sheet."""
    if path.suffix.lower() == ".csv":
        return atomic_write_text(path, compare_csv_text(rows))
    from openpyxl import Workbook
    from openpyxl.cell import WriteOnlyCell

    workbook = Workbook(write_only=True)
    sheet = workbook.create_sheet("Compare")
    sheet.freeze_panes = "B2"

    def cell(value: object, percent: bool = False) -> WriteOnlyCell:
        out = WriteOnlyCell(sheet, value=_text(value))
        if isinstance(value, str):
            out.data_type = "s"  # a run name is text, never a formula
        elif percent and value is not None:
            out.number_format = "0.00%"
        return out

    sheet.append([cell(name) for name in COMPARE_COLUMNS])
    for row in rows:
        sheet.append(
            [cell(getattr(row, name), name.endswith("_change")) for name in COMPARE_COLUMNS]
        )
    sources = workbook.create_sheet("Sources")
    for label, where in (("old", old), ("new", new)):
        sources.append([cell(label), cell(where)])
    with atomic_path(path) as tmp:
        workbook.save(tmp)
    return path
