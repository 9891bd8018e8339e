"""The stress office's sheets of the sizing workbook: `Margins` (every margin, lowest first)
and `Loads matrix` (peak per component and run, critical run highlighted).

Values are in the rows' units (the set's `report.units`, else SI); numerical noise shows
as the text `~0` in the loads matrix. A matrix of more runs than one sheet's 16,384
columns hold (4,095 runs of four columns) goes on over `Loads matrix 2`, `Loads matrix 3`,
... (the same rows and first four columns on each; `loads-matrix.csv` has no such limit).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from openpyxl.comments import Comment
from openpyxl.styles import Alignment, PatternFill
from openpyxl.utils import get_column_letter

from loadcases.report.loads_matrix import SIDES, LoadsMatrix
from loadcases.report.margin_table import MARGIN_COLUMNS, MarginLine
from loadcases.report.noise import NOISE_MARK
from loadcases.report.number_format import SIGNIFICANT_DIGITS, number_format
from loadcases.report.workbook_sheets import header_text
from loadcases.results.files import EXCEL_MAX_COLUMNS

__all__ = [
    "CRITICAL_FILL",
    "EXCEL_MAX_COLUMNS",
    "HEADS_PER_SHEET",
    "margins_sheet",
    "matrix_sheets",
]

CRITICAL_FILL = {
    "max": PatternFill("solid", start_color="F4B183", end_color="F4B183"),
    "min": PatternFill("solid", start_color="9DC3E6", end_color="9DC3E6"),
}
_NEGATIVE = PatternFill("solid", start_color="FF9999", end_color="FF9999")
_MARGIN_STYLES = {
    "load": "loads number",
    "factored_load": "loads number",
    "allowable": "loads number",
    "factor": "loads margin",
    "ms": "loads margin",
}
FIRST_HEAD_COLUMN = 5  # column, unit, critical max, critical min, then the heads
HEADS_PER_SHEET = (EXCEL_MAX_COLUMNS - FIRST_HEAD_COLUMN + 1) // 4  # 4,095 runs a sheet
MATRIX_TITLE = "Loads matrix"


def _value(value: Any) -> Any:
    """Excel has no NaN or infinity: those become empty cells."""
    return None if isinstance(value, float) and not math.isfinite(value) else value


def margins_sheet(sheet: Any, lines: list[MarginLine], digits: int = SIGNIFICANT_DIGITS) -> None:
    """One row per margin, lowest first; negative margins filled red; loads with `digits`
    significant digits of the line's largest."""
    for k, name in enumerate(MARGIN_COLUMNS, start=1):
        sheet.cell(row=1, column=k, value=name).style = "loads header"
    ms_column = MARGIN_COLUMNS.index("ms") + 1
    for r, line in enumerate(lines, start=2):
        loads = number_format((line.load, line.factored_load, line.allowable), digits)
        for k, name in enumerate(MARGIN_COLUMNS, start=1):
            value = getattr(line, name)
            cell = sheet.cell(row=r, column=k, value=_value(value))
            if name in _MARGIN_STYLES:
                cell.style = _MARGIN_STYLES[name]
            if _MARGIN_STYLES.get(name) == "loads number":
                cell.number_format = loads
        ms = sheet.cell(row=r, column=ms_column)
        if ms.value is not None and ms.value < 0:
            ms.fill = _NEGATIVE
    sheet.freeze_panes = "B2"
    sheet.column_dimensions["A"].width = 28
    sheet.column_dimensions[get_column_letter(MARGIN_COLUMNS.index("run") + 1)].width = 36


# a run's name centred across its four columns; not merged cells: openpyxl checks each new
# merge against every earlier one (1000 runs: 0.6 s, growing with the square of the runs)
_ACROSS = Alignment(horizontal="centerContinuous")
_ULTIMATE_NOTE = (
    "its case gives ultimate-level loads: shown at limit level (computed / ultimate "
    "factor), as every run of the matrix; loads-matrix.csv has the ultimate loads"
)


