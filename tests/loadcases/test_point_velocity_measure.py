"""`vx(P)`, `vy(P)`, `vz(P)` in expressions: the global velocity of a point, for forces that
depend on a rate no joint carries (the door's aerodynamic damping c * omega about a hinge
line made of a spherical and an inline joint). Reference: a 1 m bar turning about z at
omega = 2 rad/s has its tip at (cos wt, sin wt, 0) m and velocity (-2 sin wt, 2 cos wt, 0)
m/s; a torque -c * omega built from the tip velocity on a free bar decays omega as
omega0 exp(-c t / I) (I about the hinge, c = 0.3 N*m*s/rad)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.run import run_file

BAR = """\
case: bar
mechanism:
  gravity: [0, 0, 0]
  bodies:
    bar: {mass: 2, cm: [0.5, 0, 0], inertia: [0.01, 0.2, 0.2]}
  points:
    tip: {body: bar, at: [1, 0, 0]}
  joints:
    hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}
MOTION
analysis: ANALYSIS
requests:
  vx: {expression: "vx(tip)"}
  vy: {expression: "vy(tip)"}
  vz: {expression: "vz(tip)"}
  omega: {joint: hinge, quantity: omega}
"""


def _run(tmp_path: Path, text: str):
    path = tmp_path / "bar.case.yaml"
    path.write_text(text, encoding="utf-8")
    return run_file(path, output_dir=tmp_path / "out")[0].solution


def test_point_velocity_of_a_turning_bar(tmp_path: Path) -> None:
    """Kinematic, omega = 2 rad/s: exact to 1e-9 m/s."""
    sol = _run(
        tmp_path,
        BAR.replace("MOTION", 'motions:\n  drive: {joint: hinge, value: "2 * t"}').replace(
            "ANALYSIS", "{type: kinematic, end: 1.0, step: 0.1}"
        ),
    )
    t = sol.time
    assert np.allclose(sol.channels["vx.value"], -2 * np.sin(2 * t), atol=1e-9)
    assert np.allclose(sol.channels["vy.value"], 2 * np.cos(2 * t), atol=1e-9)
    assert np.allclose(sol.channels["vz.value"], 0.0, atol=1e-9)


def test_damping_torque_from_point_velocity_decays_the_rate(tmp_path: Path) -> None:
    """Dynamic, free bar from omega0 = 3 rad/s with the torque -c (x vy - y vx) / r^2 of
    its tip (= -c omega): omega = omega0 exp(-c t / I), I = 0.2 + 2 * 0.5^2 = 0.7 kg m^2;
    tolerance 1e-3 relative (integration error)."""
    text = (
        BAR.replace("MOTION", "initial:\n  hinge: {rate: 3 rad/s}")
        .replace("ANALYSIS", "{type: dynamic, end: 1.0, step: 0.05, tolerance: 1.0e-8}")
        .replace(
            "  joints:",
            "  forces:\n    drag: {type: torque, body: bar, value: [0, 0, "
            '"-0.3 * (x(tip) * vy(tip) - y(tip) * vx(tip)) / (x(tip)^2 + y(tip)^2)"]}\n  joints:',
        )
    )
    sol = _run(tmp_path, text)
    expected = 3.0 * np.exp(-0.3 * sol.time / 0.7)
    assert np.allclose(sol.channels["omega.value"], expected, rtol=1e-3)


def test_velocity_of_an_unknown_point_is_an_input_error(tmp_path: Path) -> None:
    with pytest.raises(InputError) as caught:
        _run(
            tmp_path,
            BAR.replace('"vy(tip)"', '"vy(tpi)"')
            .replace("MOTION", 'motions:\n  drive: {joint: hinge, value: "2 * t"}')
            .replace("ANALYSIS", "{type: kinematic, end: 1.0, step: 0.1}"),
        )
    assert any("unknown point 'tpi'" in d.message for d in caught.value.diagnostics)
