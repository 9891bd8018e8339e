"""`loads compare OLD NEW`: two set results compared row by row (issue 16 item 6, SPEC 2).

The crank of tests/loadcases/set_fixtures.py turns at 1 rad/s for 0.5 s holding a vertical
load P at its 0.1 m tip; its drive torque is (0.1 P + m g 0.05) cos(angle) (closed form,
statics of the crank: no angular acceleration), largest at t = 0: 1.4905 N*m for P = 10 N
and 2.4905 N*m for P = 20 N, so the comparison must show +1 N*m, i.e. +1/1.4905 = +67.09 %
of the old magnitude.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import openpyxl
import pytest
from typer.testing import CliRunner

from cli.app import app
from loadcases.report.compare import Peak, compare_envelopes
from tests.loadcases.set_fixtures import write_inputs

runner = CliRunner()
G = 9.81


def _set_result(folder: Path, load: float, out: Path) -> Path:
    (folder / "one.set.yaml").write_text(
        f"set: one\ncases: [crank.case.yaml]\nparameters: {{speed: 1.0, load: {load}}}\n",
        encoding="utf-8",
    )
    result = runner.invoke(
        app, ["run", str(folder / "one.set.yaml"), "-o", str(out), "--jobs", "1"]
    )
    assert result.exit_code == 0, result.output
    return out / "one"


@pytest.fixture(scope="module")
def two_results(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    folder = write_inputs(tmp_path_factory.mktemp("inputs"))
    return (
        _set_result(folder, 10.0, tmp_path_factory.mktemp("old")),
        _set_result(folder, 20.0, tmp_path_factory.mktemp("new")),
    )


def _rows(path: Path) -> dict[str, dict[str, str]]:
    with open(path, newline="", encoding="utf-8") as handle:
        return {row["column"]: row for row in csv.DictReader(handle)}


def test_compare_two_set_results_against_the_closed_form(two_results, tmp_path: Path) -> None:
    old, new = two_results
    out = tmp_path / "cmp.csv"
    result = runner.invoke(app, ["compare", str(old), str(new), "-o", str(out)])
    assert result.exit_code == 0, result.output
    row = _rows(out)["drive_torque.value"]
    torque_old, torque_new = 0.1 * 10 + 1.0 * G * 0.05, 0.1 * 20 + 1.0 * G * 0.05
    assert float(row["old_max"]) == pytest.approx(torque_old, rel=1e-9)
    assert float(row["new_max"]) == pytest.approx(torque_new, rel=1e-9)
    assert float(row["max_diff"]) == pytest.approx(1.0, rel=1e-9)
    assert float(row["max_change"]) == pytest.approx(1.0 / torque_old, rel=1e-9)
    # the smallest torque is at the end, angle 0.5 rad: it moves by 1 N*m * cos(0.5)
    assert float(row["min_diff"]) == pytest.approx(math.cos(0.5), rel=1e-9)
    assert row["status"] == "changed"
    assert row["old_max_run"] == row["new_max_run"] == "crank-turn"
    # the console: the header, the row with its percentage, a count line
    lines = result.stdout.splitlines()
    torque_line = next(line for line in lines if line.startswith("drive_torque.value"))
    assert torque_line.split()[:5] == ["drive_torque.value", "N*m", "1.4905", "2.4905", "+67.09%"]
    # round-off components (1e-37 N*m beside 1.5 N*m) are not changes
    assert lines[-2] == "5 changed, 0 new, 0 vanished, 5 same of 10 rows"
    assert _rows(out)["pivot_force.tx"]["status"] == "same"


def test_compare_reads_envelope_csvs_and_writes_a_workbook(two_results, tmp_path: Path) -> None:
    old, new = two_results
    out = tmp_path / "cmp.xlsx"
    result = runner.invoke(
        app, ["compare", str(old / "envelope.csv"), str(new / "envelope.csv"), "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    sheet = openpyxl.load_workbook(out)["Compare"]
    header = [c.value for c in sheet[1]]
    values = {r[0].value: dict(zip(header, (c.value for c in r))) for r in sheet.iter_rows(2)}
    assert values["drive_torque.value"]["max_diff"] == pytest.approx(1.0, rel=1e-9)
    run_cell = next(c for c in sheet[2] if header[c.column - 1] == "old_max_run")
    assert run_cell.data_type == "s"


def test_new_vanished_and_unchanged_rows() -> None:
    """Hand-made envelopes: a column only in NEW is `new`, only in OLD `vanished`, equal
    peaks `same`; a column zero in OLD has a difference but no relative change."""
    old = {
        "a": Peak(2.0, "r1", -1.0, "r1"),
        "b": Peak(1.0, "r1", 0.0, "r1"),
        "z": Peak(0.0, "r1", 0.0, "r1"),
        "gone": Peak(5.0, "r1", 1.0, "r1"),
    }
    new = {
        "a": Peak(3.0, "r2", -1.0, "r1"),
        "b": Peak(1.0, "r1", 0.0, "r1"),
        "z": Peak(0.5, "r1", 0.0, "r1"),
        "fresh": Peak(1.0, "r1", 0.0, "r1"),
    }
    rows = {r.column: r for r in compare_envelopes(old, new)}
    assert [r.column for r in compare_envelopes(old, new)] == ["a", "z", "fresh", "gone", "b"]
    assert rows["a"].max_change == pytest.approx(0.5) and rows["a"].status == "changed"
    assert rows["z"].status == "changed" and rows["z"].max_change is None
    assert rows["z"].max_diff == pytest.approx(0.5)
    assert (rows["fresh"].status, rows["gone"].status, rows["b"].status) == (
        "new",
        "vanished",
        "same",
    )


def test_compare_of_a_folder_without_results_is_an_input_error(tmp_path: Path) -> None:
    result = runner.invoke(app, ["compare", str(tmp_path), str(tmp_path)])
    assert result.exit_code == 2
    assert "no envelope.csv and no saved results" in result.output


def test_version() -> None:
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0
    assert result.stdout.startswith("loads ") and result.stdout.split()[1][0].isdigit()


def test_changes_rank_against_the_request_peak_and_round_off_is_noise() -> None:
    """A 3e-13 -> 5e-13 N*m moment beside a 5 kN*m torque (+67 % of itself) is `noise`,
    listed after the real changes; a 100 N change of a joint's fx carrying 100 kN is 1e-3
    of its request's peak, whatever fx was, and ranks below a 10 % torque change."""
    old = {
        "hinge.fx": Peak(1.0e3, "r", -1.0e3, "r", "N"),
        "hinge.fy": Peak(1.0e5, "r", 0.0, "r", "N"),
        "hinge.tx": Peak(3e-13, "r", 0.0, "r", "N*m"),
        "drive.value": Peak(5.0e3, "r", -5.0e3, "r", "N*m"),
    }
    new = {
        "hinge.fx": Peak(1.1e3, "r", -1.0e3, "r", "N"),
        "hinge.fy": Peak(1.0e5, "r", 0.0, "r", "N"),
        "hinge.tx": Peak(5e-13, "r", 0.0, "r", "N*m"),
        "drive.value": Peak(5.5e3, "r", -5.0e3, "r", "N*m"),
    }
    rows = compare_envelopes(old, new)
    assert [(r.column, r.status) for r in rows] == [
        ("drive.value", "changed"),
        ("hinge.fx", "changed"),
        ("hinge.tx", "noise"),
        ("hinge.fy", "same"),
    ]
    assert rows[0].max_change == pytest.approx(0.1, rel=1e-12)
    assert rows[1].max_change == pytest.approx(100.0 / 1.0e5, rel=1e-12)
    # round-off that becomes a load is a change
    grown = {**new, "hinge.tx": Peak(50.0, "r", 0.0, "r", "N*m")}
    assert {r.column: r.status for r in compare_envelopes(old, grown)}["hinge.tx"] == "changed"


