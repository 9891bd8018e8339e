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
from tests.loadcases.set_fixtures import SLIDER_MECH

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
TARGET = "expected a target such as 0.001 (a fraction of each request's peak, between 0 and 1)"
FORMS = f"{TARGET}, off, or a mapping {{target, budget, measure}}"


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


BOUNDS = "must lie between 0 and 1 (a fraction of the peak)"


@pytest.mark.parametrize(
    ("accuracy", "where", "key", "message"),
    [
        (
            "{target: 1e-2, budget: {steps: 1.5}}",
            "9:37",
            ".budget.steps",
            "expected a whole number, got 1.5",
        ),
        (
            "{budget: {refinements: 2.5}}",
            "9:23",
            ".budget.refinements",
            "expected a whole number, got 2.5",
        ),
        ("{budget: {steps: many}}", "9:23", ".budget.steps", "expected a whole number, got 'many'"),
        ("false", "9:3", "", f"{FORMS}, got false"),
        ('"OFF"', "9:3", "", f"{FORMS}, got 'OFF'"),
        ("none", "9:3", "", f"{FORMS}, got 'none'"),
        ("[1e-3]", "9:3", "", f"{FORMS}, got a list of 1 values"),
        ("off2", "9:3", "", f"{FORMS}, got 'off2'"),
        ("1e-3 x", "9:3", "", f"{FORMS}, got '1e-3 x'"),
        ("1 mm", "9:3", "", "expected a dimensionless number, got '1 mm' (a length)"),
        ("{target: off2}", "9:14", ".target", f"{TARGET}, got 'off2'"),
        ("'on'", "9:3", "", f"{FORMS}, got 'on'"),
        ("2", "9:3", "", f"2 {BOUNDS}"),
        ("1", "9:3", "", f"1 {BOUNDS}"),
        ("0", "9:3", "", f"0 {BOUNDS}"),
        ("{target: 1.5}", "9:14", ".target", f"1.5 {BOUNDS}"),
        ("{target: -1e-3}", "9:14", ".target", f"-0.001 {BOUNDS}"),
    ],
)
def test_a_bad_accuracy_is_refused_at_its_key_saying_what_it_takes(
    tmp_path: Path, accuracy: str, where: str, key: str, message: str
) -> None:
    """A fraction where a count is needed asks for a whole number; a text that is none
    of the accuracy's forms (no quantity at all) names them; a target outside 0 and 1 is
    refused as `loads accuracy --target` refuses it."""
    _refused(
        tmp_path, accuracy, f"pendulum.case.yaml:{where}: error: analysis.accuracy{key}: {message}"
    )


@pytest.mark.parametrize(("accuracy", "where"), [("tgtt", "9:3"), ("{target: tgtt}", "9:14")])
def test_a_mistyped_parameter_name_is_named_as_such(
    tmp_path: Path, accuracy: str, where: str
) -> None:
    """A text naming no parameter but close to one is an unknown parameter, in the number
    form as in the mapping's target (not a text that is none of the forms)."""
    path = _pendulum(tmp_path, accuracy)
    path.write_text(path.read_text(encoding="utf-8") + "parameters: {tgt: 1e-3}\n", "utf-8")
    result = loads("validate", path)
    assert result.exit_code == 2, result.output
    key = "analysis.accuracy" + (".target" if "target" in accuracy else "")
    for line in (
        f"pendulum.case.yaml:{where}: error: {key}: unknown parameter 'tgtt'",
        f"pendulum.case.yaml:{where}: hint: did you mean 'tgt'?",
    ):
        assert has_line(result.output, line), (line, result.output)


def test_a_plain_on_is_refused_without_a_hint_to_quote_it(tmp_path: Path) -> None:
    """YAML 1.1 reads `on` as true; quoted, 'on' is the same text to `loads` and is
    refused alike (above), so the hint does not suggest quoting it."""
    output = _refused(
        tmp_path,
        "on",
        f"pendulum.case.yaml:9:3: error: analysis.accuracy: {FORMS}, got 'on'",
        "pendulum.case.yaml:9:3: hint: YAML 1.1 reads the plain on as the boolean true: "
        "write the value you mean",
    )
    assert "quote" not in output


@pytest.mark.parametrize("target", ["2", "1", "0", "-0.001"])
def test_loads_accuracy_refuses_the_targets_a_case_refuses(tmp_path: Path, target: str) -> None:
    case, out = _pendulum(tmp_path, "off"), tmp_path / "o"
    result = loads("accuracy", case, "--target", target, "-o", out)
    assert result.exit_code == 2 and f"--target: {target} {BOUNDS}" in result.output, result.output
    assert not out.exists()


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


PROJECTED = """\
case: proj
mechanism: slider.mech.yaml
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
    (tmp_path / "slider.mech.yaml").write_text(SLIDER_MECH, encoding="utf-8")
    (tmp_path / "proj.case.yaml").write_text(PROJECTED, encoding="utf-8")
    result = loads("run", tmp_path / "proj.case.yaml", "-o", tmp_path / "out")
    assert result.exit_code == 0, result.output
    rates = re.findall(
        r"warning: initial rate of joint '(\w+)' changed from (\S+) to (\S+) ", result.output
    )
    assert [(name, given) for name, given, _ in rates] == [("pivot", "1.0"), ("guide", "5.0")]
    assert float(rates[0][2]) == pytest.approx(-0.292840586, abs=1e-8)
    assert float(rates[1][2]) == pytest.approx(0.021493842, abs=1e-8)
    assert "warning: initial travel of joint 'guide' changed from 0.05 to " in result.output
    summary = json.loads((tmp_path / "out" / "proj.summary.json").read_text())
    assert sum("changed from" in w for w in summary["warnings"]) == 4
