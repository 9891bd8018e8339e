"""The table sheets of the sizing workbook: Cases, Envelope, Provenance (the time histories:
`loadcases.report.workbook_history`).

Styles are the template's named styles (`loads header`, `loads number` ...; see
`loadcases.report.workbook_template`). Values are written as they are (SI floats); NaN and
infinities become empty cells because Excel has no such numbers.
"""

from __future__ import annotations

import datetime as dt
import math
from dataclasses import astuple
from typing import Any

from openpyxl.comments import Comment
from openpyxl.formatting.rule import CellIsRule
from openpyxl.styles import PatternFill
from openpyxl.utils import get_column_letter
from openpyxl.worksheet.hyperlink import Hyperlink

from loadcases.report.envelope import ENVELOPE_COLUMNS, EnvelopeRow
from loadcases.report.margin_table import allowable_lines
from loadcases.report.number_format import SIGNIFICANT_DIGITS, number_format
from loadcases.results.files import EXCEL_MAX_LINKS, EXCEL_MAX_ROWS
from loadcases.results.saved import RunRecord
from loadcases.results.verdict import AccuracyVerdict

__all__ = [
    "CASES_COLUMNS",
    "EXCEL_MAX_LINKS",
    "cases_sheet",
    "envelope_sheet",
    "excel_value",
    "header_text",
    "provenance_sheet",
    "write_header",
]

CASES_COLUMNS = (
    "run",
    "case",
    "file",
    "parameters (SI)",
    "analysis",
    "status",
    "message",
    "CPU time [s]",
    "steps",
    "reused",
    "input_sha256",
    "sheet",
    "csv",
    "level",
    "accuracy target (of peak)",
    "accuracy met",
    "accuracy outcome",
)
_NEGATIVE_FILL = PatternFill("solid", start_color="FF9999", end_color="FF9999")
_NUMBER_COLUMNS = {
    "max",
    "min",
    "max_abscissa",
    "min_abscissa",
    "abs_max",
    "ultimate_max",
    "ultimate_min",
    "allowable_max",
    "allowable_min",
    "limit_allowable_max",
    "limit_allowable_min",
}
_ABSCISSA_COLUMNS = {"max_abscissa", "min_abscissa"}
_TIME_COLUMNS = {"max_time", "min_time"}
_MARGIN_COLUMNS = {"factor", "factor_min", "ms_max", "ms_min", "ms_limit_max", "ms_limit_min"}
_HEADER_NOTES = {
    "unit": "unit of the row's values (max, min, ultimate, allowables, concurrent values): "
    "the set's report.units, else SI",
    "max_time": "s (or the report's time unit)",
    "min_time": "s (or the report's time unit)",
    "factor": "-: ultimate x fitting x case factor (of the max side)",
    "ms_max": "-: allowable_max / (factor x max) - 1",
    "ms_min": "-: allowable_min / (factor_min x min) - 1",
    "factor_min": "-: ultimate x fitting x case factor of the min side",
    "noise": "~0: numerical noise (below report.noise_floor of the request's or set's peak): "
    "no factor, no margin",
    "ms_limit_max": "-: limit_allowable_max / (factor / ultimate x max) - 1",
    "ms_limit_min": "-: limit_allowable_min / (factor_min / ultimate x min) - 1",
    "max_abscissa": "unit of the case's abscissa (column abscissa.value)",
    "max_level": "level of max_run's applied loads: limit, or ultimate (then max = its "
    "computed load / ultimate factor)",
    "min_level": "level of min_run's applied loads: limit, or ultimate (then min = its "
    "computed load / ultimate factor)",
    "min_abscissa": "unit of the case's abscissa (column abscissa.value)",
}


