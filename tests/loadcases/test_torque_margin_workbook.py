"""A set of torque-margin runs: envelope rows of the TM columns and the workbook's
`Torque margin` sheet, read back by value (a failing hinge line red); the set's
`comparisons:` of the two runs (comparisons.csv, sheet `Comparison`) against the closed
form."""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any

import pytest

from tests.loadcases.set_fixtures import TM_PANEL_CASE as CASE

# the drive spring's torque compared between the two runs
COMPARISONS = """\
comparisons:
  softer:
    reference: "torque-margin-panel[k_drive=2]"
    runs: ["torque-margin-panel[k_drive=0.1]"]
    columns: [spring, drive_torque.value]
"""


@pytest.fixture(scope="module")
def tm_set(tmp_path_factory: pytest.TempPathFactory) -> tuple[Any, Path]:
    """The set run once for the torque-margin and the comparison tests."""
    from loadcases.sets.campaign import run_set

    tmp_path = tmp_path_factory.mktemp("tm")
    text = CASE.read_text().replace("requests:\n", "requests:\n  spring: {force: drive}\n")
    (tmp_path / CASE.name).write_text(text)
    (tmp_path / "tm.set.yaml").write_text(
        "set: tm\ncases: [torque_margin_panel.case.yaml]\n"
        "sweep: {k_drive: [2, 0.1]}\n" + COMPARISONS + "report: {output: tm.xlsx}\n"
    )
    return run_set(tmp_path / "tm.set.yaml", output_dir=tmp_path / "out"), tmp_path


def test_set_reports_torque_margin(tm_set: tuple[Any, Path]) -> None:
    from openpyxl import load_workbook

    result, tmp_path = tm_set
    assert all(r.ok for r in result.records)
    row = next(r for r in result.envelope if r.column == "tm_HL1.ratio")
    assert row.min_run == "torque-margin-panel[k_drive=0.1]"
    sheet = load_workbook(tmp_path / "out" / "tm" / "tm.xlsx")["Torque margin"]
    rows = {r[0]: r for r in sheet.iter_rows(min_row=2, values_only=True)}
    strong, weak = rows["torque-margin-panel[k_drive=2]"], rows["torque-margin-panel[k_drive=0.1]"]
    assert strong[1] == "HL1" and strong[2] == pytest.approx(2.0, rel=1e-12)
    assert strong[-1] == "pass" and weak[-1] == "FAIL"
    assert weak[3] == pytest.approx(row.min, rel=1e-12) and weak[3] < 2
    red = {sheet.cell(row=r, column=4).style for r in (2, 3)}
    assert red == {"loads failed", "Normal"}


def test_set_compares_runs(tm_set: tuple[Any, Path]) -> None:
    """The drive spring k (theta - pi) peaks at theta = 0 (t = 0): -k pi, ratio 0.1 / 2."""
    from openpyxl import load_workbook

    folder = tm_set[1] / "out" / "tm"
    with open(folder / "comparisons.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    spring = {r["run"]: r for r in rows if r["column"] == "spring.value"}
    stiff, soft = (
        spring["torque-margin-panel[k_drive=2]"],
        spring["torque-margin-panel[k_drive=0.1]"],
    )
    assert float(stiff["peak"]) == pytest.approx(-2 * math.pi, rel=1e-12)
    assert float(stiff["time"]) == 0.0 and float(stiff["ratio"]) == 1.0
    assert float(soft["ratio"]) == pytest.approx(0.05, rel=1e-12)
    assert stiff["unit"] == "N*m" and {r["comparison"] for r in rows} == {"softer"}
    sheet = load_workbook(folder / "tm.xlsx")["Comparison"]
    lines = list(sheet.iter_rows(values_only=True))
    assert lines[0][:4] == ("comparison", "column", "unit", "torque-margin-panel[k_drive=2] peak")
    assert lines[0][7] == "torque-margin-panel[k_drive=0.1] / reference"
    row = next(line for line in lines if line[1] == "spring.value")
    assert row[2] == "N*m" and row[3] == pytest.approx(-2 * math.pi, rel=1e-12)
    assert row[7] == pytest.approx(0.05, rel=1e-12)
