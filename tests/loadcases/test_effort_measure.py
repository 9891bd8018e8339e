"""`effort(motion)` in expressions: a handle force as torque / lever arm, and the
'let go of the handle' event of the door thesis (section 4.1) when the effort turns
negative. Reference: a 2 kg bar of 1 m on a hinge lifted at 1 rad/s against gravity needs
T = m g (L/2) cos(theta) (constant speed: no inertia torque), which turns negative at
theta = pi/2, i.e. t = pi/2 s."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.run import run_file

CASE = """\
case: handle
mechanism:
  gravity: [0, -9.81, 0]
  bodies:
    bar: {mass: 2, cm: [0.5, 0, 0], inertia: [0.01, 0.2, 0.2]}
  joints:
    hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}
motions:
  drive: {joint: hinge, value: "1.0 * t"}
events:
  let_go: {when: "effort(drive) < 0", then: [{deactivate: drive}]}
analysis: {type: dynamic, end: 2.0, step: 0.01, tolerance: 1.0e-8}
requests:
  handle_force: {expression: "effort(drive) / 0.2"}     # N at a 200 mm grip
  torque: {motion: drive, quantity: torque}
"""


def test_handle_force_and_let_go(tmp_path: Path) -> None:
    path = tmp_path / "handle.case.yaml"
    path.write_text(CASE, encoding="utf-8")
    sol = run_file(path, output_dir=tmp_path / "out")[0].solution
    assert [e.name for e in sol.events] == ["let_go"]
    assert sol.events[0].time == pytest.approx(math.pi / 2, abs=1e-6)
    before = sol.time < math.pi / 2 - 1e-9
    expected = 2 * 9.81 * 0.5 * np.cos(sol.time[before]) / 0.2
    assert np.abs(sol.channels["handle_force.value"][before] - expected).max() < 1e-3 * 49.05
    assert np.allclose(
        sol.channels["handle_force.value"][before],
        sol.channels["torque.value"][before] / 0.2,
        rtol=1e-9,
        atol=1e-9,
    )
    assert np.all(sol.channels["torque.value"][sol.time > math.pi / 2 + 1e-9] == 0.0)


def test_effort_of_an_unknown_motion_is_an_input_error(tmp_path: Path) -> None:
    path = tmp_path / "bad.case.yaml"
    path.write_text(
        CASE.replace('expression: "effort(drive) / 0.2"', 'expression: "effort(drvie) / 0.2"'),
        encoding="utf-8",
    )
    with pytest.raises(InputError) as caught:
        run_file(path, output_dir=tmp_path / "out")
    assert [d.message for d in caught.value.diagnostics] == [
        "effort(drvie): no motion 'drvie' in this case"
    ]
