"""The accuracy block and warnings as a user reads them (0.10.0 trial, items 11-12): the
outcome of a run not tightened says why; `loads run` prints the projected initial values,
a joint's rate as a number."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from loadcases.run.global_error import DEFAULT_ACCURACY, accuracy_aim
from tests.hardening.conftest import loads

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


def _pendulum(tmp_path: Path, accuracy: str, extra: str = "") -> Path:
    """The pendulum case with `analysis.accuracy: ACCURACY` (line 9) and `extra` lines of
    its analysis."""
    path = tmp_path / "pendulum.case.yaml"
    text = PENDULUM.replace("ACCURACY", accuracy).replace(
        "  type: dynamic\n", f"  type: dynamic\n{extra}"
    )
    path.write_text(text, encoding="utf-8")
    return path


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
