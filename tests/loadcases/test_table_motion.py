"""A motion read from a table beyond its data (`extrapolate: linear`): the joint's angle
continues the table's last line, and its rate and acceleration are that line's slope and
zero (the exact time derivatives of the expression go through the table's derivative,
which gave the end's curvature before 0.10.0: a rate of 0 for a linear table).
Reference: the table's line, by hand: 0 -> 10 deg over 0 -> 1 s, then on at 10 deg/s."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from loadcases.run import run_file

CASE = """\
case: table-motion
mechanism:
  gravity: [0, -9.81, 0]
  tables:
    lift: {x: "[0, 0.5, 1] s", y: "[0, 5, 10] deg", interpolation: INTERPOLATION,
           extrapolate: linear}
  bodies:
    arm: {mass: 2, cm: [0.5, 0, 0], inertia: [0.01, 0.2, 0.2]}
  joints:
    hinge: {type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 0, 1]}
motions:
  drive: {joint: hinge, value: "table(lift, t)"}
analysis: {type: kinematic, end: 2.0, step: 0.1}
requests:
  angle: {joint: hinge, quantity: angle}
  rate: {joint: hinge, quantity: omega}
  acceleration: {joint: hinge, quantity: alpha}
"""


@pytest.mark.parametrize("interpolation", ["linear", "akima", "cubic"])
def test_a_table_motion_beyond_its_data(tmp_path: Path, interpolation: str) -> None:
    """Angle, rate and acceleration at 0 to 2 s: 10 deg/s throughout (the three points lie
    on one line, so every interpolation is that line), to 1e-9."""
    path = tmp_path / "table.case.yaml"
    path.write_text(CASE.replace("INTERPOLATION", interpolation), encoding="utf-8")
    sol = run_file(path, output_dir=tmp_path / "out")[0].solution
    assert sol.ok, sol.message
    slope = math.radians(10.0)  # rad/s
    assert np.abs(sol.channels["angle.value"] - slope * sol.time).max() < 1e-9
    assert np.abs(sol.channels["rate.value"] - slope).max() < 1e-9
    assert np.abs(sol.channels["acceleration.value"]).max() < 1e-9
    assert sol.time[-1] == pytest.approx(2.0)
