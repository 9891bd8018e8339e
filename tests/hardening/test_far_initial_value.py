"""A given initial value far from the drawn geometry (a unit slip: 1e6 m) made the assembly
follow the way in stages of 0.524 m for minutes (1e6 m: 1.9 million stages) or for ever
(1e300 m): beyond MAX_STAGES stages the run fails at once (exit 1) saying how far."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

from mechlib.solvers.assembly import MAX_STAGES
from tests.hardening.conftest import SPRING_MASS, loads

FAR = (
    """\
case: spring-mass-far
"""
    + SPRING_MASS
    + """\
initial:
  slide: {value: VALUE, rate: 0}
analysis: {type: dynamic, end: 0.01, step: 0.001}
requests:
  x: {joint: slide, quantity: travel}
"""
)


@pytest.mark.parametrize(
    ("value", "shown", "stages"), [("1e6", "1e+06", "1.91e+06"), ("1e300", "1e+300", "1.91e+300")]
)
def test_a_value_too_far_from_the_drawing_fails_at_once_with_the_numbers(
    tmp_path: Path, value: str, shown: str, stages: str
) -> None:
    case = tmp_path / "far.case.yaml"
    case.write_text(FAR.replace("VALUE", value), encoding="utf-8")
    began = time.process_time()
    result = loads("run", case, "-o", tmp_path / "out")
    assert time.process_time() - began < 30.0  # was minutes (1e6 m) or for ever (1e300 m)
    assert result.exit_code == 1, result.output
    summary = json.loads((tmp_path / "out" / "spring-mass-far.summary.json").read_text())
    assert summary["status"] == "failed"
    assert summary["message"] == (
        f"the initial positions could not be assembled: joint 'slide' is given {shown} m, "
        f"{shown} m from the drawn geometry (0 m), too far to assemble: the assembly follows "
        f"the drawn geometry in stages of at most 0.524 m, and it would take {stages} stages, "
        f"more than {MAX_STAGES}; give a value nearer the drawn geometry"
    )


PENDULUM = """\
case: pendulum-far
mechanism:
  name: pendulum
  gravity: [0, -9.81, 0]
  bodies:
    bar: {mass: 1.0, cm: [0, -0.5, 0], inertia: [0.1, 0.001, 0.1]}
  joints:
    hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}
initial:
  hinge: {value: 1e5, rate: 0}
analysis: {type: dynamic, end: 0.01, step: 0.001}
requests:
  angle: {joint: hinge, quantity: angle}
"""


def test_an_angle_too_far_from_the_drawing_fails_in_radians(tmp_path: Path) -> None:
    """1e5 rad (16 000 turns) takes 190 986 stages of 30 deg: refused at once, in rad."""
    case = tmp_path / "far.case.yaml"
    case.write_text(PENDULUM, encoding="utf-8")
    result = loads("run", case, "-o", tmp_path / "out")
    assert result.exit_code == 1, result.output
    summary = json.loads((tmp_path / "out" / "pendulum-far.summary.json").read_text())
    assert summary["message"] == (
        "the initial positions could not be assembled: joint 'hinge' is given 100000 rad, "
        "100000 rad from the drawn geometry (0 rad), too far to assemble: the assembly "
        "follows the drawn geometry in stages of at most 0.524 rad, and it would take "
        f"1.91e+05 stages, more than {MAX_STAGES}; give a value nearer the drawn geometry"
    )
