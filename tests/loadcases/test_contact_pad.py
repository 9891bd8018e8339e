"""A bounded plane (`extent`): a ball over the pad rests on it with contact force = weight;
the same ball beside the pad falls through freely (z = -g t^2 / 2)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from loadcases.run import run_file

CASE = """\
case: pad-{x}
mechanism:
  gravity: [0, 0, -9.81]
  bodies:
    ball: {{mass: 0.5, cm: [{x}, 0, 0.01], inertia: [1.0e-5, 1.0e-5, 1.0e-5]}}
  contacts:
    pad:
      type: impact
      bodies: [ball, ground]
      geometry: {{shape: sphere_plane, center: [{x}, 0, 0.01], radius: 0.01,
                  plane_point: [0, 0, 0], normal: [0, 0, 1], extent: 0.05}}
      stiffness: 1.0e6
      exponent: 1.0
      damping: 2000
      depth: 1.0e-6
analysis: {{type: dynamic, end: 0.5, step: 0.01}}
requests:
  z: {{point: c, quantity: position}}
  contact: {{contact: pad, quantity: force}}
"""


def _run(tmp_path: Path, x: float):
    text = CASE.format(x=x).replace(
        "  bodies:\n", f"  points: {{c: {{body: ball, at: [{x}, 0, 0.01]}}}}\n  bodies:\n", 1
    )
    path = tmp_path / f"pad{x}.case.yaml"
    path.write_text(text, encoding="utf-8")
    return run_file(path, output_dir=tmp_path / "out")[0].solution


def test_ball_on_the_pad_rests_with_its_weight(tmp_path: Path) -> None:
    """Contact force settles at m g within 0.1 % (static balance)."""
    sol = _run(tmp_path, 0.02)
    assert sol.ok
    assert sol.channels["contact.normal"][-1] == pytest.approx(0.5 * 9.81, rel=1e-3)


def test_ball_beside_the_pad_falls_freely(tmp_path: Path) -> None:
    """Outside the 50 mm pad there is no contact: free fall within 1e-6 m."""
    sol = _run(tmp_path, 0.2)
    assert sol.ok and np.all(sol.channels["contact.normal"] == 0.0)
    fall = 0.01 - 0.5 * 9.81 * sol.time**2
    assert np.abs(sol.channels["z.z"] - fall).max() < 1e-6
