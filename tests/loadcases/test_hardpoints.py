"""Hardpoint tables (`points: {from: hardpoints.csv}`, issue 16 item 7): points read from a
CAD-style CSV give the same numbers as the same points inline; every bad table is an input
error naming the CSV file, line and column (exit 2 from `loads validate` and `loads run`).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cli.app import app
from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.hardpoints import split_cells
from loadcases.inputs.loader import load_case, load_mechanism
from loadcases.run import run_case

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "examples"
INLINE_POINTS = """\
points:
  crank_pin: {body: crank, at: [100, 0, 0]}
  slider_c:  {body: slider, at: [400, 0, 0]}
"""
TABLE = """\
name,body,x,y,z,units
crank_pin,crank,100,0,0,mm
slider_c,slider,400,0,0,
"""
runner = CliRunner()


def _press(folder: Path, points: str, table: str | None = TABLE) -> Path:
    """The crank press of the examples with its `points:` section replaced; the case file."""
    mech = (LIBRARY / "press.mech.yaml").read_text()
    assert INLINE_POINTS in mech
    (folder / "press.mech.yaml").write_text(mech.replace(INLINE_POINTS, points))
    shutil.copy(LIBRARY / "press_stroke.case.yaml", folder / "press_stroke.case.yaml")
    if table is not None:
        (folder / "hardpoints.csv").write_text(table)
    return folder / "press_stroke.case.yaml"


def _errors(case: Path) -> list[str]:
    with pytest.raises(InputError) as caught:
        load_case(case)
    return [d.format() for d in caught.value.diagnostics if d.severity == "error"]


def test_table_points_give_the_same_results_as_inline_points(tmp_path: Path) -> None:
    """Bit-for-bit equal channels: the table's cells are converted exactly as bare numbers
    under the file's `units: {length: mm}` (an empty units cell takes that unit)."""
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    inline = _press(tmp_path / "a", INLINE_POINTS)
    table = _press(tmp_path / "b", "points: {from: hardpoints.csv}\n")
    a, b = load_case(inline), load_case(table)
    assert a.mechanism.points == b.mechanism.points
    assert a.input_sha256 != b.input_sha256
    first, second = run_case(a).solution, run_case(b).solution
    assert first.status == second.status == "ok"
    assert set(first.channels) == set(second.channels)
    for name, values in first.channels.items():
        np.testing.assert_array_equal(values, second.channels[name], err_msg=name)


def test_units_column_and_mixed_inline_points(tmp_path: Path) -> None:
    """A row in inches (15.748 in = 0.4 m to 1e-12) beside an inline point."""
    case = _press(
        tmp_path,
        "points:\n  from: hardpoints.csv\n  crank_pin: {body: crank, at: [100, 0, 0]}\n",
        "Name, Body, X, Y, Z, Units, Comment\n"
        '"slider_c", slider, 15.748031496062993, 0, 0, in, "from CAD, rev B"\n',
    )
    cf = load_case(case)
    assert cf.mechanism.points["slider_c"].at == pytest.approx((0.4, 0, 0), abs=1e-12)
    assert cf.mechanism.points["crank_pin"].at == pytest.approx((0.1, 0, 0), abs=1e-15)
    assert any("unknown column 'Comment' (ignored)" in d.message for d in cf.warnings)


def test_a_changed_table_changes_the_input_hash(tmp_path: Path) -> None:
    case = _press(tmp_path, "points: {from: hardpoints.csv}\n")
    before = load_case(case).input_sha256
    (tmp_path / "hardpoints.csv").write_text(TABLE.replace("400,0,0", "401,0,0"))
    assert load_case(case).input_sha256 != before
    mech_before = load_mechanism(tmp_path / "press.mech.yaml").input_sha256
    (tmp_path / "hardpoints.csv").write_text(TABLE)
    assert load_mechanism(tmp_path / "press.mech.yaml").input_sha256 != mech_before


@pytest.mark.parametrize(
    ("table", "expected"),
    [
        (
            "name,body,x,y,z\ncrank_pin,crank,100,0,0\n",
            "hardpoints.csv:1:1: error: header: missing column units",
        ),
        (
            TABLE + "pin2,crnk,1,2,3,mm\n",
            "hardpoints.csv:4:6: error: body: unknown body 'crnk'",
        ),
        (
            TABLE + "pin2,crank,1,two,3,mm\n",
            "hardpoints.csv:4:14: error: y: expected a number, got 'two'",
        ),
        (
            TABLE + "pin2,crank,1,2,nan,mm\n",
            "hardpoints.csv:4:16: error: z: expected a finite number, got 'nan'",
        ),
        (
            TABLE + "pin2,crank,1,2,inf,mm\n",
            "hardpoints.csv:4:16: error: z: expected a finite number, got 'inf'",
        ),
        (
            TABLE + "pin2,crank,1,2,3,zork\n",
            "hardpoints.csv:4:18: error: units: unknown unit 'zork'",
        ),
        (
            TABLE + "pin2,crank,1,2,3,kg\n",
            "hardpoints.csv:4:18: error: units: 'kg' is not a unit of length",
        ),
        (
            TABLE + "pin2,crank,1,2,3,mm*1e3\n",
            "hardpoints.csv:4:18: error: units: unknown unit 'mm*1e3'",
        ),
        (
            TABLE + "crank_pin,crank,1,2,3,mm\n",
            "hardpoints.csv:4:1: error: name: point 'crank_pin' given twice (first on line 2)",
        ),
        (
            TABLE + "pin2,crank,1\n",
            "hardpoints.csv:4:1: error: expected 6 cells, got 3",
        ),
        (  # issue 39: names shown as written
            TABLE + "pin\u202e2,crank,1,2,3,mm\n",
            "hardpoints.csv:4:1: error: name: the point name holds a right-to-left override "
            "(U+202E), a character not shown as written",
        ),
        ("", "hardpoints.csv:1:1: error: header: empty file"),
    ],
)
def test_bad_tables_name_file_line_and_column(tmp_path: Path, table: str, expected: str) -> None:
    case = _press(tmp_path, "points: {from: hardpoints.csv}\n", table)
    errors = _errors(case)
    assert any(error.startswith(str(tmp_path / expected)) for error in errors), errors


