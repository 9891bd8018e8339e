"""The time-history sheets of the sizing workbook: one run, or a family's runs stacked, each
column shown with the significant digits of its peak (`loadcases.report.number_format`),
and where each run's rows are (the charts' series point at them)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from openpyxl.cell.cell import Cell

from loadcases.report.number_format import SIGNIFICANT_DIGITS, number_format
from loadcases.report.workbook_sheets import excel_value, header_text, write_header
from loadcases.results.files import EXCEL_MAX_ROWS, TIME_COLUMN
from loadcases.results.saved import SavedRun

__all__ = ["Block", "append_columns", "history_sheet"]


@dataclass(frozen=True)
class Block:
    """Where a run's time histories are: sheet, first/last data row, column of each name."""

    sheet: str
    first_row: int
    last_row: int
    columns: dict[str, int]


def append_columns(
    sheet: Any,
    columns: list[Any],
    digits: int,
    lead: list[Any] | None = None,
    general: int = 0,
) -> None:
    """Append one row per entry of `columns` (equal-length sequences of numbers; NaN
    and infinities become empty cells), each column shown with `digits` significant digits
    of its largest magnitude but the first `general` (shown in full: time); `lead`: cells
    put first in every row (a run's name), as they are. The format's style is made once
    per column and given to each cell as it is made (setting it cell by cell afterwards
    took three times as long)."""
    styles = []
    for k, values in enumerate(columns):
        probe = Cell(sheet)
        if k >= general:
            probe.number_format = number_format((float(v) for v in values), digits)
        styles.append(probe._style)
    first = lead or []
    for values in zip(*columns):
        sheet.append(
            first
            + [
                Cell(sheet, value=excel_value(float(v)), style_array=st)
                for v, st in zip(values, styles)
            ]
        )


def history_sheet(
    sheet: Any,
    runs: list[SavedRun],
    *,
    stacked: bool,
    note: str | None = None,
    digits: int = SIGNIFICANT_DIGITS,
) -> dict[str, Block]:
    """Time histories of one run (or, `stacked`, of a family's runs one under the other,
    first column `run`); returns where each run's rows are. `note`: shown beside the
    header (how the rows were chosen); values with `digits` significant digits of each
    column's peak in the run."""
    columns = list(dict.fromkeys(c for run in runs for c in run.channels))
    units = {TIME_COLUMN: "s", **{k: v for run in runs for k, v in run.units.items()}}
    names = ["run"] * stacked + [TIME_COLUMN, *columns]
    write_header(sheet, [n if n == "run" else header_text(n, units.get(n)) for n in names])
    sheet.freeze_panes = "C2" if stacked else "B2"
    if note:
        sheet.cell(row=1, column=len(names) + 2, value=note).style = "loads note"
    blocks, row = {}, 2
    for run in runs:
        count = min(run.time.size, EXCEL_MAX_ROWS - row + 1)
        data = [run.time[:count]] + [
            run.channels[c][:count] if c in run.channels else [math.nan] * count for c in columns
        ]
        append_columns(sheet, data, digits, [run.name] if stacked else None, general=1)
        blocks[run.name] = Block(
            sheet.title, row, row + count - 1, {n: k for k, n in enumerate(names, start=1)}
        )
        row += count
        if count < run.time.size:
            sheet.cell(
                row=1,
                column=len(names) + 2,
                value=(f"rows truncated to Excel's limit; {run.name}.csv holds every row"),
            ).style = "loads note"
            break
    return blocks
