"""Flexible bodies in a planar mechanism (issue 36): built as the 3-D system with its
geometry in the plane (mechlib.system.planar.make_system).

References: the same four-bar with a flexible coupler written in 3-D (no `plane`), whose
motion the planar file must reproduce (1e-9 relative: the same equations); the static tip
deflection of a horizontal cantilever under its own weight in the plane, w L^4/(8 E I)
(Euler-Bernoulli, Roark table 8.1 case 2a), within the modal truncation (1e-3).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

FOURBAR = """\
case: planar-flex-fourbar
mechanism:
  units: {length: mm}
  plane: xy
  gravity: [0, -9.81, 0]
  bodies:
    crank: {mass: 0.5, cm: [0, 50, 0], inertia: [0.001, 0.001, 0.001]}
    rocker: {mass: 0.8, cm: [345, 140, 0], inertia: [0.004, 0.004, 0.008]}
    coupler:
      flexible:
        beam:
          start: [0, 100, 0]
          end: [240, 280, 0]
          section: {width: 10, height: 4}
          material: {E: 70 GPa, nu: 0.33, rho: 2700 kg/m^3}
          elements: 6
        interface: {b: [0, 100, 0], c: [240, 280, 0]}
        fixed_interface_modes: 4
  joints:
    crank_pivot: {type: revolute, bodies: [crank, ground], at: [0, 0, 0], axis: [0, 0, 1]}
    pin_b: {type: revolute, bodies: [coupler.b, crank], at: [0, 100, 0], axis: [0, 0, 1]}
    pin_c: {type: revolute, bodies: [coupler.c, rocker], at: [240, 280, 0], axis: [0, 0, 1]}
    rocker_pivot: {type: revolute, bodies: [rocker, ground], at: [450, 0, 0], axis: [0, 0, 1]}
analysis: {type: dynamic, end: 0.02, step: 0.005}
requests:
  c: {point: coupler.c, quantity: position}
  crank: {joint: crank_pivot, quantity: angle}
  modal: {flexible: coupler, quantity: modes}
"""

CANTILEVER = """\
case: planar-flex-cantilever
mechanism:
  units: {length: mm}
  plane: xy
  gravity: [0, -9.81, 0]
  bodies:
    beam:
      flexible:
        beam:
          start: [0, 0, 0]
          end: [800, 0, 0]
          section: {width: 30, height: 10, shear: false}
          material: {E: 70 GPa, nu: 0.33, rho: 2700 kg/m^3}
          elements: 8
        interface: {root: [0, 0, 0], tip: [800, 0, 0]}
        fixed_interface_modes: 6
  joints:
    clamp: {type: fixed, bodies: [beam.root, ground], at: [0, 0, 0]}
analysis: {type: static}
requests:
  tip: {point: beam.tip, quantity: position}
"""


def _run(tmp_path: Path, text: str, name: str = "flex"):
    path = tmp_path / f"{name}.case.yaml"
    path.write_text(text, "utf-8")
    return run_case(load_case(path)).solution


def test_planar_fourbar_with_flexible_coupler_moves_as_in_3d(tmp_path: Path) -> None:
    """The planar file and the same file in 3-D give the same motion and modal
    coordinates (1e-9 of each channel's peak); nothing leaves the plane (the out-of-plane
    modes stay unloaded: c.z and their coordinates below 1e-12 of the in-plane ones)."""
    planar = _run(tmp_path, FOURBAR, "planar")
    space = _run(tmp_path, FOURBAR.replace("  plane: xy\n", ""), "space").channels
    channels = planar.channels
    assert set(channels) == set(space)
    for name, values in channels.items():
        peak = max(float(np.abs(space[name]).max()), 1e-300)
        assert np.abs(np.asarray(values) - space[name]).max() <= 1e-9 * peak, name
    assert abs(channels["crank.value"][-1]) > 1e-3  # it moved under gravity
    modal = np.array([channels[n] for n in channels if n.startswith("modal.q")])
    peaks = np.abs(modal).max(axis=1)
    assert peaks.max() > 1e-7  # the in-plane modes deform
    assert np.abs(channels["c.z"]).max() < 1e-12 * 0.24
    assert (peaks < 1e-12 * peaks.max()).sum() >= 3  # out-of-plane modes at rest


def test_planar_cantilever_tip_under_own_weight(tmp_path: Path) -> None:
    """0.8 m, 30 x 10 mm aluminium (10 mm in the plane), clamped, its weight along -y:
    tip deflection w L^4 / (8 E I), w = rho A g, to 1e-3 (modal truncation, floating
    frame), and nothing along z."""
    channels = _run(tmp_path, CANTILEVER).channels
    E, rho, g, width, height, L = 70e9, 2700.0, 9.81, 0.03, 0.01, 0.8
    w, inertia = rho * width * height * g, width * height**3 / 12.0
    exact = w * L**4 / (8.0 * E * inertia)
    assert -channels["tip.y"][0] == pytest.approx(exact, rel=1e-3)
    assert abs(channels["tip.z"][0]) < 1e-12


@pytest.mark.parametrize(
    ("old", "new", "key", "message"),
    [
        (
            "c: [240, 280, 0]}\n        fixed",
            "c: [240, 280, 5]}\n        fixed",
            "mechanism.bodies.coupler.flexible.interface.c",
            "point 'c' is 0.005 m off the body's plane along z: it would leave plane xy",
        ),
        (
            "end: [240, 280, 0]",
            "end: [240, 280, 30]",
            "mechanism.bodies.coupler.flexible.beam.end",
            "the beam leaves plane xy: its ends differ along the normal",
        ),
        (
            "elements: 6\n",
            "elements: 6\n          y_axis: [0, 1, 1]\n",
            "mechanism.bodies.coupler.flexible.beam.y_axis",
            "the section's y_axis must be along the normal of plane xy (z) or lie in the plane",
        ),
    ],
)
def test_flexible_body_out_of_the_plane_refused_at_its_key(
    tmp_path: Path, old: str, new: str, key: str, message: str
) -> None:
    """Each refusal names the file, line, column and key."""
    assert old in FOURBAR
    path = tmp_path / "off.case.yaml"
    path.write_text(FOURBAR.replace(old, new), "utf-8")
    with pytest.raises(InputError) as raised:
        load_case(path)
    text = str(raised.value)
    line = next(t for t in text.splitlines() if key in t)
    assert line.startswith(f"{path}:") and f"error: {key}: {message}" in line
    assert line.split(":")[1].isdigit() and line.split(":")[2].isdigit()
