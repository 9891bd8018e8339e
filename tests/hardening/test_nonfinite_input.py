"""Issue 15 item 1: NaN, infinity and overflowing constants are input errors (exit 2) at
file:line:col, from `loads validate` and `loads run` alike; never an `ok` run of NaN."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.hardening.conftest import has_line, loads

MASS = "crank: {mass: 1.0,"
PUSH = '"-load"'
# (mechanism change, expected diagnostic line)
MECHANISM_PROBES = [
    (
        (MASS, "crank: {mass: .nan,"),
        "crank.mech.yaml:5:11: error: bodies.crank.mass: expected a finite number, got NaN",
    ),
    (
        (MASS, "crank: {mass: .inf,"),
        "crank.mech.yaml:5:11: error: bodies.crank.mass: expected a finite number, got infinity",
    ),
    (
        (MASS, "crank: {mass: -.inf,"),
        "crank.mech.yaml:5:11: error: bodies.crank.mass: expected a finite number, got -infinity",
    ),
    (
        (MASS, "crank: {mass: 1e999,"),
        "crank.mech.yaml:5:11: error: bodies.crank.mass: expected a finite number, got infinity",
    ),
    (
        (MASS, "crank: {mass: 1e999 kg,"),
        "crank.mech.yaml:5:11: error: bodies.crank.mass: expected a finite number, got '1e999 kg'",
    ),
    (
        ("cm: [0.05, 0, 0]", "cm: [0.05, 1e999, 0]"),
        "crank.mech.yaml:5:22: error: bodies.crank.cm: item 2: expected a finite number, "
        "got infinity",
    ),
    (
        ("at: [0.1, 0, 0]", 'at: "[0.1, 1e999, 0] m"'),
        "crank.mech.yaml:7:22: error: points.tip.at: item 2: expected a finite number, "
        "got '1e999 m'",
    ),
    (
        ("load: 10.0", "load: .nan"),
        "crank.mech.yaml:3:26: error: parameters.load: expected a finite number, got NaN",
    ),
    (
        (PUSH, ".inf"),
        "crank.mech.yaml:11:46: error: forces.push.value[1]: expected a finite number, "
        "got infinity",
    ),
    (
        (PUSH, '"-1e999*t"'),
        "crank.mech.yaml:11:48: error: forces.push.value[1]: invalid expression: number out of "
        "range (not finite)",
    ),
    (
        (PUSH, '"10**10**10*t"'),
        "crank.mech.yaml:11:46: error: forces.push.value[1]: invalid expression: overflow in "
        "'**' at character 3",
    ),
    (
        (PUSH, '"1/0*t"'),
        "crank.mech.yaml:11:46: error: forces.push.value[1]: invalid expression: division by "
        "zero at character 2",
    ),
    (
        (PUSH, '"t/(load - 10)"'),
        "crank.mech.yaml:11:46: error: forces.push.value[1]: invalid expression: division by "
        "zero at character 2",
    ),
    (
        (PUSH, '"1e300*1e300*t"'),
        "crank.mech.yaml:11:46: error: forces.push.value[1]: invalid expression: overflow in "
        "'*' at character 6",
    ),
]


@pytest.mark.parametrize("command", ["validate", "run"])
@pytest.mark.parametrize("change,expected", MECHANISM_PROBES)
def test_non_finite_mechanism_values_are_input_errors(
    crank, tmp_path: Path, command: str, change, expected: str
) -> None:
    case = crank(mech=change)
    extra = ["-o", tmp_path / "out"] if command == "run" else []
    result = loads(command, case, *extra)
    assert result.exit_code == 2, result.output
    assert has_line(result.output, expected), result.output
    assert not (tmp_path / "out" / "crank-turn.csv").exists()


@pytest.mark.parametrize(
    "change,expected",
    [
        (
            ("end: 0.5", "end: .inf"),
            "crank.case.yaml:5:29: error: analysis.end: expected a finite number, got infinity",
        ),
        (
            ("step: 0.05", "step: .nan"),
            "crank.case.yaml:5:39: error: analysis.step: expected a finite number, got NaN",
        ),
        (
            ('"speed * t"', '"speed * t / (speed - 1)"'),
            "crank.case.yaml:4:25: error: motions.drive.value: invalid expression: division by "
            "zero "
            "at character 11",
        ),
        (
            ('"speed * t"', '"speed * t * 1e999"'),
            "crank.case.yaml:4:45: error: motions.drive.value: invalid expression: number out of "
            "range (not finite)",
        ),
    ],
)
@pytest.mark.parametrize("command", ["validate", "run"])
def test_non_finite_case_values_are_input_errors(
    crank, tmp_path: Path, command: str, change, expected: str
) -> None:
    case = crank(case=change)
    extra = ["-o", tmp_path / "out"] if command == "run" else []
    result = loads(command, case, *extra)
    assert result.exit_code == 2, result.output
    assert has_line(result.output, expected), result.output


@pytest.mark.parametrize("command", ["validate", "run"])
def test_non_finite_sweep_value_is_an_input_error(crank, tmp_path: Path, command: str) -> None:
    crank()
    (tmp_path / "s.set.yaml").write_text(
        "set: s\ncases: [crank.case.yaml]\nsweep:\n  speed: [1.0, 1e999]\n", encoding="utf-8"
    )
    extra = ["-o", tmp_path / "out"] if command == "run" else []
    result = loads(command, tmp_path / "s.set.yaml", *extra)
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        "s.set.yaml:4:16: error: sweep.speed[1]: expected a finite number, got infinity",
    ), result.output
    assert not (tmp_path / "out" / "s").exists()


def test_sweep_value_overflowing_an_expression_is_an_input_error(crank, tmp_path: Path) -> None:
    """A finite swept value that makes a constant expression overflow once substituted
    (load = 1e300 in `-load*1e10`) is found when its run is built: that run is reported
    with the expression's position, the other runs are solved, and the command exits 2."""
    crank(mech=('"-load"', '"-load*1e10"'))
    (tmp_path / "s.set.yaml").write_text(
        "set: s\ncases: [crank.case.yaml]\nsweep:\n  load: [1e300, 10]\n", encoding="utf-8"
    )
    result = loads("run", tmp_path / "s.set.yaml", "-o", tmp_path / "out")
    assert result.exit_code == 2, result.output
    assert (
        "crank.mech.yaml:11:46: error: forces.push.value[1]: invalid expression: overflow in "
        "'*' at character 6" in result.output
    )
    assert "crank-turn[load=10]: ok" in result.output
    assert "make the input invalid (1, exit 2): crank-turn[load=1e+300]" in result.output
