"""`analysis.accuracy` where it is not used: a phase's target, as a number or a mapping, is
warned that the global error of a phased case is not estimated (a phase's `off` asks for
just that: no warning); the documented `off` where it does nothing (a kinematic analysis, a
static phase) gets that warning and no YAML 1.1 hint."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.hardening.conftest import SPRING_MASS, has_line, loads

PHASED = (
    """\
case: sm-phases
"""
    + SPRING_MASS
    + """\
initial:
  slide: {value: 0.1, rate: 0}
phases:
  - name: hold
    analysis: {type: static}
    locks: [slide]
  - name: swing
    analysis: {type: dynamic, end: 0.05, step: 0.01, accuracy: ACCURACY}
requests:
  x: {joint: slide, quantity: travel}
"""
)
NOT_ESTIMATED = (
    "sm.case.yaml:20:54: warning: phases[1].analysis.accuracy: the global error is not "
    "estimated for a phased case: set the phase's tolerance instead"
)
HINT = "hint: YAML 1.1 reads the plain off"


def _phased(tmp_path: Path, accuracy: str) -> Path:
    path = tmp_path / "sm.case.yaml"
    path.write_text(PHASED.replace("ACCURACY", accuracy), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "accuracy", ["1e-4", "{target: 1e-4}", "{budget: {cpu: 60 s}}", "{measure: histories}"]
)
def test_a_phase_accuracy_in_any_form_is_warned_by_validate(tmp_path: Path, accuracy: str) -> None:
    result = loads("validate", _phased(tmp_path, accuracy))
    assert result.exit_code == 0, result.output
    assert has_line(result.output, NOT_ESTIMATED), result.output
    assert HINT not in result.output


def test_a_dynamic_phase_accuracy_off_is_quiet(tmp_path: Path) -> None:
    result = loads("validate", _phased(tmp_path, "off"))
    assert result.exit_code == 0, result.output
    assert "warning" not in result.output and "hint" not in result.output, result.output


def test_a_phase_accuracy_mapping_is_warned_by_run_and_in_the_summary(tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = loads("run", _phased(tmp_path, "{target: 1e-4}"), "-o", out)
    assert result.exit_code == 0, result.output
    assert any(line.strip().endswith(NOT_ESTIMATED) for line in result.output.splitlines())
    summary = json.loads((out / "sm-phases.summary.json").read_text(encoding="utf-8"))
    assert NOT_ESTIMATED.split(": warning: ")[1] in summary["warnings"]


def test_accuracy_off_in_a_kinematic_analysis_is_warned_without_a_hint(crank) -> None:
    analysis = "analysis: {type: kinematic, end: 0.5, step: 0.05}"
    case = crank(case=(analysis, analysis[:-1] + ", accuracy: off}"))
    result = loads("validate", case)
    assert result.exit_code == 0, result.output
    expected = (
        "crank.case.yaml:5:51: warning: analysis.accuracy: does nothing for a kinematic analysis"
    )
    assert has_line(result.output, expected), result.output
    assert "hint:" not in result.output


def test_accuracy_off_in_a_static_phase_is_warned_without_a_hint(tmp_path: Path) -> None:
    path = _phased(tmp_path, "1e-3").read_text(encoding="utf-8")
    path = path.replace("{type: static}", "{type: static, accuracy: off}")
    (tmp_path / "sm.case.yaml").write_text(path, encoding="utf-8")
    result = loads("validate", tmp_path / "sm.case.yaml")
    assert result.exit_code == 0, result.output
    expected = (
        "sm.case.yaml:17:30: warning: phases[0].analysis.accuracy: does nothing for a static "
        "analysis"
    )
    assert has_line(result.output, expected), result.output
    assert HINT not in result.output