def test_compare_shows_report_units(two_results, tmp_path: Path) -> None:
    """--units torque=N*mm: the console and the workbook in N*mm (x 1e3), percentages
    unchanged, the CSV in SI."""
    old, new = two_results
    args = ["compare", str(old), str(new), "--units", "torque=N*mm"]
    result = runner.invoke(app, [*args, "-o", str(tmp_path / "c.xlsx")])
    assert result.exit_code == 0, result.output
    line = next(x for x in result.stdout.splitlines() if x.startswith("drive_torque.value"))
    assert line.split()[:5] == ["drive_torque.value", "N*mm", "1490.5", "2490.5", "+67.09%"]
    sheet = openpyxl.load_workbook(tmp_path / "c.xlsx")["Compare"]
    header = [c.value for c in sheet[1]]
    values = {r[0].value: dict(zip(header, (c.value for c in r))) for r in sheet.iter_rows(2)}
    assert values["drive_torque.value"]["unit"] == "N*mm"
    assert values["drive_torque.value"]["max_diff"] == pytest.approx(1000.0, rel=1e-9)
    torque_row = next(r for r in sheet.iter_rows(2) if r[0].value == "drive_torque.value")
    formats = {header[c.column - 1]: c.number_format for c in torque_row}
    assert (formats["new_max"], formats["max_change"]) == ("0", "0.00%")  # 2490.5 N*mm
    runner.invoke(app, [*args, "-o", str(tmp_path / "c.csv")])
    assert _rows(tmp_path / "c.csv")["drive_torque.value"]["unit"] == "N*m"
    bad = runner.invoke(app, ["compare", str(old), str(new), "--units", "torque=mm"])
    assert bad.exit_code == 2 and "--units 'torque=mm'" in bad.output
