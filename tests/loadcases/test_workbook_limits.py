"""The workbook of a large campaign within Excel's limits of a worksheet.

A campaign of 4,100 runs needs 4 + 4 x 4,100 = 16,404 columns for its loads matrix: the
matrix must go on over a second sheet, every run's peaks on one of them, never a column
past XFD (Excel reports such a file as corrupt; openpyxl writes it without complaint). Its
Cases sheet links each run's CSV file: at most 65,530 hyperlinks and 1,048,576 rows.
"""

from __future__ import annotations

from pathlib import Path

import openpyxl
import pytest

from loadcases.report import workbook_sheets as sheets
from loadcases.report.loads_matrix import loads_matrix
from loadcases.report.peaks import RunPeak
from loadcases.report.workbook import _load_template
from loadcases.report.workbook_tables import (
    CRITICAL_FILL,
    EXCEL_MAX_COLUMNS,
    HEADS_PER_SHEET,
    matrix_sheets,
)
from loadcases.results.saved import RunRecord
from loadcases.results.xlsx_floats import exact_floats

RUNS = 4100
HIGH, LOW = 4098, 10  # the runs of the largest max (on the second sheet) and smallest min


def _peak(k: int) -> RunPeak:
    top = 5.0 + (1.0 if k == HIGH else 0.0) + 1e-4 * k
    bottom = -5.0 - (1.0 if k == LOW else 0.0) + 1e-4 * k
    return RunPeak(f"crank[rate={k}]", "crank", top, 0.001 * k, None, bottom, 0.002 * k, None)


def _matrix():
    runs = [(f"crank[rate={k}]", "crank") for k in range(RUNS)]
    peaks = {"pivot_force.fx": [_peak(k) for k in range(RUNS)]}
    return loads_matrix(peaks, runs, units={"pivot_force.fx": "N"}, at={})


def test_a_matrix_wider_than_a_sheet_goes_on_over_a_second_one(tmp_path: Path) -> None:
    matrix = _matrix()
    workbook = _load_template(None)
    sheets = matrix_sheets(workbook.create_sheet, matrix)
    assert [s.title for s in sheets] == ["Loads matrix", "Loads matrix 2"]
    path = tmp_path / "m.xlsx"
    with exact_floats():  # as write_workbook saves: 17 significant digits
        workbook.save(path)
    book = openpyxl.load_workbook(path)
    first, second = book["Loads matrix"], book["Loads matrix 2"]
    assert HEADS_PER_SHEET == 4095
    assert first.max_column == EXCEL_MAX_COLUMNS == 4 + 4 * HEADS_PER_SHEET
    assert second.max_column == 4 + 4 * (RUNS - HEADS_PER_SHEET)
    # every run's max and min, each on the sheet and in the columns of its head
    for k in range(RUNS):
        sheet, h = (first, k) if k < HEADS_PER_SHEET else (second, k - HEADS_PER_SHEET)
        column = 5 + 4 * h
        assert sheet.cell(row=1, column=column).value == f"crank[rate={k}]"
        assert sheet.cell(row=3, column=column).value == _peak(k).max
        assert sheet.cell(row=3, column=column + 1).value == pytest.approx(0.001 * k)
        assert sheet.cell(row=3, column=column + 2).value == _peak(k).min
    # the critical runs named on both sheets, their cells filled where they are
    for sheet in (first, second):
        assert sheet.cell(row=3, column=3).value == f"crank[rate={HIGH}]"
        assert sheet.cell(row=3, column=4).value == f"crank[rate={LOW}]"
        assert "Loads matrix 2: runs 4096 to 4100" in sheet.cell(row=5, column=1).value
    high = second.cell(row=3, column=5 + 4 * (HIGH - HEADS_PER_SHEET))
    low = first.cell(row=3, column=5 + 4 * LOW + 2)
    assert high.fill.fgColor.rgb.endswith(CRITICAL_FILL["max"].fgColor.rgb[-6:])
    assert low.fill.fgColor.rgb.endswith(CRITICAL_FILL["min"].fgColor.rgb[-6:])