def excel_value(value: Any) -> Any:
    """The value as a cell holds it: NaN and infinities empty (Excel has no such numbers)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def header_text(name: str, unit: str | None) -> str:
    """`pivot_force.fx [N]`; `[-]` for a dimensionless or unknown unit."""
    return f"{name} [{unit if unit not in (None, '', '1') else '-'}]"


def write_header(sheet: Any, titles: list[str], row: int = 1) -> None:
    """Header cells in the template's `loads header` style, from column 1 of `row`."""
    for column, title in enumerate(titles, start=1):
        sheet.cell(row=row, column=column, value=title).style = "loads header"


def _link(cell: Any, sheet_name: str | None) -> None:
    if sheet_name:
        # An internal link (a location, not a `#` URL) opens the sheet in any viewer.
        cell.hyperlink = Hyperlink(ref=cell.coordinate, location=f"'{sheet_name}'!A1")
        cell.style = "Hyperlink"


def cases_sheet(
    sheet: Any,
    records: list[RunRecord],
    run_sheets: dict[str, str],
    csv_links: dict[str, str] | None = None,
) -> None:
    """One row per run: case, file, parameters, analysis, status, message, CPU time, hash,
    its time-history sheet and its CSV file (`csv_links` {run: path from the workbook}),
    level, and a dynamic run's accuracy verdict (target, met, outcome; empty without one).
    Within Excel's limits: at most EXCEL_MAX_ROWS - 1 runs and EXCEL_MAX_LINKS hyperlinks
    (the links to the runs' sheets first, then to their CSV files, in run order); a note
    beside the header says what is left out (the CSV column still names every file)."""
    links = csv_links or {}
    write_header(sheet, list(CASES_COLUMNS))
    shown = records[: EXCEL_MAX_ROWS - 1]
    to_sheets = [r.name for r in shown if run_sheets.get(r.name)]
    to_files = [r.name for r in shown if r.name in links]
    linked_sheets = set(to_sheets[:EXCEL_MAX_LINKS])
    file_links = set(to_files[: EXCEL_MAX_LINKS - len(linked_sheets)])
    for row, r in enumerate(shown, start=2):
        parameters = ", ".join(f"{k}={v:g}" for k, v in r.parameters.items())
        values = (
            r.name,
            r.family,
            r.case_file,
            parameters,
            r.analysis,
            r.status,
            r.message,
            r.cpu_seconds,
            r.steps,
            "yes" if r.reused else "no",
            r.input_sha256,
            run_sheets.get(r.name, ""),
            links.get(r.name, ""),
            r.level,
            *_verdict_cells(r.accuracy),
        )
        for column, value in enumerate(values, start=1):
            sheet.cell(row=row, column=column, value=value)
        if r.name in linked_sheets:
            _link(sheet.cell(row=row, column=1), run_sheets[r.name])
        if r.name in file_links:  # a file next to the workbook: opens in any spreadsheet program
            csv_cell = sheet.cell(row=row, column=CASES_COLUMNS.index("csv") + 1)
            csv_cell.hyperlink, csv_cell.style = links[r.name], "Hyperlink"
        if not r.ok:
            for column in (6, 7):
                sheet.cell(row=row, column=column).style = "loads failed"
    linked, wanted = len(linked_sheets) + len(file_links), len(to_sheets) + len(to_files)
    note = _cases_note(len(records), len(shown), linked < wanted)
    if note:
        sheet.cell(row=1, column=len(CASES_COLUMNS) + 2, value=note).style = "loads note"
    sheet.freeze_panes = "B2"
    for letter, width in zip("ABCDEFG", (36, 24, 40, 30, 12, 8, 60)):
        sheet.column_dimensions[letter].width = width
    outcome = get_column_letter(CASES_COLUMNS.index("accuracy outcome") + 1)
    sheet.column_dimensions[outcome].width = 60


def _verdict_cells(verdict: AccuracyVerdict | None) -> tuple[float | None, str, str]:
    """The Cases sheet's accuracy target, met and outcome of a run (empty without)."""
    if verdict is None:
        return None, "", ""
    return verdict.target, verdict.met_text, verdict.outcome


