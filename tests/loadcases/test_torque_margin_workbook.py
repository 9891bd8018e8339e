"""A set of torque-margin runs: envelope rows of the TM columns and the workbook's
`Torque margin` sheet, read back by value (a failing hinge line red)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

CASE = (
    Path(__file__).resolve().parents[2]
    / "loadcases"
    / "library"
    / "verification"
    / "solar_array"
    / "torque_margin_panel.case.yaml"
)


def test_set_reports_torque_margin(tmp_path: Path) -> None:
    from openpyxl import load_workbook

    from loadcases.sets.campaign import run_set

    shutil.copy(CASE, tmp_path / CASE.name)
    (tmp_path / "tm.set.yaml").write_text(
        "set: tm\ncases: [torque_margin_panel.case.yaml]\n"
        "sweep: {k_drive: [2, 0.1]}\nreport: {output: tm.xlsx}\n"
    )
    result = run_set(tmp_path / "tm.set.yaml", output_dir=tmp_path / "out")
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
