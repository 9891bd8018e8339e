"""Envelope-curve sheets and the native Excel charts of the sizing workbook.

Each family gets a `Curves FAMILY` sheet: its abscissa (`abscissa.value`, or `time` when
the case has no `abscissa:`), then the upper and lower envelope of every column. The
`Charts` sheet holds, per family, a line chart (scatter with straight lines) of the upper
and lower envelope of each main request column over the abscissa, and a chart of the same
column against time with one line per run (the first `MAX_SERIES` runs).

Main columns of a family: see `loadcases.report.curves.main_columns`.
"""

from __future__ import annotations

from typing import Any

from openpyxl.chart import Reference, ScatterChart, Series

from loadcases.foundation.clip import visible
from loadcases.report.curves import EnvelopeCurve, main_columns
from loadcases.report.number_format import SIGNIFICANT_DIGITS
from loadcases.report.workbook_history import Block, append_columns
from loadcases.report.workbook_sheets import header_text
from loadcases.results.files import TIME_COLUMN

__all__ = ["MAX_SERIES", "charts_sheet", "curves_sheet"]

MAX_SERIES = 12
CHART_WIDTH, CHART_HEIGHT = 16.0, 7.5  # cm
ROWS_PER_CHART, COLUMNS_PER_CHART = 16, 10  # anchor spacing on the Charts sheet


def curves_sheet(
    sheet: Any, curve: EnvelopeCurve, digits: int = SIGNIFICANT_DIGITS
) -> dict[str, tuple[int, int]]:
    """Write a family's curves (`digits` significant digits of each column's peak); return
    {column: (upper col, lower col)} (rows 2..n+1)."""
    titles = [header_text(curve.abscissa, curve.abscissa_unit)]
    where: dict[str, tuple[int, int]] = {}
    for column in curve.upper:
        unit = curve.units.get(column)
        where[column] = (len(titles) + 1, len(titles) + 2)
        titles += [header_text(f"{column} upper", unit), header_text(f"{column} lower", unit)]
    for k, title in enumerate(titles, start=1):
        sheet.cell(row=1, column=k, value=title).style = "loads header"
    data = [curve.x] + [a for c in curve.upper for a in (curve.upper[c], curve.lower[c])]
    append_columns(sheet, data, digits)
    sheet.freeze_panes = "B2"
    return where


def _chart(title: str, x_title: str, y_title: str) -> ScatterChart:
    """A chart; its titles hold names of runs and requests, hidden characters escaped (the
    chart's XML cannot hold a control character)."""
    chart = ScatterChart()
    chart.title, chart.style = visible(title), 13
    chart.x_axis.title, chart.y_axis.title = visible(x_title), visible(y_title)
    chart.x_axis.delete = chart.y_axis.delete = False  # openpyxl hides axes by default
    chart.width, chart.height = CHART_WIDTH, CHART_HEIGHT
    return chart


def _series(
    sheet: Any, x_col: int, y_col: int, first: int, last: int, title: str | None = None
) -> Series:
    """A line without markers: y from column `y_col`, x from `x_col`, rows first..last."""
    x = Reference(sheet, min_col=x_col, min_row=first, max_row=last)
    if title is None:
        series = Series(
            Reference(sheet, min_col=y_col, min_row=first - 1, max_row=last),
            x,
            title_from_data=True,
        )
    else:
        series = Series(
            Reference(sheet, min_col=y_col, min_row=first, max_row=last), x, title=visible(title)
        )
    series.marker.symbol = "none"
    series.smooth = False
    return series


def _family_charts(
    workbook: Any,
    curve: EnvelopeCurve,
    data_sheet: Any,
    where: dict[str, tuple[int, int]],
    blocks: dict[str, Block],
) -> list[ScatterChart]:
    charts, last = [], curve.x.size + 1
    x_title = header_text(curve.abscissa, curve.abscissa_unit)
    for column in main_columns(curve):
        y_title = header_text(column, curve.units.get(column))
        if last >= 2:
            chart = _chart(f"{curve.family}: envelope of {column}", x_title, y_title)
            for col in where[column]:
                chart.series.append(_series(data_sheet, 1, col, 2, last))
            charts.append(chart)
        chart = _chart(f"{curve.family}: {column} per run", header_text(TIME_COLUMN, "s"), y_title)
        for run in curve.runs[:MAX_SERIES]:
            block = blocks.get(run)
            if block is None or column not in block.columns or block.last_row < block.first_row:
                continue
            sheet = workbook[block.sheet]
            chart.series.append(
                _series(
                    sheet,
                    block.columns[TIME_COLUMN],
                    block.columns[column],
                    block.first_row,
                    block.last_row,
                    title=run,
                )
            )
        if chart.series:
            charts.append(chart)
    return charts


def charts_sheet(
    sheet: Any,
    curves: list[EnvelopeCurve],
    data_sheets: list[Any],
    wheres: list[dict[str, tuple[int, int]]],
    blocks: dict[str, Block],
) -> None:
    """Per family a heading row then its charts, two per row."""
    row = 1
    for curve, data_sheet, where in zip(curves, data_sheets, wheres):
        sheet.cell(
            row=row,
            column=1,
            value=f"{curve.family} (abscissa: {curve.abscissa}; runs: {len(curve.runs)})",
        ).style = "loads label"
        row += 1
        charts = _family_charts(sheet.parent, curve, data_sheet, where, blocks)
        for k, chart in enumerate(charts):
            column = 1 + (k % 2) * COLUMNS_PER_CHART
            sheet.add_chart(chart, f"{_letter(column)}{row + (k // 2) * ROWS_PER_CHART}")
        row += ((len(charts) + 1) // 2) * ROWS_PER_CHART + 1


def _letter(column: int) -> str:
    from openpyxl.utils import get_column_letter

    return get_column_letter(column)