def test_point_both_inline_and_in_the_table(tmp_path: Path) -> None:
    case = _press(
        tmp_path,
        "points:\n  from: hardpoints.csv\n  slider_c: {body: slider, at: [400, 0, 0]}\n",
    )
    errors = _errors(case)
    expected = (
        f"{tmp_path / 'hardpoints.csv'}:3:1: error: name: point 'slider_c' is also given "
        "inline (press.mech.yaml line 21)"
    )
    assert any(e.startswith(expected) for e in errors), errors


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("missing.csv", "hardpoint file not found"),
        ("../hardpoints.csv", "'../hardpoints.csv' leaves the folder of the file that holds"),
        ("/etc/passwd", "'/etc/passwd' leaves the folder"),
        ("link.csv", "(a link leads out)"),
        ("[1, 2]", "expected the name of a CSV file"),
    ],
)
def test_table_path_stays_in_the_folder_tree(tmp_path: Path, source: str, expected: str) -> None:
    """Missing, outside (absolute, `..`, a symbolic link out) or not a file name: the error
    is at `points.from` of the mechanism file (line 19 there)."""
    folder = tmp_path / "project"
    folder.mkdir()
    (tmp_path / "hardpoints.csv").write_text(TABLE)
    (folder / "link.csv").symlink_to(tmp_path / "hardpoints.csv")
    case = _press(folder, f"points: {{from: {source}}}\n", table=None)
    errors = _errors(case)
    head = f"{folder / 'press.mech.yaml'}:19:"
    assert any(e.startswith(head) and "points.from" in e and expected in e for e in errors), errors


def test_inline_mechanism_table_is_relative_to_the_case_file(tmp_path: Path) -> None:
    (tmp_path / "pts.csv").write_text("name,body,x,y,z,units\ntip,bar,0,-1000,0,mm\n")
    (tmp_path / "pend.case.yaml").write_text(
        "case: pend\nmechanism:\n  bodies:\n    bar: {mass: 1, cm: [0, -0.5, 0], "
        "inertia: [0.1, 0.1, 0.1]}\n  points: {from: pts.csv}\n  joints:\n    hinge: "
        "{type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}\n"
        "motions:\n  m: {joint: hinge, value: 't'}\nanalysis: {type: kinematic, end: 0.1, "
        "step: 0.1}\nrequests:\n  tip: {point: tip, quantity: position}\n"
    )
    cf = load_case(tmp_path / "pend.case.yaml")
    assert cf.mechanism.points["tip"].at == pytest.approx((0.0, -1.0, 0.0))


def test_validate_and_run_report_table_errors_with_exit_2(tmp_path: Path) -> None:
    case = _press(tmp_path, "points: {from: hardpoints.csv}\n", TABLE + "pin2,crnk,1,2,3,mm\n")
    expected = f"{tmp_path / 'hardpoints.csv'}:4:6: error: body: unknown body 'crnk'"
    for args in (["validate", str(case)], ["run", str(case), "-o", str(tmp_path / "res")]):
        result = runner.invoke(app, args)
        assert result.exit_code == 2, result.output
        assert expected in result.output
        assert "hint: did you mean 'crank'?" in result.output
    ok = _press(tmp_path, "points: {from: hardpoints.csv}\n")
    assert runner.invoke(app, ["validate", str(tmp_path / "press.mech.yaml")]).exit_code == 0
    assert runner.invoke(app, ["validate", str(ok)]).exit_code == 0


@pytest.mark.parametrize(
    ("line", "cells"),
    [
        ("a,b,c", [(1, "a"), (3, "b"), (5, "c")]),
        (' a , "b, c" ,d', [(2, "a"), (7, "b, c"), (14, "d")]),
        ('"say ""hi""",', [(2, 'say "hi"'), (14, "")]),
        ("", [(1, "")]),
    ],
)
def test_split_cells_columns(line: str, cells: list[tuple[int, str]]) -> None:
    assert split_cells(line) == cells
