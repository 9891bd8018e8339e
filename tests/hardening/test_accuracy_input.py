"""`analysis.accuracy` as a user writes it (0.10.0 trial, items 8-12): a mapping's keys are
each optional (the target defaults to the sizing accuracy); a fraction where a whole
number is needed, and a word that is none of the accuracy's forms, are named as such; a
target lies between 0 and 1 in a case as for `loads accuracy --target`; the outcome of a
run not tightened says why; `loads run` prints the projected initial values, a joint's
rate as a number."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from loadcases.foundation.accuracy_target import DEFAULT_ACCURACY
from loadcases.inputs.loader import load_case
from loadcases.run.global_error import Aim, Budget, accuracy_aim
from tests.hardening.conftest import has_line, loads

PENDULUM = """\
case: pendulum
mechanism:
  name: pendulum
  gravity: [0, -9.81, 0]
  bodies: {bar: {mass: 3.0, cm: [0, -0.5, 0], inertia: [0.25, 0.001, 0.25]}}
  joints: {hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
initial: {hinge: {value: 60 deg, rate: 0}}
analysis:
  accuracy: ACCURACY
  type: dynamic
  end: 0.5
  step: 0.01
requests:
  hinge_force: {joint: hinge, quantity: force, frame: ground}
"""
FORMS = (
    "expected a target such as 0.001 (a fraction of each request's peak, between 0 and 1), "
    "off, or a mapping {target, budget, measure}"
)


def _pendulum(tmp_path: Path, accuracy: str, extra: str = "") -> Path:
    """The pendulum case with `analysis.accuracy: ACCURACY` (line 9) and `extra` lines of
    its analysis."""
    path = tmp_path / "pendulum.case.yaml"
    text = PENDULUM.replace("ACCURACY", accuracy).replace(
        "  type: dynamic\n", f"  type: dynamic\n{extra}"
    )
    path.write_text(text, encoding="utf-8")
    return path


def _refused(tmp_path: Path, accuracy: str, *lines: str) -> str:
    result = loads("validate", _pendulum(tmp_path, accuracy))
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output and "internal error" not in result.output
    for line in lines:
        assert has_line(result.output, line), (line, result.output)
    return result.output


@pytest.mark.parametrize(
    ("accuracy", "measure", "cpu"),
    [("{measure: histories}", "histories", 600.0), ("{budget: {cpu: 60 s}}", "peaks", 60.0)],
)
def test_a_mapping_without_a_target_takes_the_default_target(
    tmp_path: Path, accuracy: str, measure: str, cpu: float
) -> None:
    path = _pendulum(tmp_path, accuracy)
    result = loads("validate", path)
    assert result.exit_code == 0, result.output
    given = load_case(path).case.analysis.accuracy
    assert given.target == DEFAULT_ACCURACY
    assert accuracy_aim(given, None) == Aim(DEFAULT_ACCURACY, Budget(cpu, None, 8), measure)


def test_a_run_without_a_target_is_judged_against_the_default(tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = loads("run", _pendulum(tmp_path, "{budget: {cpu: 60 s}}"), "-o", out)
    assert result.exit_code == 0, result.output
    block = json.loads((out / "pendulum.summary.json").read_text())["accuracy"]
    assert block["target"] == 0.001
    assert block["budget"] == {"cpu": 60.0, "steps": None, "refinements": 8}


@pytest.mark.parametrize(
    ("accuracy", "where", "key", "got"),
    [
        ("{target: 1e-2, budget: {steps: 1.5}}", "9:37", "budget.steps", "1.5"),
        ("{budget: {refinements: 2.5}}", "9:23", "budget.refinements", "2.5"),
        ("{budget: {steps: many}}", "9:23", "budget.steps", "'many'"),
    ],
)
def test_a_fraction_of_a_count_asks_for_a_whole_number(
    tmp_path: Path, accuracy: str, where: str, key: str, got: str
) -> None:
    _refused(
        tmp_path,
        accuracy,
        f"pendulum.case.yaml:{where}: error: analysis.accuracy.{key}: expected a whole "
        f"number, got {got}",
    )


@pytest.mark.parametrize(
    ("accuracy", "got"),
    [("false", "false"), ('"OFF"', "'OFF'"), ("none", "'none'"), ("[1e-3]", "a list of 1 values")],
)
def test_a_word_that_is_no_accuracy_form_names_the_forms(
    tmp_path: Path, accuracy: str, got: str
) -> None:
    _refused(
        tmp_path, accuracy, f"pendulum.case.yaml:9:3: error: analysis.accuracy: {FORMS}, got {got}"
    )


def test_a_plain_on_is_refused_without_a_hint_to_quote_it(tmp_path: Path) -> None:
    """YAML 1.1 reads `on` as true; quoted, 'on' is the same text to `loads` and is
    refused alike, so the hint does not suggest quoting it."""
    output = _refused(
        tmp_path,
        "on",
        f"pendulum.case.yaml:9:3: error: analysis.accuracy: {FORMS}, got 'on'",
        "pendulum.case.yaml:9:3: hint: YAML 1.1 reads the plain on as the boolean true: "
        "write the value you mean",
    )
    assert "quote" not in output
    _refused(
        tmp_path, "'on'", f"pendulum.case.yaml:9:3: error: analysis.accuracy: {FORMS}, got 'on'"
    )


@pytest.mark.parametrize(
    ("accuracy", "where", "key", "shown"),
    [
        ("2", "9:3", "analysis.accuracy", "2"),
        ("1", "9:3", "analysis.accuracy", "1"),
        ("0", "9:3", "analysis.accuracy", "0"),
        ("{target: 1.5}", "9:14", "analysis.accuracy.target", "1.5"),
        ("{target: -1e-3}", "9:14", "analysis.accuracy.target", "-0.001"),
    ],
)
def test_a_target_outside_0_and_1_is_refused_as_loads_accuracy_refuses_it(
    tmp_path: Path, accuracy: str, where: str, key: str, shown: str
) -> None:
    bounds = f"{shown} must lie between 0 and 1 (a fraction of the peak)"
    _refused(tmp_path, accuracy, f"pendulum.case.yaml:{where}: error: {key}: {bounds}")
    result = loads("accuracy", _pendulum(tmp_path, "off"), "--target", shown, "-o", tmp_path / "o")
    assert result.exit_code == 2 and f"--target: {bounds}" in result.output, result.output
    assert not (tmp_path / "o").exists()


def test_a_target_within_0_and_1_is_taken(tmp_path: Path) -> None:
    result = loads("validate", _pendulum(tmp_path, "0.5"))
    assert result.exit_code == 0, result.output


def test_loads_schema_states_the_bounds_and_the_default() -> None:
    result = loads("schema")
    assert result.exit_code == 0
    defs = json.loads(result.output)["$defs"]
    target = defs["AccuracyTarget"]["properties"]["target"]
    assert (target["exclusiveMinimum"], target["exclusiveMaximum"]) == (0.0, 1.0)
    assert target["default"] == DEFAULT_ACCURACY and "target" not in defs["AccuracyTarget"].get(
        "required", []
    )
    accuracy = defs["Analysis"]["properties"]["accuracy"]
    assert (accuracy["exclusiveMinimum"], accuracy["exclusiveMaximum"]) == (0.0, 1.0)


def test_a_target_with_a_tolerance_says_the_tolerance_fixes_the_steps(tmp_path: Path) -> None:
    out = tmp_path / "out"
    case = _pendulum(tmp_path, "1e-5", "  tolerance: 1e-6\n")
    result = loads("run", case, "-o", out)
    assert result.exit_code == 0, result.output
    block = json.loads((out / "pendulum.summary.json").read_text())["accuracy"]
    assert block["met"] is False and block["budget"] is None and block["tightenings"] == 0
    assert block["outcome"] == (
        "not met: not tightened (the case sets a tolerance, which fixes the steps: drop "
        "`tolerance` to let the engine tighten them)"
    )


def test_no_target_in_the_case_says_so() -> None:
    aim = accuracy_aim(None, 1e-3)
    assert (aim.target, aim.budget) == (DEFAULT_ACCURACY, None)
    assert aim.untightened == (
        "no accuracy target in the case: the default one is estimated against only"
    )
    assert accuracy_aim(2e-3, None).untightened == ""


SLIDER_CRANK = """\
name: sc90
plane: xy
units: {length: mm, angle: deg}
gravity: [0, -9.81, 0]
bodies:
  crank:  {mass: 1.2, cm: [0, 50, 0],  inertia: [0.001, 0.0001, 0.001]}
  rod:    {mass: 0.8, cm: [141.42, 50, 0], inertia: [0.0001, 0.006, 0.006]}
  slider: {mass: 2.0, cm: [282.84, 0, 0], inertia: [0.001, 0.001, 0.001]}
joints:
  pivot: {type: revolute,  bodies: [crank, ground], at: [0, 0, 0],   axis: [0, 0, 1]}
  big:   {type: revolute,  bodies: [rod, crank],    at: [0, 100, 0], axis: [0, 0, 1]}
  small: {type: revolute,  bodies: [slider, rod],   at: [282.8427, 0, 0], axis: [0, 0, 1]}
  guide: {type: prismatic, bodies: [slider, ground], at: [282.8427, 0, 0], axis: [1, 0, 0]}
"""
PROJECTED = """\
case: proj
mechanism: sc90.mech.yaml
initial:
  pivot: {value: 30 deg, rate: 1}
  guide: {value: 0.05, rate: 5}
analysis: {type: dynamic, end: 0.05, step: 0.01, accuracy: off}
requests:
  crank_angle: {joint: pivot, quantity: angle}
"""


def test_loads_run_prints_the_projected_rates_as_numbers(tmp_path: Path) -> None:
    """A slider-crank given both joints' values and rates: one degree of freedom, so the
    constraints change them, and `loads run` prints each change (SI), a joint's rate as
    a number, not a list of one."""
    (tmp_path / "sc90.mech.yaml").write_text(SLIDER_CRANK, encoding="utf-8")
    (tmp_path / "proj.case.yaml").write_text(PROJECTED, encoding="utf-8")
    result = loads("run", tmp_path / "proj.case.yaml", "-o", tmp_path / "out")
    assert result.exit_code == 0, result.output
    rates = re.findall(
        r"warning: initial rate of joint '(\w+)' changed from (\S+) to (\S+) ", result.output
    )
    assert [(name, given) for name, given, _ in rates] == [("pivot", "1.0"), ("guide", "5.0")]
    assert float(rates[0][2]) == pytest.approx(1.230385908, abs=1e-8)
    assert float(rates[1][2]) == pytest.approx(-0.088005497, abs=1e-8)
    assert "warning: initial travel of joint 'guide' changed from 0.05 to " in result.output
    summary = json.loads((tmp_path / "out" / "proj.summary.json").read_text())
    assert sum("changed from" in w for w in summary["warnings"]) == 4
