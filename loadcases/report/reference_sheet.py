"""The workbook's `Reference curves` sheet: the difference table of a set's `curves:`
(`loadcases.report.reference_curves`), then per curve, column and run a chart of the run's
curve with the reference curve over the abscissa, and the data the chart draws (the run's
rows thinned as the other charts' are, the reference's points), in the report's units."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import astuple
from typing import Any

import numpy as np
from openpyxl.chart import Reference, ScatterChart, Series
from openpyxl.utils import get_column_letter

from loadcases.foundation.clip import visible
from loadcases.report.decimate import chart_rows
from loadcases.report.number_format import SIGNIFICANT_DIGITS, number_format
from loadcases.report.reference_curves import DIFFERENCE_COLUMNS, Overlay
from loadcases.report.workbook_sheets import header_text

__all__ = ["REFERENCE_SHEET", "reference_sheet"]

REFERENCE_SHEET = "Reference curves"
_UNITS = {
    "max_difference": "unit",
    "at": "abscissa_unit",
    "relative_at": "abscissa_unit",
    "of_peak": "-",
    "max_relative": "-",
}
CHART_ROWS = 16  # rows between charts
DATA_COLUMN = 12  # first column of the charts' data, right of the charts


def _title(name: str) -> str:
    """A header with its unit (`-`: a ratio; else the row's column that names it)."""
    unit = _UNITS.get(name)
    return name if unit is None else f"{name} [{unit}]"


def _table(sheet: Any, overlays: Sequence[Overlay], digits: int) -> int:
    """The difference table from row 1 (each number with `digits` significant digits);
    the next free row."""
    for k, name in enumerate(DIFFERENCE_COLUMNS, start=1):
        sheet.cell(row=1, column=k, value=_title(name)).style = "loads header"
    for r, overlay in enumerate(overlays, start=2):
        for k, value in enumerate(astuple(overlay.difference), start=1):
            cell = sheet.cell(row=r, column=k, value=value)
            if isinstance(value, float):
                cell.style = "loads number"
                cell.number_format = number_format((value,), digits)
    sheet.column_dimensions["D"].width = 30
    return len(overlays) + 3


def _series(sheet: Any, x_col: int, first: int, last: int, title: str, line: bool) -> Series:
    x = Reference(sheet, min_col=x_col, min_row=first, max_row=last)
    y = Reference(sheet, min_col=x_col + 1, min_row=first, max_row=last)
    series = Series(y, x, title=visible(title))
    series.smooth = False
    if line:
        series.marker.symbol = "none"
    else:
        series.marker.symbol = "circle"
        series.graphicalProperties.line.noFill = True
    return series


def _block(
    sheet: Any,
    row: int,
    column: int,
    title: str,
    x: Any,
    y: Any,
    units: tuple[str, str],
    digits: int = SIGNIFICANT_DIGITS,
) -> int:
    """Two columns (x, y) from `row` with their header, each with `digits` significant
    digits of its largest magnitude; the last row written."""
    sheet.cell(row=row, column=column, value=header_text(title, None)).style = "loads label"
    sheet.cell(row=row + 1, column=column, value=units[0]).style = "loads header"
    sheet.cell(row=row + 1, column=column + 1, value=units[1]).style = "loads header"
    formats = [number_format((float(v) for v in values), digits) for values in (x, y)]
    for k, pair in enumerate(zip(x, y), start=row + 2):
        for c, (value, shown) in enumerate(zip(pair, formats)):
            cell = sheet.cell(row=k, column=column + c)
            if np.isfinite(value):
                cell.value = float(value)
                cell.number_format = shown
    return row + 1 + len(x)


def reference_sheet(
    sheet: Any, overlays: Sequence[Overlay], digits: int = SIGNIFICANT_DIGITS
) -> None:
    """The difference table, then one chart per overlay with its data to the right (numbers
    with `digits` significant digits, `report.digits`)."""
    row = _table(sheet, overlays, digits)
    data_row = row
    for overlay in overlays:
        chart = ScatterChart()
        chart.title = visible(f"{overlay.curve}: {overlay.column} - {overlay.run}")
        chart.style = 13
        x_title = header_text(overlay.abscissa, overlay.abscissa_unit)
        chart.x_axis.title = visible(x_title)
        chart.y_axis.title = visible(header_text(overlay.column, overlay.unit))
        chart.x_axis.delete = chart.y_axis.delete = False
        chart.width, chart.height = 16.0, 7.5
        x, y = np.asarray(overlay.x, float), np.asarray(overlay.y, float)
        rows = chart_rows(x.size, [y])
        x, y = x[rows], y[rows]
        names = (x_title, header_text(overlay.column, overlay.unit))
        end = _block(sheet, data_row, DATA_COLUMN, overlay.run, x, y, names, digits)
        if len(x):
            chart.series.append(_series(sheet, DATA_COLUMN, data_row + 2, end, overlay.run, True))
        ref_names = (x_title, header_text(overlay.difference.reference, None))
        ref_end = _block(
            sheet,
            data_row,
            DATA_COLUMN + 2,
            overlay.label,
            overlay.ref_x,
            overlay.ref_y,
            ref_names,
            digits,
        )
        chart.series.append(
            _series(sheet, DATA_COLUMN + 2, data_row + 2, ref_end, overlay.label, False)
        )
        sheet.add_chart(chart, f"A{row}")
        row += CHART_ROWS
        data_row = max(end, ref_end) + 2
    sheet.column_dimensions[get_column_letter(DATA_COLUMN)].width = 14
    sheet.freeze_panes = "A2"
