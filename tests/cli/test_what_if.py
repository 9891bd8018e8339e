"""`loads run FILE --set NAME=VALUE` (issue 16 item 7): the overridden value reaches the
solution, names the run and its summary, is part of a set run's reuse key, and bad
options are input errors (exit 2) that name the option.

Reference: an arm of mass m on a hinge driven at constant rate omega, no gravity, its
centre of mass at distance L: the hinge reaction is the centripetal force m omega^2 L
(exact for a kinematic analysis: the cm moves on a circle at constant speed).
"""

from __future__ import annotations

import json
from pathlib import Path

import openpyxl
import pytest
from typer.testing import CliRunner

from cli.app import app

runner = CliRunner()
MASS = 3.0  # kg, as in ARM below

ARM = """\
case: arm
mechanism:
  name: arm
  parameters:
    length: 1 m
    omega: 2 rad/s
  bodies:
    bar: {mass: 3.0, cm: [0, length, 0], inertia: [0.001, 0.001, 0.001]}
  joints:
    hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}
motions:
  spin: {joint: hinge, value: "omega * t"}
analysis: {type: kinematic, end: 0.1, step: 0.05}
requests:
  hinge_force: {joint: hinge, quantity: force}
"""

SET = """\
set: arm-set
cases: [arm.case.yaml]
sweep: {omega: [2 rad/s, 3 rad/s]}
"""


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "arm.case.yaml").write_text(ARM)
    (tmp_path / "arm.set.yaml").write_text(SET)
    return tmp_path


def _summary(path: Path) -> dict:
    return json.loads(path.read_text())


def _reaction(summary: dict) -> float:
    return summary["extremes"]["hinge_force.f"]["max"]


def test_override_reaches_the_solution_and_names_the_run(folder: Path) -> None:
    """1500 mm instead of 1 m: reaction 3 * 2^2 * 1.5 = 18 N instead of 12 N (to 1e-9)."""
    out = folder / "res"
    base = runner.invoke(app, ["run", str(folder / "arm.case.yaml"), "-o", str(out)])
    assert base.exit_code == 0, base.output
    result = runner.invoke(
        app, ["run", str(folder / "arm.case.yaml"), "-o", str(out), "--set", "length=1500 mm"]
    )
    assert result.exit_code == 0, result.output
    assert "arm[length=1500mm]: ok" in result.stdout  # the value as given
    plain, what_if = (
        _summary(out / "arm.summary.json"),
        _summary(out / "arm[length=1500mm].summary.json"),
    )
    assert _reaction(plain) == pytest.approx(MASS * 2.0**2 * 1.0, rel=1e-9)
    assert _reaction(what_if) == pytest.approx(MASS * 2.0**2 * 1.5, rel=1e-9)
    assert what_if["overrides"] == {"length": 1.5} and plain["overrides"] == {}
    assert what_if["parameters"]["length"] == 1.5
    assert what_if["input_sha256"] != plain["input_sha256"]


def test_two_overrides_and_a_bare_number_is_si(folder: Path) -> None:
    out = folder / "res"
    result = runner.invoke(
        app,
        [
            "run",
            str(folder / "arm.case.yaml"),
            "-o",
            str(out),
            "--set",
            "omega=3",
            "--set",
            "length=2",
        ],
    )
    assert result.exit_code == 0, result.output
    summary = _summary(out / "arm[omega=3,length=2].summary.json")
    assert _reaction(summary) == pytest.approx(MASS * 3.0**2 * 2.0, rel=1e-9)


