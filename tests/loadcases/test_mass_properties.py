"""Mass properties of a set's bodies in a chosen configuration (`mass_properties:`),
against inertias by hand. An arm (2 kg, cm (0.5, 0, 0) m, I = diag(0.01, 0.2, 0.2) kg*m^2)
turns about z through the origin, 90 deg at t = 1 s; a block (1 kg, cm (1, 0, 0) m,
Ixx = Iyy = Izz = 0.1, Ixy = 0.02 kg*m^2) is welded to it. Turned by 90 deg about z
(R = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]): arm cm (0, 0.5, 0), I = diag(0.2, 0.01, 0.2); block
cm (0, 1, 0), Ixx and Iyy swapped, Ixy = -0.02. Assembly: 3 kg, cm (0, 2/3, 0); about it
(parallel axis theorem) Ixx = Izz = 0.2 + 0.1 + 2 (1/6)^2 + 1 (1/3)^2 = 0.3 + 1/6,
Iyy = 0.01 + 0.1, Ixy = -0.02; about z through the origin: 0.2 + 2 x 0.5^2 + 0.1 + 1 x 1^2 =
1.8. Tolerance 1e-9 (the solved positions)."""

from __future__ import annotations

import csv

import openpyxl
import pytest
from set_fixtures import write_inputs

from loadcases.inputs.loader import validate_files
from loadcases.sets.campaign import run_set

MECH = """\
name: arm
gravity: [0, 0, 0]
bodies:
  arm:   {mass: 2.0, cm: [0.5, 0, 0], inertia: [0.01, 0.2, 0.2]}
  block: {mass: 1.0, cm: [1.0, 0, 0], inertia: [0.1, 0.1, 0.1, 0.02, 0, 0]}
joints:
  pivot: {type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 0, 1]}
  weld:  {type: fixed, bodies: [block, arm], at: [1, 0, 0]}
"""
CASE = """\
case: turn
mechanism: arm.mech.yaml
motions:
  drive: {joint: pivot, value: "90*deg * t"}
analysis: {type: kinematic, end: 1.0, step: 0.25}
requests:
  torque: {motion: drive, quantity: torque}
"""
SET = """\
set: arm-mass
cases: [turn.case.yaml]
units: {length: mm}
mass_properties:
  case: {case}
  at: 1 s
  axis: {name: pivot axis, at: [0, 0, 0], direction: [0, 0, 2]}
report: {output: arm.xlsx}
"""

# body: (mass, cm, Ixx Iyy Izz Ixy Ixz Iyz, about the axis), by hand (module doc)
EXPECTED = {
    "arm": (2.0, (0.0, 0.5, 0.0), (0.2, 0.01, 0.2, 0.0, 0.0, 0.0), 0.2 + 2.0 * 0.25),
    "block": (1.0, (0.0, 1.0, 0.0), (0.1, 0.1, 0.1, -0.02, 0.0, 0.0), 0.1 + 1.0),
    "assembly": (
        3.0,
        (0.0, 2.0 / 3.0, 0.0),
        (0.3 + 1.0 / 6.0, 0.11, 0.3 + 1.0 / 6.0, -0.02, 0.0, 0.0),
        1.8,
    ),
}


def _write(folder, case="turn"):
    (folder / "arm.mech.yaml").write_text(MECH, encoding="utf-8")
    (folder / "turn.case.yaml").write_text(CASE, encoding="utf-8")
    (folder / "arm.set.yaml").write_text(SET.replace("{case}", case), encoding="utf-8")
    return folder / "arm.set.yaml"


def test_mass_properties_against_hand_inertias(tmp_path):
    run_set(_write(tmp_path), output_dir=tmp_path / "out")
    folder = tmp_path / "out" / "arm-mass"
    lines = (folder / "mass-properties.csv").read_text(encoding="utf-8").splitlines()
    rows = {row["body"]: row for row in csv.DictReader(lines)}
    assert rows["arm"]["configuration"].startswith("run turn at t = 1 s")
    for body, (mass, cm, inertia, about) in EXPECTED.items():
        row = rows[body]
        assert float(row["mass [kg]"]) == pytest.approx(mass, abs=1e-12)
        for axis, value in zip("xyz", cm):
            assert float(row[f"cm {axis} [m]"]) == pytest.approx(value, abs=1e-9)
        for name, value in zip(("Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz"), inertia):
            assert float(row[f"{name} [kg*m^2]"]) == pytest.approx(value, abs=1e-9), (body, name)
        assert float(row["I about pivot axis [kg*m^2]"]) == pytest.approx(about, abs=1e-9)
    sheet = openpyxl.load_workbook(folder / "arm.xlsx")["Mass properties"]
    assert sheet.cell(row=2, column=7).value == "Iyy [kg*m^2]"
    assert sheet.cell(row=5, column=1).value == "assembly"
    assert sheet.cell(row=5, column=12).value == pytest.approx(1.8, abs=1e-9)
    # each column with 4 significant digits of its largest magnitude (report.digits)
    assert sheet.cell(row=5, column=2).number_format == "0.000"  # 3 kg
    assert sheet.cell(row=3, column=12).number_format == "0.000"  # up to 1.8 kg*m^2


def test_unknown_case_and_zero_axis_are_input_errors(tmp_path):
    path = _write(tmp_path, case="tunr")
    messages = [d.format() for d in validate_files([path]) if d.severity == "error"]
    assert any("mass_properties.case: unknown case 'tunr'" in m for m in messages), messages
    path.write_text(SET.replace("{case}", "turn").replace("[0, 0, 2]", "[0, 0, 0]"))
    messages = [d.format() for d in validate_files([path]) if d.severity == "error"]
    assert any("direction must not be zero" in m for m in messages), messages


def test_case_failing_before_the_time_gives_no_rows_and_says_why(tmp_path):
    """The slider of set_fixtures pushed out of its crank's reach (stroke 0.2 m/s: the solve
    fails before 1 s): the table is empty, its configuration says why, the set ends with
    its failed run (exit 1, no traceback)."""
    write_inputs(tmp_path)
    text = (
        "set: slider-mass\ncases: [slider.case.yaml]\nparameters: {stroke: 0.2}\n"
        "mass_properties: {case: slider-push, at: 1 s}\nreport: {output: s.xlsx}\n"
    )
    (tmp_path / "m.set.yaml").write_text(text, encoding="utf-8")
    result = run_set(tmp_path / "m.set.yaml", output_dir=tmp_path / "out")
    assert [r.status for r in result.records] == ["failed"]
    lines = (tmp_path / "out" / "slider-mass" / "mass-properties.csv").read_text().splitlines()
    assert len(lines) == 1  # the header only
    sheet = openpyxl.load_workbook(tmp_path / "out" / "slider-mass" / "s.xlsx")["Mass properties"]
    assert sheet.cell(row=1, column=1).value.startswith("not computed: slider-push did not reach")
