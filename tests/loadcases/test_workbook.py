"""The sizing workbook read back by value (pandas, openpyxl): sheets, numbers, links, charts."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import openpyxl
import pandas as pd
import pytest

import loadcases.report.workbook as workbook_module
from loadcases.report.workbook import sheet_title
from loadcases.results.files import read_results
from loadcases.sets.campaign import run_set
from tests.loadcases.set_fixtures import write_inputs


@pytest.fixture(scope="module")
def crank_set(tmp_path_factory: pytest.TempPathFactory):
    folder = write_inputs(tmp_path_factory.mktemp("wb"))
    return run_set(folder / "crank.set.yaml", output_dir=folder / "out")


def test_sheets_and_envelope_sheet_equal_envelope_csv(crank_set) -> None:
    path = crank_set.directory / "crank-envelope.xlsx"
    book = openpyxl.load_workbook(path)
    for name in ("Cover", "Cases", "Envelope", "Charts", "Curves crank-turn", "Provenance"):
        assert name in book.sheetnames
    from_csv = pd.read_csv(crank_set.directory / "envelope.csv")
    from_book = pd.read_excel(path, sheet_name="Envelope")
    assert list(from_book.columns) == list(from_csv.columns)
    assert list(from_csv.columns[:7]) == [
        "column",
        "max",
        "max_run",
        "max_time",
        "min",
        "min_run",
        "min_time",
    ]
    # the abscissa is the runs' x axis: a row of envelope.csv (SPEC 3), not a load row
    assert "abscissa.value" in set(from_csv["column"])
    from_csv = from_csv[from_csv["column"] != "abscissa.value"].reset_index(drop=True)
    pd.testing.assert_frame_equal(from_book, from_csv, check_dtype=False)
    sheet = book["Envelope"]
    assert sheet.freeze_panes == "B2"
    assert sheet["C2"].hyperlink is not None and sheet["C2"].hyperlink.location
    assert sheet.conditional_formatting  # negative margins highlighted
    assert len(book["Charts"]._charts) >= 2


def test_time_histories_equal_the_csv_results_by_value(crank_set) -> None:
    """Runs shorter than CHART_ROWS keep every row; the columns marked ~0 are left out."""
    path = crank_set.directory / "crank-envelope.xlsx"
    cases = pd.read_excel(path, sheet_name="Cases")
    assert list(cases["status"]) == ["ok"] * 6
    assert cases["run"].tolist() == [r.name for r in crank_set.records]
    noise = crank_set.sizing.noise
    assert noise == {"pivot_force.fz", "pivot_force.tx", "pivot_force.ty"}  # planar crank
    for record, sheet in zip(crank_set.records, cases["sheet"]):
        time, channels = read_results(record.csv_path)
        frame = pd.read_excel(path, sheet_name=sheet)
        assert frame.columns[0] == "time [s]"
        np.testing.assert_array_equal(frame.iloc[:, 0].to_numpy(), time)
        shown = [c for c in channels if c not in noise]
        for k, column in enumerate(shown, start=1):
            assert frame.columns[k].startswith(column + " [")
            np.testing.assert_array_equal(frame.iloc[:, k].to_numpy(dtype=float), channels[column])
    assert cases["csv"].tolist() == [r.csv_path.name for r in crank_set.records]


def test_many_runs_stack_per_family(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(workbook_module, "MAX_RUN_SHEETS", 2)
    folder = write_inputs(tmp_path)
    result = run_set(folder / "crank.set.yaml", output_dir=folder / "out")
    frame = pd.read_excel(result.directory / "crank-envelope.xlsx", sheet_name="crank-turn")
    assert frame["run"].drop_duplicates().tolist() == [r.name for r in result.records]
    last = result.records[-1]
    time, _channels = read_results(last.csv_path)
    block = frame[frame["run"] == last.name]
    np.testing.assert_array_equal(block["time [s]"].to_numpy(), time)


def test_sheet_titles_are_valid_and_unique() -> None:
    used: set[str] = set()
    assert sheet_title("a[b=1]/c", used) == "a(b=1)_c"
    long = "x" * 40
    assert sheet_title(long, used) == "x" * 31
    assert sheet_title(long, used) == "x" * 27 + " (2)"


def test_a_campaign_keeps_the_histories_of_the_governing_runs_only(
    crank_set, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Above MAX_HISTORY_RUNS ok runs the history sheets hold the runs named in the
    envelope's max_run / min_run, with a note; the Cases sheet still lists every run."""
    from loadcases.report.workbook import WorkbookData, write_workbook
    from loadcases.results.saved import load_saved_run

    monkeypatch.setattr(workbook_module, "MAX_HISTORY_RUNS", 2)
    runs = [load_saved_run(r.csv_path) for r in crank_set.records]
    data = WorkbookData.from_set(crank_set, runs, {})
    data.rows = [row for row in data.rows if row.column == "pivot_force.fx"]
    path = write_workbook(data, tmp_path / "c.xlsx")
    governing = {data.rows[0].max_run, data.rows[0].min_run}
    assert 0 < len(governing) < len(runs)
    cases = pd.read_excel(path, sheet_name="Cases")
    assert cases["run"].tolist() == [r.name for r in crank_set.records]
    with_sheet = set(cases.loc[cases["sheet"].notna(), "run"])
    assert with_sheet == governing
    book = openpyxl.load_workbook(path)
    sheet = book[cases.loc[cases["sheet"].notna(), "sheet"].iloc[0]]
    notes = [c.value for c in sheet[1] if isinstance(c.value, str) and "govern" in c.value]
    assert notes and "more than 2" in notes[0]