def _cases_note(runs: int, shown: int, unlinked: bool) -> str | None:
    """What the Cases sheet leaves out for Excel's limits (None: nothing)."""
    notes = []
    if shown < runs:
        notes.append(
            f"the first {shown} of {runs} runs (Excel's {EXCEL_MAX_ROWS} rows a sheet): every "
            "run's CSV and summary are in the set's folder"
        )
    if unlinked:
        notes.append(
            f"hyperlinks for the first runs only (Excel holds {EXCEL_MAX_LINKS} a sheet): "
            "the csv column names every run's file"
        )
    return "; ".join(notes) or None


def _row_formats(row: EnvelopeRow, digits: int) -> tuple[str, str]:
    """(format of the row's values, format of its abscissae): `digits` significant digits
    of the row's peak (max, min; its ultimate loads and allowables share the decimals)
    and of its largest abscissa, in the unit shown."""
    at = (row.max_abscissa, row.min_abscissa)
    return number_format((row.max, row.min), digits), number_format(at, digits)


def envelope_sheet(
    sheet: Any,
    rows: list[EnvelopeRow],
    run_sheets: dict[str, str],
    digits: int = SIGNIFICANT_DIGITS,
) -> None:
    """The envelope table: header = `envelope.csv`'s, frozen, margins flagged, values with
    `digits` significant digits of each row's peak."""
    write_header(sheet, list(ENVELOPE_COLUMNS))
    for column, name in enumerate(ENVELOPE_COLUMNS, start=1):
        note = _HEADER_NOTES.get(
            name, "unit: see column 'unit'" if name in _NUMBER_COLUMNS else None
        )
        if note:
            sheet.cell(row=1, column=column).comment = Comment(note, "loads")
    index = {name: k for k, name in enumerate(ENVELOPE_COLUMNS, start=1)}
    for r, row in enumerate(rows, start=2):
        formats = _row_formats(row, digits)
        for name, value in zip(ENVELOPE_COLUMNS, astuple(row)):
            cell = sheet.cell(row=r, column=index[name], value=excel_value(value))
            if name in _NUMBER_COLUMNS:
                cell.style = "loads number"
                cell.number_format = formats[name in _ABSCISSA_COLUMNS]
            elif name in _TIME_COLUMNS:
                cell.style = "loads time"
            elif name in _MARGIN_COLUMNS:
                cell.style = "loads margin"
        _link(sheet.cell(row=r, column=index["max_run"]), run_sheets.get(row.max_run or ""))
        _link(sheet.cell(row=r, column=index["min_run"]), run_sheets.get(row.min_run or ""))
    last = max(len(rows) + 1, 2)
    for name in ("ms_max", "ms_min", "ms_limit_max", "ms_limit_min"):
        letter = get_column_letter(index[name])
        sheet.conditional_formatting.add(
            f"{letter}2:{letter}{last}",
            CellIsRule(operator="lessThan", formula=["0"], fill=_NEGATIVE_FILL),
        )
    sheet.freeze_panes = "B2"
    sheet.column_dimensions["A"].width = 28
    for name in ("max_run", "min_run", "max_concurrent", "min_concurrent"):
        sheet.column_dimensions[get_column_letter(index[name])].width = 30


def provenance_sheet(sheet: Any, data: Any, python_version: str) -> None:
    """Engine version, date, inputs with SHA-256, solver settings and options, every
    allowable given (ultimate and limit, in the rows' units)."""
    now = dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M:%S UTC")
    lines = [
        ("engine", "loads"),
        ("engine version", data.version),
        ("date", now),
        ("python", python_version),
        ("set", data.title),
        ("set file", data.source),
    ]
    write_header(sheet, ["item", "value", "sha256"])
    for key, value in lines:
        sheet.append([key, value])
    for path, sha in data.inputs:
        sheet.append(["input file", path, sha])
    for key, value in [*data.settings, *allowable_lines(data.rows)]:
        sheet.append([key, value])
    sheet.column_dimensions["A"].width = 32
    sheet.column_dimensions["B"].width = 70
    sheet.column_dimensions["C"].width = 66