def _heads(sheet: Any, matrix: LoadsMatrix, heads: range) -> None:
    """Two header rows: the run (family) over its four columns, then max / at / min / at,
    for the matrix's `heads`."""
    for k, title in enumerate(("column", "unit", "critical max", "critical min"), start=1):
        sheet.cell(row=1, column=k, value=title).style = "loads header"
        sheet.cell(row=2, column=k).style = "loads header"
    for h, g in enumerate(heads):
        head, (name, unit) = matrix.heads[g], matrix.at[g]
        first = FIRST_HEAD_COLUMN + 4 * h
        for k in range(4):
            cell = sheet.cell(row=1, column=first + k, value=head if k == 0 else None)
            cell.style = "loads header"
            cell.alignment = _ACROSS
        if g < len(matrix.levels) and matrix.levels[g] == "ultimate":
            sheet.cell(row=1, column=first).comment = Comment(_ULTIMATE_NOTE, "loads")
        at = header_text(f"at {name}", unit)
        for k, title in enumerate(("max", at, "min", at)):
            sheet.cell(row=2, column=first + k, value=title).style = "loads header"


def matrix_sheets(
    new_sheet: Callable[[str], Any], matrix: LoadsMatrix, digits: int = SIGNIFICANT_DIGITS
) -> list[Any]:
    """The loads matrix on sheets made by `new_sheet(title)`: `Loads matrix`, then, for more
    than HEADS_PER_SHEET runs (families), `Loads matrix 2`, ... with the next ones; below
    the rows of each sheet of several, a note of which runs are on which sheet."""
    parts = [
        range(start, min(start + HEADS_PER_SHEET, len(matrix.heads)))
        for start in range(0, max(len(matrix.heads), 1), HEADS_PER_SHEET)
    ]
    sheets = []
    for k, heads in enumerate(parts, start=1):
        sheet = new_sheet(MATRIX_TITLE if k == 1 else f"{MATRIX_TITLE} {k}")
        _matrix_sheet(sheet, matrix, heads, digits)
        sheets.append(sheet)
    if len(parts) > 1:
        note = "; ".join(
            f"{sheet.title}: {matrix.by} {heads.start + 1} to {heads.stop}"
            for sheet, heads in zip(sheets, parts)
        )
        for sheet in sheets:
            sheet.cell(row=len(matrix.rows) + 4, column=1, value=note).style = "loads note"
    return sheets


def _matrix_sheet(
    sheet: Any, matrix: LoadsMatrix, heads: range, digits: int = SIGNIFICANT_DIGITS
) -> None:
    """The loads matrix's `heads` (the critical columns name the matrix's critical run,
    wherever it is): each row's critical max cell orange, critical min cell blue."""
    _heads(sheet, matrix, heads)
    for r, row in enumerate(matrix.rows, start=3):
        loads = number_format(
            (getattr(c, side) for c in row.cells if c is not None for side in SIDES), digits
        )
        critical = [
            matrix.heads[k] if k is not None else None for k in map(row.critical.get, SIDES)
        ]
        for k, value in enumerate((row.column, row.unit, *critical), start=1):
            sheet.cell(row=r, column=k, value=value)
        for h, g in enumerate(heads):
            cell = row.cells[g]
            if cell is None:
                continue
            for s, side in enumerate(SIDES):
                column = FIRST_HEAD_COLUMN + 4 * h + 2 * s
                peak = sheet.cell(row=r, column=column)
                if row.noise:
                    peak.value = NOISE_MARK
                    continue
                peak.value = _value(getattr(cell, side))
                peak.style = "loads number"
                peak.number_format = loads
                sheet.cell(row=r, column=column + 1, value=_value(cell.at(side)))
                if row.critical.get(side) == g:
                    peak.fill = CRITICAL_FILL[side]
    sheet.freeze_panes = f"{get_column_letter(FIRST_HEAD_COLUMN)}3"
    sheet.column_dimensions["A"].width = 28