def test_a_matrix_that_fits_stays_on_one_sheet_without_a_note() -> None:
    runs = [("a", "a"), ("b", "b")]
    peaks = {
        "f.fx": [
            RunPeak("a", "a", 1.0, 0.1, None, -2.0, 0.2, None),
            RunPeak("b", "b", 3.0, 0.3, None, -1.0, 0.4, None),
        ]
    }
    matrix = loads_matrix(peaks, runs, units={"f.fx": "N"}, at={})
    workbook = _load_template(None)
    (sheet,) = matrix_sheets(workbook.create_sheet, matrix)
    assert sheet.title == "Loads matrix" and sheet.max_column == 12
    assert sheet.cell(row=3, column=3).value == "b" and sheet.cell(row=3, column=4).value == "a"
    assert sheet.cell(row=5, column=1).value is None


def _record(k: int) -> RunRecord:
    return RunRecord(
        f"crank[rate={k}]", "crank", "crank.case.yaml", {"rate": float(k)}, "dynamic", "ok",
        "finished", 1005, 0.04, "0" * 64, Path(f"crank[rate={k}].csv"),
    )  # fmt: skip


def test_the_cases_sheet_keeps_within_excels_rows_and_hyperlinks(tmp_path, monkeypatch) -> None:
    """Excel holds 65,530 hyperlinks and 1,048,576 rows a sheet (a campaign's Cases sheet
    has a link per run): beyond them the sheet keeps the first runs, the links to the runs'
    sheets first, and says so; every shown row still names its CSV file. The limits are
    made small here (5 rows, 3 links), as a sheet of 65,531 runs takes minutes to write."""
    assert (sheets.EXCEL_MAX_LINKS, sheets.EXCEL_MAX_ROWS) == (65_530, 1_048_576)
    monkeypatch.setattr(sheets, "EXCEL_MAX_ROWS", 6)
    monkeypatch.setattr(sheets, "EXCEL_MAX_LINKS", 3)
    records = [_record(k) for k in range(7)]
    run_sheets = {records[1].name: "crank", records[3].name: "crank"}
    links = {r.name: f"campaign/{r.name}.csv" for r in records}
    workbook = _load_template(None)
    sheets.cases_sheet(workbook.create_sheet("Cases"), records, run_sheets, links)
    path = tmp_path / "cases.xlsx"
    workbook.save(path)
    sheet = openpyxl.load_workbook(path)["Cases"]
    names = [sheet.cell(row=r, column=1).value for r in range(2, 8)]
    assert names == [r.name for r in records[:5]] + [None]
    linked = {
        (cell.row, cell.column) for row in sheet.iter_rows() for cell in row if cell.hyperlink
    }
    assert linked == {(3, 1), (5, 1), (2, 13)}  # both sheet links, then one file link
    assert [sheet.cell(row=r, column=13).value for r in range(2, 7)] == [
        links[r.name] for r in records[:5]
    ]
    note = sheet.cell(row=1, column=len(sheets.CASES_COLUMNS) + 2).value  # beside the header
    assert "the first 5 of 7 runs" in note and "hyperlinks for the first runs only" in note


def test_the_cases_sheet_of_a_small_set_links_every_run_without_a_note(tmp_path) -> None:
    records = [_record(k) for k in range(3)]
    links = {r.name: f"campaign/{r.name}.csv" for r in records}
    workbook = _load_template(None)
    sheets.cases_sheet(workbook.create_sheet("Cases"), records, {}, links)
    sheet = workbook["Cases"]
    assert [sheet.cell(row=r, column=13).hyperlink.target for r in (2, 3, 4)] == list(
        links.values()
    )
    assert sheet.cell(row=1, column=len(sheets.CASES_COLUMNS) + 2).value is None
