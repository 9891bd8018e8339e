"""Reference curves of a set (`curves:`): a CSV with units in its header read against a
case's abscissa, compared run by run, tabulated, overlaid. Reference: the crank of
set_fixtures turned at constant speed (kinematic, no angular acceleration) needs the drive
torque (0.1 m x load + 0.05 m x 1 kg x 9.81 m/s^2) cos(angle) (statics by hand); the run is
interpolated linearly between its rows 0.05 rad apart, so it can differ from the closed form
by at most h^2/8 x max|torque''| = 0.05^2 / 8 x 1.4905 = 4.7e-4 N*m."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from set_fixtures import write_inputs

from loadcases.inputs.loader import validate_files
from loadcases.inputs.reference_tables import read_reference_table
from loadcases.report.number_format import number_format
from loadcases.report.reference_curves import DIFFERENCE_COLUMNS, difference, overlays
from loadcases.report.reference_sheet import DATA_COLUMN
from loadcases.results.saved import SavedRun
from loadcases.schema.setfile import ReferenceCurve
from loadcases.sets.campaign import run_set

PEAK = 0.1 * 10.0 + 0.05 * 9.81  # N*m: drive torque at angle 0 (speed 1, load 10 N)


def _reference(folder: Path, scale: float = 1.0, name: str = "hand.csv") -> None:
    lines = ["crank angle [deg], drive torque [N*mm]"]
    for deg in range(0, 29, 2):  # the run covers 0 .. 0.5 rad = 28.6 deg
        lines.append(f"{deg}, {1000.0 * scale * PEAK * math.cos(math.radians(deg)):.12g}")
    (folder / name).write_text("\n".join(lines) + "\n", encoding="utf-8")


def _set(folder: Path, curve: str) -> Path:
    text = (
        "set: crank-ref\ncases: [crank.case.yaml]\n"
        f"curves:\n  hand:\n{curve}\nreport: {{output: crank.xlsx}}\n"
    )
    (folder / "ref.set.yaml").write_text(text, encoding="utf-8")
    return folder / "ref.set.yaml"


GOOD = (
    "    file: hand.csv\n    case: crank-turn\n    x: angle(pivot)\n"
    '    columns: {drive_torque.value: "drive torque [N*mm]"}'
)


def test_difference_by_hand():
    """Run y = 2x on [0, 1]; reference (0, 0), (0.5, 0.9), (1, 2.2), (1.5, 3) (outside)."""
    x = np.linspace(0.0, 1.0, 11)
    points, worst, at, of_peak, relative, rel_at = difference(
        x, 2.0 * x, np.array([0.0, 0.5, 1.0, 1.5]), np.array([0.0, 0.9, 2.2, 3.0])
    )
    assert (points, at, rel_at) == (3, 1.0, 0.5)
    assert worst == pytest.approx(-0.2, abs=1e-12)
    assert of_peak == pytest.approx(-0.2 / 2.2, rel=1e-12)
    assert relative == pytest.approx(0.1 / 0.9, rel=1e-12)  # the zero point is not counted


def test_set_overlays_reference_against_closed_form(tmp_path):
    write_inputs(tmp_path)
    _reference(tmp_path)
    _reference(tmp_path, scale=1.1, name="high.csv")
    curve = GOOD + "\n  high:\n" + GOOD.replace("hand.csv", "high.csv")
    result = run_set(_set(tmp_path, curve), output_dir=tmp_path / "out")
    folder = tmp_path / "out" / "crank-ref"
    text = (folder / "reference-curves.csv").read_text(encoding="utf-8")
    rows = list(csv.DictReader(text.splitlines()))
    hand, high = rows
    assert (hand["curve"], hand["unit"], hand["note"]) == ("hand", "N*m", "")
    assert int(hand["points"]) == 15
    assert abs(float(hand["max_difference"])) < 4.7e-4  # interpolation bound (module doc)
    # a reference 10 % high: run - reference = -0.1 x reference, largest at angle 0
    assert float(high["of_peak"]) == pytest.approx(-0.1 / 1.1, abs=5e-4)
    assert float(high["at"]) <= math.radians(4.0)  # cos ~ 1 there: interpolation decides
    assert float(high["max_relative"]) == pytest.approx(0.1 / 1.1, abs=5e-4)
    assert (folder / "reference-hand-drive_torque.value.png").stat().st_size > 1000
    sheet = openpyxl.load_workbook(folder / "crank.xlsx")["Reference curves"]
    assert sheet.cell(row=2, column=1).value == "hand" and len(sheet._charts) == 2
    # report.digits (4) significant digits, as the other sheets: -0.09091 reads -0.09091
    of_peak = sheet.cell(row=3, column=DIFFERENCE_COLUMNS.index("of_peak") + 1)
    assert of_peak.number_format == number_format((of_peak.value,)) == "0.00000"
    torque = sheet.cell(row=7, column=DATA_COLUMN + 1)  # the run's first charted row
    assert torque.value == pytest.approx(PEAK, rel=1e-9) and torque.number_format == "0.000"
    assert result.files and folder / "reference-curves.csv" in result.files


def _messages(path: Path) -> list[str]:
    return [d.format() for d in validate_files([path]) if d.severity == "error"]


@pytest.mark.parametrize(
    ("curve", "expected"),
    [
        (GOOD.replace("crank-turn", "crank-tur"), "curves.hand.case: no case 'crank-tur'"),
        (GOOD.replace("angle(pivot)", "time"), "has the abscissa 'angle(pivot)', not 'time'"),
        (GOOD.replace('"drive torque [N*mm]"', '"torque [N*mm]"'), "no column 'torque [N*mm]'"),
        (GOOD.replace("drive_torque.value", "drive_torq.value"), "no request 'drive_torq'"),
        (GOOD.replace("hand.csv", "../hand.csv"), "leaves the folder of the set file"),
        (GOOD.replace("hand.csv", "none.csv"), "reference file not found"),
    ],
)
def test_bad_curves_are_named_by_key(tmp_path, curve, expected):
    write_inputs(tmp_path)
    _reference(tmp_path)
    messages = _messages(_set(tmp_path, curve))
    assert any(expected in m and "ref.set.yaml:" in m for m in messages), messages


def test_bad_reference_file_named_by_line_and_column(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("angle [deg], torque\n0, 1\n", encoding="utf-8")
    (problem,) = read_reference_table(path).problems
    assert (problem.line, problem.column) == (1, 14) and "has no unit" in problem.message
    path.write_text("angle [deg], torque [N*m]\n0, 1\n5, 1e400\n3, 2\n", encoding="utf-8")
    problems = read_reference_table(path).problems
    assert [(p.line, p.column) for p in problems] == [(3, 4), (1, 1)]
    assert "finite number" in problems[0].message and "increasing" in problems[1].message
    path.write_text("angle [deg], torque [splonk]\n0, 1\n1, 2\n", encoding="utf-8")
    assert "unit of 'torque [splonk]'" in read_reference_table(path).problems[0].message


def test_reference_in_another_dimension_is_not_compared(tmp_path):
    """A header in m against a column in N: a note, no numbers (and no error after a run)."""
    (tmp_path / "m.csv").write_text("angle [deg], f [m]\n0, 1\n10, 2\n", encoding="utf-8")
    table = read_reference_table(tmp_path / "m.csv")
    run = SavedRun(
        "r",
        np.array([0.0, 1.0]),
        {"abscissa.value": np.radians([0.0, 10.0]), "rod.f": np.array([1.0, 2.0])},
        {"rod.f": "N", "abscissa.value": "rad"},
    )
    curve = ReferenceCurve(file="m.csv", case="r", columns={"rod.f": "f [m]"})
    (overlay,) = overlays({"c": curve}, {"c": table}, [run], {})
    assert overlay.difference.note == "'f [m]' is not in a unit of the run's N"
    assert overlay.difference.max_difference is None
    curve = ReferenceCurve(file="m.csv", case="r", columns={"rod.f": "f [m]"})
    run.units["rod.f"] = "m"
    (overlay,) = overlays({"c": curve}, {"c": table}, [run], {})
    assert overlay.difference.points == 2
    assert overlay.difference.max_difference == pytest.approx(0.0, abs=1e-15)


def test_good_reference_reads_in_si(tmp_path):
    _reference(tmp_path)
    table = read_reference_table(tmp_path / "hand.csv")
    assert not table.problems
    assert table.x[1] == pytest.approx(math.radians(2.0), rel=1e-15)
    assert table.columns["drive torque [N*mm]"][0] == pytest.approx(PEAK, rel=1e-12)
