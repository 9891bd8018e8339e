"""A report that is right (issue 36 items 3-4): every column with a unit in the report
units, engineering number formats, the allowables stated, charts of the loads, run names as
the set wrote them.

Reference (closed form, statics of the crank of set_fixtures.py with pin friction): the crank
(m = 1 kg, centre of mass at 0.05 m) turns at 1 rad/s holding P at its 0.1 m tip; pin
friction mu = 0.2 on a 0.01 m pin. At t = 0 the pin carries fy = P + m g and the centripetal
fx = -m omega^2 0.05 = -0.05 N, so the friction torque is mu r |F| and the drive torque
0.1 P + m g 0.05 + mu r |F|: for P = 20 N, |F| = 29.810042 N, friction 0.0596201 N*m, drive
2.5501201 N*m. Shown in N*mm, kN and mJ they are the SI values x 1e3, / 1e3 and x 1e3.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from typer.testing import CliRunner

from cli.app import app
from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.run_identity import value_label
from loadcases.report.curves import envelope_curves, main_columns
from loadcases.report.number_format import number_format
from loadcases.results.saved import SavedRun
from loadcases.sets.specs import load_and_compile_set

runner = CliRunner()
G, MASS, MU, PIN = 9.81, 1.0, 0.2, 0.01
MECH = f"""\
name: crank
gravity: [0, -{G}, 0]
parameters: {{speed: 1.0, load: 10.0}}
bodies:
  crank: {{mass: {MASS}, cm: [0.05, 0, 0], inertia: [0.0001, 0.001, 0.001]}}
points:
  tip: {{body: crank, at: [0.1, 0, 0]}}
