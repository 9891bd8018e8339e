"""Contact friction in quasi-static runs (no velocities): it opposes the travel between
consecutive equilibria, as joint_friction and seal do. A ball riding on a carriage (free to
drop along z) rests on a plane with its weight and is dragged along x and back: the drive
force is -/+ mu m g. Source: Coulomb's law F_t = mu F_N; tolerance 1e-3 relative."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from loadcases.run import run_file

MASS, MU, G = 2.0, 0.3, 9.81

CASE = f"""\
case: drag
mechanism:
  gravity: [0, 0, -{G}]
  bodies:
    carriage: {{mass: 1.0, cm: [0, 0, 0.01], inertia: [1.0e-3, 1.0e-3, 1.0e-3]}}
    ball: {{mass: {MASS}, cm: [0, 0, 0.01], inertia: [1.0e-5, 1.0e-5, 1.0e-5]}}
  joints:
    slide: {{type: prismatic, bodies: [carriage, ground], at: [0, 0, 0.01], axis: [1, 0, 0]}}
    drop: {{type: prismatic, bodies: [ball, carriage], at: [0, 0, 0.01], axis: [0, 0, 1]}}
  contacts:
    floor:
      type: impact
      bodies: [ball, ground]
      geometry: {{shape: sphere_plane, center: [0, 0, 0.01], radius: 0.01004,
                  plane_point: [0, 0, 0], normal: [0, 0, 1]}}
      stiffness: 1.0e8
      exponent: 1.5
      damping: 1.0e4
      depth: 1.0e-4
      friction: {{model: coulomb, mu_dynamic: {MU}}}
motions:
  drag: {{joint: slide, value: "0.05 * sin(pi * t)"}}
analysis: {{type: quasi-static, end: 2.0, step: 0.1}}
requests:
  drive: {{motion: drag, quantity: force}}
  floor: {{contact: floor, quantity: force}}
"""


def test_quasi_static_contact_friction_opposes_the_travel(tmp_path: Path) -> None:
    path = tmp_path / "drag.case.yaml"
    path.write_text(CASE, encoding="utf-8")
    sol = run_file(path, output_dir=tmp_path / "out")[0].solution
    assert sol.ok, sol.message
    ch, t = sol.channels, sol.time
    assert np.allclose(ch["floor.normal"], MASS * G, rtol=1e-3)  # F_N = m g
    drive = ch["drive.value"] if "drive.value" in ch else ch["drive.f"]
    going, back = (t > 0.05) & (t < 0.45), (t > 0.55) & (t < 1.45)
    # the carriage drags the ball against mu m g going out (+x), the other way coming back
    assert np.allclose(np.abs(drive[going]), MU * MASS * G, rtol=1e-3)
    assert np.allclose(np.abs(drive[back]), MU * MASS * G, rtol=1e-3)
    assert np.sign(drive[going][0]) == -np.sign(drive[back][0])
    assert drive[0] == pytest.approx(0.0, abs=1e-6)  # the first state has no travel yet
