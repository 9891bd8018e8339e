"""`report.units` of a set (SPEC 1.4, normative): the workbook, the plots and the envelope
tables show each kind in the unit the set names; envelope.csv and the runs' CSV stay SI.

The crank of set_fixtures.py holds P = 10 N at its 0.1 m tip while turning 0.5 rad: its
drive torque peaks at 0.1 P + m g 0.05 = 1.4905 N*m (t = 0) and the pivot's vertical reaction
at 19.81 N (closed form, statics of the crank). Shown in kN and N*mm they must read
0.01981 kN and 1490.5 N*mm, the abscissa (angle) 0.5 rad as 28.648 deg.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import openpyxl
import pytest
from typer.testing import CliRunner

from cli.app import app
from tests.loadcases.set_fixtures import write_inputs

runner = CliRunner()
UNITS = "{force: kN, torque: N*mm, angle: deg, length: mm}"


def _run(folder: Path, units: str) -> tuple[int, str]:
    (folder / "u.set.yaml").write_text(
        "set: u\ncases: [crank.case.yaml]\nparameters: {speed: 1.0, load: 10}\n"
        f"report: {{output: u.xlsx, units: {units}}}\n",
        encoding="utf-8",
    )
    result = runner.invoke(
        app, ["run", str(folder / "u.set.yaml"), "-o", str(folder / "out"), "--jobs", "1"]
    )
    return result.exit_code, result.output


def test_workbook_shows_the_report_units_and_the_csv_stays_si(tmp_path: Path) -> None:
    folder = write_inputs(tmp_path)
    code, output = _run(folder, UNITS)
    assert code == 0, output
    out = folder / "out" / "u"
    with open(out / "envelope.csv", newline="") as handle:
        si = {row["column"]: row for row in csv.DictReader(handle)}
    torque = 0.1 * 10 + 1.0 * 9.81 * 0.05
    assert float(si["drive_torque.value"]["max"]) == pytest.approx(torque, rel=1e-9)
    assert si["drive_torque.value"]["unit"] == "N*m"
    book = openpyxl.load_workbook(out / "u.xlsx")
    sheet = book["Envelope"]
    header = [c.value for c in sheet[1]]
    rows = {r[0].value: dict(zip(header, (c.value for c in r))) for r in sheet.iter_rows(2)}
    assert rows["drive_torque.value"]["unit"] == "N*mm"
    assert rows["drive_torque.value"]["max"] == pytest.approx(torque * 1e3, rel=1e-9)
    assert rows["pivot_force.fy"]["unit"] == "kN"
    assert rows["pivot_force.fy"]["max"] == pytest.approx(
        float(si["pivot_force.fy"]["max"]) / 1e3, rel=1e-12
    )
    assert rows["pivot_force.fy"]["max"] == pytest.approx(19.81e-3, rel=1e-6)
    assert "abscissa.value" not in rows  # the x axis, not a load row
    curves = book["Curves crank-turn"]  # named by its expression, in the report's unit
    assert curves["A1"].value == "angle(pivot) [deg]"
    assert max(c.value for c in curves["A"][1:]) == pytest.approx(math.degrees(0.5), rel=1e-9)
    assert rows["pivot_force.fy"]["max_abscissa"] == pytest.approx(
        math.degrees(float(si["pivot_force.fy"]["max_abscissa"])), rel=1e-9
    )
    # concurrent components in their report units too
    concurrent = rows["pivot_force.fy"]["max_concurrent"]
    fx_si = float(
        dict(p.split("=") for p in si["pivot_force.fy"]["max_concurrent"].split("; "))["fx"]
    )
    assert f"fx={fx_si / 1e3:g}" in concurrent
    # the time history headers name the units shown
    history = next(book[n] for n in book.sheetnames if n.startswith("crank-turn"))
    headers = [c.value for c in history[1]]
    assert "drive_torque.value [N*mm]" in headers and "pivot_force.fy [kN]" in headers
    assert any(
        v == "report units" for row in book["Provenance"].iter_rows(values_only=True) for v in row
    )


@pytest.mark.parametrize(
    "units, message",
    [
        ("{force: mm}", "report.units.force: 'mm' is not a unit of force"),
        ("{forse: kN}", "report.units.forse"),
    ],
)
def test_bad_report_units_are_input_errors_at_their_key(
    tmp_path: Path, units: str, message: str
) -> None:
    folder = write_inputs(tmp_path)
    code, output = _run(folder, units)
    assert code == 2, output
    assert "u.set.yaml:4:" in output and message in output