def test_set_runs_with_an_override_never_reuse_other_runs(folder: Path) -> None:
    """Runs with an override are new runs (named with it); the same override again is
    reused; another value is solved again. Reactions m omega^2 L for each run."""
    args = ["run", str(folder / "arm.set.yaml"), "-o", str(folder / "res"), "--jobs", "1"]
    assert runner.invoke(app, args).exit_code == 0
    first = runner.invoke(app, [*args, "--set", "length=0.5 m"])
    assert first.exit_code == 0, first.output
    assert "2 runs, 0 failed, 0 reused" in first.stdout
    set_dir = folder / "res" / "arm-set"
    for omega in (2.0, 3.0):
        summary = _summary(set_dir / f"arm[omega={omega:g}rad_per_s,length=0.5m].summary.json")
        assert _reaction(summary) == pytest.approx(MASS * omega**2 * 0.5, rel=1e-9)
        assert summary["overrides"] == {"length": 0.5}
    again = runner.invoke(app, [*args, "--set", "length=0.5 m"])
    assert "2 runs, 0 failed, 2 reused" in again.stdout
    other = runner.invoke(app, [*args, "--set", "length=0.7 m"])
    assert "2 runs, 0 failed, 0 reused" in other.stdout
    envelope = (set_dir / "envelope.csv").read_text()
    assert "arm[omega=3rad_per_s,length=0.7m]" in envelope
    book = openpyxl.load_workbook(set_dir / "envelope.xlsx", read_only=True)
    provenance = [
        [c for c in row if c is not None] for row in book["Provenance"].iter_rows(values_only=True)
    ]
    assert ["--set", "length=0.7 m"] in provenance


@pytest.mark.parametrize(
    ("option", "message"),
    [
        ("length", "--set 'length': expected NAME=VALUE"),
        ("=2", "--set '=2': expected NAME=VALUE"),
        ("length=", "--set 'length=': expected NAME=VALUE"),
        ("length=nan", "--set length: expected a finite number, got NaN"),
        ("length=1e999 m", "--set length: expected a finite number, got '1e999 m'"),
        ("length=two m", "--set length: cannot read 'two m'"),
    ],
)
def test_malformed_options_exit_2(folder: Path, option: str, message: str) -> None:
    result = runner.invoke(
        app, ["run", str(folder / "arm.case.yaml"), "-o", str(folder / "res"), "--set", option]
    )
    assert result.exit_code == 2
    assert message in result.output
    assert not (folder / "res").exists()


def test_unknown_parameter_and_wrong_dimension_exit_2(folder: Path) -> None:
    result = runner.invoke(
        app,
        [
            "run",
            str(folder / "arm.case.yaml"),
            "-o",
            str(folder / "res"),
            "--set",
            "lenght=2 m",
            "--set",
            "omega=3 kg",
        ],
    )
    assert result.exit_code == 2
    assert "--set lenght=2 m: no parameter 'lenght' in the case" in result.output
    assert "did you mean 'length'?" in result.output
    assert (
        "arm.case.yaml:6:5: error: mechanism.parameters.omega: --set omega=3 kg: expected an "
        "angular velocity like '2 rad/s', got a mass" in result.output
    )


def test_override_of_a_swept_parameter_is_refused(folder: Path) -> None:
    result = runner.invoke(
        app, ["run", str(folder / "arm.set.yaml"), "-o", str(folder / "res"), "--set", "omega=5"]
    )
    assert result.exit_code == 2
    assert "arm.set.yaml:3:9: error: sweep.omega: --set omega=5: the set varies 'omega'" in (
        result.output
    )


def test_set_override_of_an_unknown_parameter_is_refused(folder: Path) -> None:
    result = runner.invoke(
        app, ["run", str(folder / "arm.set.yaml"), "-o", str(folder / "res"), "--set", "lenth=2"]
    )
    assert result.exit_code == 2
    assert "--set lenth=2: no parameter 'lenth' in the set or its cases" in result.output
    assert not (folder / "res" / "arm-set").exists()


def test_same_name_twice_is_refused(folder: Path) -> None:
    result = runner.invoke(
        app,
        ["run", str(folder / "arm.case.yaml"), "--set", "length=1", "--set", "length=2"],
    )
    assert result.exit_code == 2
    assert "--set length: given twice (1, 2)" in result.output


def test_validate_checks_a_case_as_run_set_would_run_it(tmp_path: Path) -> None:
    """`loads validate FILE --set NAME=VALUE` checks the overridden case (exit 2 for a value
    of another dimension, naming the option; 0 for a good one), and writes nothing."""
    case = tmp_path / "arm.case.yaml"
    case.write_text(ARM, encoding="utf-8")
    good = runner.invoke(app, ["validate", str(case), "--set", "length=1.5 m"])
    assert good.exit_code == 0, good.output
    bad = runner.invoke(app, ["validate", str(case), "--set", "length=2 kg"])
    assert bad.exit_code == 2, bad.output
    assert "--set length=2 kg: expected a length" in bad.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm.case.yaml"]
