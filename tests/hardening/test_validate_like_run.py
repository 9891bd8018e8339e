"""Issue 15 item 8: every input mistake is exit 2 with a position, and `loads validate`
refuses what `loads run` refuses (same checks, short of solving), for case, mechanism and
set files."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.hardening.conftest import has_line, loads

ANALYSIS = "analysis: {type: kinematic, end: 0.5, step: 0.05}"
DYNAMIC = "analysis: {type: dynamic, end: 0.5, step: 0.05"
NO_MOTION = ('motions:\n  drive: {joint: pivot, value: "speed * t"}\n', "")
SLIDER_DAMPER = """\
name: d
bodies:
  slider: {mass: 1.0, cm: [0, 0, 0], inertia: [0.001, 0.001, 0.001]}
joints:
  guide: {type: prismatic, bodies: [slider, ground], at: [0, 0, 0], axis: [1, 0, 0]}
forces:
  brake: {type: damper, joint: guide, damping: 10}
"""
DAMPER_ERROR = (
    "d.mech.yaml:7:25: error: forces.brake.joint: joint 'guide' is prismatic; "
    "this element needs a revolute or cylindrical or inline joint"
)


def _dynamic(crank, extra: str) -> Path:
    case = crank(case=(ANALYSIS, DYNAMIC + extra + "}"))
    text = (
        case.read_text(encoding="utf-8")
        .replace(NO_MOTION[0], "")
        .replace("  drive_torque: {motion: drive, quantity: torque}\n", "")
    )
    case.write_text(text, encoding="utf-8")
    return case


@pytest.mark.parametrize(
    "extra,expected",
    [
        (", tolerance: 0", "crank.case.yaml:3:49: error: analysis.tolerance: must be positive"),
        (", tolerance: -1e-4", "crank.case.yaml:3:49: error: analysis.tolerance: must be positive"),
        (", max_step: 0", "crank.case.yaml:3:49: error: analysis.max_step: must be positive"),
        (
            ", tolerance: .inf",
            "crank.case.yaml:3:49: error: analysis.tolerance: expected a finite "
            "number, got infinity",
        ),
    ],
)
@pytest.mark.parametrize("command", ["validate", "run"])
def test_dynamic_settings_out_of_range_are_input_errors(
    crank, tmp_path: Path, command: str, extra: str, expected: str
) -> None:
    case = _dynamic(crank, extra)
    args = ["-o", tmp_path / "out"] if command == "run" else []
    result = loads(command, case, *args)
    assert result.exit_code == 2, result.output
    assert has_line(result.output, expected), result.output


@pytest.mark.parametrize("command", ["validate", "run"])
def test_non_finite_initial_value_is_an_input_error(crank, tmp_path: Path, command: str) -> None:
    case = crank(case=(ANALYSIS, ANALYSIS + "\ninitial:\n  pivot: {value: .nan}"))
    args = ["-o", tmp_path / "out"] if command == "run" else []
    result = loads(command, case, *args)
    assert result.exit_code == 2, result.output
    assert any(
        ": error: initial.pivot.value: expected a finite number, got NaN" in line
        for line in result.output.splitlines()
    ), result.output


def test_validate_of_a_mechanism_file_builds_it(tmp_path: Path) -> None:
    (tmp_path / "d.mech.yaml").write_text(SLIDER_DAMPER, encoding="utf-8")
    for command in ("validate", "run"):
        result = (
            loads(command, tmp_path / "d.mech.yaml", "-o", tmp_path / "out")
            if command == "run"
            else loads(command, tmp_path / "d.mech.yaml")
        )
        assert result.exit_code == 2, (command, result.output)
        assert has_line(result.output, DAMPER_ERROR), (command, result.output)


def test_validate_of_a_set_builds_its_cases(crank, tmp_path: Path) -> None:
    (tmp_path / "d.mech.yaml").write_text(SLIDER_DAMPER, encoding="utf-8")
    (tmp_path / "d.case.yaml").write_text(
        "case: d\nmechanism: d.mech.yaml\nanalysis: {type: dynamic, end: 0.1, step: 0.05}\n"
        "requests:\n  g: {joint: guide, quantity: force}\n",
        encoding="utf-8",
    )
    (tmp_path / "s.set.yaml").write_text("set: s\ncases: [d.case.yaml]\n", encoding="utf-8")
    for command in ("validate", "run"):
        args = ["-o", tmp_path / "out"] if command == "run" else []
        result = loads(command, tmp_path / "s.set.yaml", *args)
        assert result.exit_code == 2, (command, result.output)
        assert has_line(result.output, DAMPER_ERROR), (command, result.output)
    assert not (tmp_path / "out" / "s").exists()


def test_set_case_with_degrees_of_freedom_left_is_refused_before_solving(
    crank, tmp_path: Path
) -> None:
    """A kinematic case without its motion has 1 degree of freedom left: `loads run` of the
    case refuses it (exit 2), and so do `validate` and `run` of a set holding it."""
    crank(case=NO_MOTION)
    text = (
        (tmp_path / "crank.case.yaml")
        .read_text(encoding="utf-8")
        .replace("  drive_torque: {motion: drive, quantity: torque}\n", "")
    )
    (tmp_path / "crank.case.yaml").write_text(text, encoding="utf-8")
    (tmp_path / "s.set.yaml").write_text("set: s\ncases: [crank.case.yaml]\n", encoding="utf-8")
    single = loads("validate", tmp_path / "crank.case.yaml")
    assert single.exit_code == 2, single.output
    expected = next(line for line in single.output.splitlines() if ": error: " in line)
    for command in ("validate", "run"):
        args = ["-o", tmp_path / "out"] if command == "run" else []
        result = loads(command, tmp_path / "s.set.yaml", *args)
        assert result.exit_code == 2, (command, result.output)
        assert expected in result.output.splitlines(), (command, result.output)
    assert not (tmp_path / "out" / "s").exists()


def test_run_prints_a_case_warning_as_validate_does(crank, tmp_path: Path) -> None:
    """A warning of the case file (`accuracy` on a kinematic analysis) is printed by
    `loads run` under the run's status line as `loads validate` prints it: with its file,
    line and column."""
    case = crank(case=(ANALYSIS, ANALYSIS[:-1] + ", accuracy: 1e-2}"))
    expected = f"{case}:5:51: warning: analysis.accuracy: does nothing for a kinematic analysis"
    checked = loads("validate", case)
    assert checked.exit_code == 0, checked.output
    assert expected in checked.stdout.splitlines()
    ran = loads("run", case, "-o", tmp_path / "out")
    assert ran.exit_code == 0, ran.output
    assert "  " + expected in ran.stdout.splitlines()


@pytest.mark.parametrize(
    ("extra", "sweep", "expected"),
    [
        (
            ", accuracy: {target: tgt}",
            "tgt: [1e-2, 2, 1e-4]",
            "crank.case.yaml:3:60: error: analysis.accuracy.target: 2 must lie between 0 and 1 "
            "(a fraction of the peak)",
        ),
        (
            ", tolerance: tgt",
            "tgt: [1e-6, -1, 1e-5]",
            "crank.case.yaml:3:49: error: analysis.tolerance: must be positive",
        ),
    ],
)
def test_a_set_whose_swept_value_makes_a_run_invalid_is_refused_by_validate(
    crank, tmp_path: Path, extra: str, sweep: str, expected: str
) -> None:
    """`loads validate SET` refuses, at the case's key, what `loads run` refuses a run of
    the set for (exit 2), naming the runs: the value swept into a numeric field."""
    case = _dynamic(crank, extra)
    case.write_text(
        case.read_text(encoding="utf-8") + "parameters: {tgt: 1e-3}\n", encoding="utf-8"
    )
    (tmp_path / "s.set.yaml").write_text(
        f"set: s\ncases: [crank.case.yaml]\nsweep:\n  {sweep}\n  load: [10, 20]\n",
        encoding="utf-8",
    )
    bad = sweep.split("[")[1].split(", ")[1]
    runs = f"runs crank-turn[tgt={bad},load=10], crank-turn[tgt={bad},load=20]"
    checked = loads("validate", tmp_path / "s.set.yaml")
    assert checked.exit_code == 2, checked.output
    assert has_line(checked.output, f"{expected}, in {runs}"), checked.output
    assert "s.set.yaml: ok" not in checked.output