joints:
  pivot: {{type: revolute, bodies: [crank, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
forces:
  push: {{type: force, point: tip, value: [0, "-load", 0], frame: ground}}
  rub: {{type: joint_friction, joint: pivot, mu: {MU}, pin_radius: {PIN}}}
"""
CASE = """\
case: crank-turn
mechanism: crank.mech.yaml
motions:
  drive: {joint: pivot, value: "speed * t"}
analysis: {type: kinematic, end: 0.5, step: 0.05}
requests:
  pivot_force: {joint: pivot, quantity: force, frame: ground}
  drive_torque: {motion: drive, quantity: torque}
  rub: {force: rub, quantity: force}
  energy: {quantity: energy}
abscissa: "angle(pivot)"
"""
SET = """\
set: u
cases: [crank.case.yaml]
sweep: {load: ["10 N", "20 N"]}
factors: {ultimate: 1.5}
allowables:
  drive_torque.value: {ultimate: {max: 2.5 N*m, min: -2.5 N*m}, limit: {max: 2 N*m, min: -1.5 N*m}}
  pivot_force.fy: {max: 100 N}
report: {output: u.xlsx, units: {force: kN, torque: N*mm, angle: deg, energy: mJ}}
"""
NORMAL = math.hypot(20.0 + MASS * G, MASS * 1.0**2 * 0.05)  # N, P = 20 N at t = 0
FRICTION = MU * PIN * NORMAL  # N*m
DRIVE = 0.1 * 20.0 + MASS * G * 0.05 + FRICTION  # N*m


def _write(folder: Path, set_text: str = SET) -> Path:
    for name, text in (
        ("crank.mech.yaml", MECH),
        ("crank.case.yaml", CASE),
        ("u.set.yaml", set_text),
    ):
        (folder / name).write_text(text, encoding="utf-8")
    return folder


@pytest.fixture(scope="module")
def result(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = _write(tmp_path_factory.mktemp("report"))
    run = runner.invoke(
        app, ["run", str(folder / "u.set.yaml"), "-o", str(folder / "out"), "--jobs", "1"]
    )
    assert run.exit_code == 0, run.output
    return folder / "out" / "u"


def _envelope(book: openpyxl.Workbook) -> dict[str, dict[str, openpyxl.cell.Cell]]:
    sheet = book["Envelope"]
    header = [c.value for c in sheet[1]]
    return {r[0].value: dict(zip(header, r)) for r in sheet.iter_rows(2)}


def test_friction_and_energy_columns_show_their_unit_in_report_units(result: Path) -> None:
    with open(result / "envelope.csv", newline="") as handle:
        si = {row["column"]: row for row in csv.DictReader(handle)}
    assert (si["rub.value"]["unit"], si["rub.normal"]["unit"]) == ("N*m", "N")
    assert float(si["rub.value"]["max"]) == pytest.approx(FRICTION, rel=1e-9)
    assert float(si["rub.normal"]["max"]) == pytest.approx(NORMAL, rel=1e-9)
    assert float(si["drive_torque.value"]["max"]) == pytest.approx(DRIVE, rel=1e-9)
    rows = _envelope(openpyxl.load_workbook(result / "u.xlsx"))
    shown = {c: (rows[c]["unit"].value, rows[c]["max"].value) for c in rows}
    assert shown["rub.value"] == ("N*mm", pytest.approx(FRICTION * 1e3, rel=1e-9))
    assert shown["rub.capacity"][0] == "N*mm"
    assert shown["rub.normal"] == ("kN", pytest.approx(NORMAL / 1e3, rel=1e-9))
    assert all(unit == "mJ" for c, (unit, _) in shown.items() if c.startswith("energy."))
    drive_work = float(si["energy.drive_work"]["max"])
    assert shown["energy.drive_work"][1] == pytest.approx(drive_work * 1e3, rel=1e-12)
    assert all(unit not in (None, "", "-") for unit, _ in shown.values())


def test_workbook_numbers_show_four_significant_digits_in_the_report_unit(result: Path) -> None:
    rows = _envelope(openpyxl.load_workbook(result / "u.xlsx"))
    assert rows["drive_torque.value"]["max"].number_format == "0"  # 2550 N*mm
    assert rows["drive_torque.value"]["ultimate_max"].number_format == "0"
    assert rows["pivot_force.fy"]["max"].number_format == "0.00000"  # 0.02981 kN
    assert rows["rub.value"]["max"].number_format == "0.00"  # 59.62 N*mm
    assert rows["drive_torque.value"]["max_abscissa"].number_format == "0.00"  # 28.65 deg
    for row in rows.values():
        value = row["max"].value
        if value and 1e-3 <= abs(value) < 1e7:
            assert "E" not in row["max"].number_format, row["column"].value
    book = openpyxl.load_workbook(result / "u.xlsx")
    history = book["crank-turn(20N)"]  # its time histories: time in full, loads in 4 digits
    second = {c.value: cell for c, cell in zip(history[1], history[2])}
    assert second["time [s]"].number_format == "General"
    assert second["drive_torque.value [N*mm]"].number_format == "0"
    assert second["drive_torque.value [N*mm]"].value == pytest.approx(DRIVE * 1e3, rel=1e-9)
    assert second["rub.normal [kN]"].number_format == "0.00000"
    curves = book["Curves crank-turn"]
    assert {c.value: cell.number_format for c, cell in zip(curves[1], curves[2])}[
        "drive_torque.value upper [N*mm]"
    ] == "0"


@pytest.mark.parametrize(
    ("values", "expected"),
    [
        ((128.6,), "0.0"),
        ((-1.286, 0.5), "0.000"),
        ((9.9996,), "0.00"),  # rounds to 10.00
        ((0.0, -0.0), "0"),
        ((1.5e-5,), "0.000E+00"),
        ((3.2e8,), "0.000E+00"),
        ((float("nan"), None), "General"),
    ],
)
def test_number_format_keeps_four_significant_digits(values: tuple, expected: str) -> None:
    assert number_format(values) == expected


def test_provenance_states_every_allowable_given(result: Path) -> None:
    sheet = openpyxl.load_workbook(result / "u.xlsx")["Provenance"]
    items = {row[0]: row[1] for row in sheet.iter_rows(values_only=True)}
    assert items["allowable drive_torque.value"] == (
        "ultimate: max 2500 N*mm, min -2500 N*mm; limit: max 2000 N*mm, min -1500 N*mm"
    )
    assert items["allowable pivot_force.fy"] == "ultimate: max 0.1 kN, min none"
    assert not any("None" in str(value) for value in items.values())


def test_charts_and_envelope_plots_show_the_loads_not_friction_or_energy(result: Path) -> None:
    plotted = sorted(p.name for p in result.glob("envelope-*.png"))
    assert plotted == [
        "envelope-crank-turn-drive_torque.value.png",
        "envelope-crank-turn-pivot_force.f.png",
        "envelope-crank-turn-pivot_force.tz.png",
    ]


def _run(name: str, kinds: dict[str, str]) -> SavedRun:
    time = np.linspace(0.0, 1.0, 5)
    channels = {
        "hinge.fx": 1e5 * time,  # N: the largest force
        "hinge.fy": 2e4 * time,  # N: the same request, not charted twice
        "drive.value": 3e3 * time,  # N*m: the largest torque
        "rub.value": 5e4 * time,  # N*m: friction, larger but not charted unless asked
        "energy.kinetic": 9e6 * time,  # J: has the dimension of N*m, is no load
        "rod.value": 5e2 * time,  # N: a small element force, charted fourth
        "angle.value": time,  # rad
    }
    units = {
        "hinge.fx": "N",
        "hinge.fy": "N",
        "drive.value": "N*m",
        "rub.value": "N*m",
        "energy.kinetic": "J",
        "rod.value": "N",
        "angle.value": "rad",
    }
    return SavedRun(name, time, channels, units, kinds=kinds)


KINDS = {
    "hinge": "reaction",
    "drive": "effort",
    "rub": "friction",
    "energy": "energy",
    "rod": "element",
    "angle": "kinematics",
}


def test_main_columns_rank_each_unit_against_its_largest_one_per_request() -> None:
    (curve,) = envelope_curves([_run("a[x=1]", KINDS), _run("a[x=2]", KINDS)])
    # hinge.fx and drive.value both lead their unit (ratio 1); rod.value is 5e-3 of fx
    assert main_columns(curve) == ["hinge.fx", "drive.value", "rod.value"]
    (asked,) = envelope_curves([_run("a", KINDS)] * 2, asked=["rub", "energy.kinetic"])
    assert main_columns(asked) == [
        "hinge.fx",
        "drive.value",
        "rod.value",
        "rub.value",
        "energy.kinetic",
    ]


def test_an_unknown_request_in_report_charts_is_an_error_at_its_key(tmp_path: Path) -> None:
    text = SET.replace("report: {output: u.xlsx,", "report: {output: u.xlsx, charts: [rubb],")
    folder = _write(tmp_path, text)
    with pytest.raises(InputError) as error:
        load_and_compile_set(folder / "u.set.yaml")
    message = str(error.value)
    assert "u.set.yaml:8:" in message and "report.charts[0]" in message and "'rub'" in message


def test_run_names_keep_the_value_and_unit_the_set_wrote(result: Path) -> None:
    assert (result / "crank-turn[load=20N].csv").is_file()
    cases = openpyxl.load_workbook(result / "u.xlsx")["Cases"]
    assert [r[0] for r in cases.iter_rows(min_row=2, values_only=True)] == [
        "crank-turn[load=10N]",
        "crank-turn[load=20N]",
    ]
    assert value_label("250 kt") == "250kt"
    assert value_label(128.611) == "128.611"
    assert value_label("1e300") == "1e+300"  # a bare number: %g
    assert value_label("360 deg/s") == "360deg_per_s"  # `/` would make a sub-folder


def test_loads_plot_shows_the_set_report_units(
    result: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`loads plot --set SET --units ...`: the values drawn and their labels' units are the
    report's (N*mm from the set, --units angle=rad wins over its deg)."""
    from loadcases.report import plots

    drawn: dict = {}

    def capture(runs: list, columns: object, *, x: str, units: dict, out_dir: Path) -> list:
        drawn.update(runs={name: channels for name, _, channels in runs}, units=units)
        return []

    monkeypatch.setattr(plots, "plot_runs", capture)
    args = ["plot", str(result), "--set", str(result.parents[1] / "u.set.yaml")]
    outcome = runner.invoke(app, [*args, "--units", "angle=rad", "-o", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output
    assert drawn["units"]["drive_torque.value"] == "N*mm"
    assert drawn["units"]["rub.normal"] == "kN" and drawn["units"]["abscissa.value"] == "rad"
    channels = drawn["runs"]["crank-turn[load=20N]"]
    assert channels["drive_torque.value"].max() == pytest.approx(DRIVE * 1e3, rel=1e-9)
    assert channels["abscissa.value"].max() == pytest.approx(0.5, rel=1e-12)


def test_bare_numbers_that_print_alike_are_a_name_clash_at_their_sweep(tmp_path: Path) -> None:
    text = SET.replace('sweep: {load: ["10 N", "20 N"]}', "sweep: {load: [10.0000001, 10.0000002]}")
    folder = _write(tmp_path, text)
    with pytest.raises(InputError) as error:
        load_and_compile_set(folder / "u.set.yaml")
    message = str(error.value)
    assert "u.set.yaml:3:" in message and "both named 'crank-turn[load=10]'" in message
    # the same value written two ways is one run, named as first written
    text = SET.replace('sweep: {load: ["10 N", "20 N"]}', 'sweep: {load: ["10 N", "0.01 kN"]}')
    names = [r.name for r in load_and_compile_set(_write(tmp_path, text) / "u.set.yaml").runs]
    assert names == ["crank-turn[load=10N]"]


def test_report_charts_of_a_set_reaches_the_charted_columns(tmp_path: Path) -> None:
    from loadcases.inputs.loader import load_set
    from loadcases.report.sizing import size_runs

    text = SET.replace("report: {output: u.xlsx,", "report: {output: u.xlsx, charts: [rub],")
    model = load_set(_write(tmp_path, text) / "u.set.yaml").model
    runs = [_run("a[x=1]", KINDS), _run("a[x=2]", KINDS)]
    (curve,) = size_runs(runs, model).curves
    assert list(curve.charted) == ["hinge.fx", "drive.value", "rod.value", "rub.value"]
    (plain,) = size_runs(runs, None).curves
    assert "rub.value" not in plain.charted


def test_loads_plot_with_a_bad_unit_is_an_input_error(result: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.set.yaml"
    bad.write_text(
        "set: u\ncases: [x.case.yaml]\nreport: {output: u.xlsx, units: {force: mm}}\n",
        encoding="utf-8",
    )
    outcome = runner.invoke(app, ["plot", str(result), "--set", str(bad), "-o", str(tmp_path)])
    assert outcome.exit_code == 2
    assert "bad.set.yaml:3:34: error: report.units.force: 'mm' is not a unit of force" in (
        outcome.output
    )
    outcome = runner.invoke(app, ["plot", str(result), "--units", "forse=kN", "-o", str(tmp_path)])
    assert outcome.exit_code == 2 and "expected KIND=UNIT with KIND one of force" in outcome.output
    assert not list(tmp_path.glob("*.png"))


def test_report_digits_sets_the_significant_digits_shown(result: Path, tmp_path: Path) -> None:
    """`report.digits: 6` through `loads envelope --set` (the saved runs, no solving):
    2550.12 N*mm shows `0.00`, 0.0298100 kN `0.0000000`."""
    text = SET.replace("report: {output: u.xlsx,", "report: {output: u.xlsx, digits: 6,")
    set_file = _write(tmp_path, text) / "u.set.yaml"
    out = tmp_path / "six.xlsx"
    outcome = runner.invoke(app, ["envelope", str(result), "-o", str(out), "--set", str(set_file)])
    assert outcome.exit_code == 0, outcome.output
    rows = _envelope(openpyxl.load_workbook(out))
    assert rows["drive_torque.value"]["max"].number_format == "0.00"
    assert rows["pivot_force.fy"]["max"].number_format == "0.0000000"
    bad = _write(
        tmp_path, SET.replace("report: {output: u.xlsx,", "report: {output: u.xlsx, digits: 1,")
    )
    with pytest.raises(InputError, match=r"report\.digits"):
        load_and_compile_set(bad / "u.set.yaml")
