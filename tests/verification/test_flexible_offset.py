"""Offset attachments on a flexible body (issue 13, seed 003 3.4.2.1): a point given on
`BODY.POINT` (an interface point's node) away from the node is carried by a rigid arm from
it, so a force there reaches the node as the same force plus its moment.

References (closed forms, the beam's section constants from Roark for the torsion constant):
- static: a clamped 0.8 m, 30 x 10 mm aluminium cantilever, 5 N along z at the end of a
  100 mm arm along y from the tip: the tip deflects P L^3/(3 E I) + P L/(k G A) and twists
  by P e L/(G J); the arm's end rises by e * twist more than the tip;
- dynamic: a 1 kg mass on a 100 mm arm along x beyond the tip of a light cantilever (beam
  mass 0.65 g) under gravity vibrates at omega = 1/sqrt(m c), with c = (L^3/3 + a L^2 +
  a^2 L)/(E I) the compliance at the mass (tip force P and moment P a); without the arm
  (c = L^3/(3 E I)) it would be 19 % faster.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from tests.loadcases.test_flexible_yaml import CASE, LIBRARY

E, NU = 70e9, 0.33
G = E / (2.0 * (1.0 + NU))
L, WIDTH, HEIGHT = 0.8, 0.03, 0.01
IY = WIDTH * HEIGHT**3 / 12.0
AREA = WIDTH * HEIGHT
A_, B_ = WIDTH / 2.0, HEIGHT / 2.0  # Roark: J = a b^3 (16/3 - 3.36 b/a (1 - b^4/12a^4))
J = A_ * B_**3 * (16.0 / 3.0 - 3.36 * B_ / A_ * (1.0 - B_**4 / (12 * A_**4)))

ARM = """\
  points:
    arm_end: {body: beam.tip, at: [800, 100, 0]}"""
STATIC = (
    CASE.replace("{extra_body}", ARM).replace("point: beam.tip, value", "point: arm_end, value")
    + "  arm: {point: arm_end, quantity: position}\n"
)

MASS = """\
    mass: {mass: 1.0, cm: [900, 0, 0], inertia: [1e-8, 1e-8, 1e-8]}
  points:
    mass_cm: {body: mass, at: [900, 0, 0]}"""
WELD = "    weld: {type: fixed, bodies: [mass, beam.tip], at: [900, 0, 0]}\n"
DYNAMIC = (
    CASE.replace("{extra_body}", MASS)
    .replace("units: {length: mm}", "units: {length: mm}\n  gravity: [0, 0, -9.81]")
    .replace("2700 kg/m^3", "2.7 kg/m^3")
    .replace("elements: 8", "elements: 1")
    .replace("fixed_interface_modes: 6", "fixed_interface_modes: 0")
    .replace(
        "at: [0, 0, 0]}\n",
        "at: [0, 0, 0]}\n    weld: {type: fixed, bodies: [mass, beam.tip], at: [900, 0, 0]}\n",
        1,
    )
    .replace("value: [0, 0, 5]", "value: [0, 0, 0]")
    .replace(
        "analysis: {type: static}",
        "analysis: {type: dynamic, end: 0.3, step: 0.002, tolerance: 2.0e-6}",
    )
    + "  mass: {point: mass_cm, quantity: position}\n"
)


def _run(tmp_path: Path, text: str) -> dict[str, np.ndarray]:
    """The channels of the case `text`, with its output times as `time` (s)."""
    path = tmp_path / "offset.case.yaml"
    path.write_text(text, "utf-8")
    solution = run_case(load_case(path)).solution
    return {"time": np.asarray(solution.time), **solution.channels}


def test_static_force_on_an_offset_arm_bends_and_twists_the_beam(tmp_path: Path) -> None:
    """Tip deflection and twist from the arm's moment within 1e-3 of the closed forms
    (measured 8.2e-5 and 6.4e-5: the floating frame's second-order geometry)."""
    channels = _run(tmp_path, STATIC)
    P, e = 5.0, 0.1
    bending = P * L**3 / (3 * E * IY) + P * L / (5.0 / 6.0 * G * AREA)
    twist = P * e * L / (G * J)
    assert channels["tip.z"][0] == pytest.approx(bending, rel=1e-3)
    measured = (channels["arm.z"][0] - channels["tip.z"][0]) / e
    assert measured == pytest.approx(twist, rel=1e-3)
    assert abs(measured / twist - 1.0) < 2e-4  # regression guard at the measured 6.4e-5


def test_mass_on_an_offset_arm_vibrates_at_the_closed_form(tmp_path: Path) -> None:
    """Released under gravity from the design position, the mass oscillates about its
    static deflection m g c at omega = 1/sqrt(m c) (the beam's own mass, 0.65 g, neglected):
    the mean period of the zero crossings within 1e-3 at tolerance 2e-6 (measured 6.6e-4).
    The integrator's error at that tolerance, converging with it: 1.07e-3 at 3e-6, 2.9e-4 at
    1e-6 since a step change carries the integrator's own velocity with the step
    (rules.constraint_velocity; 9.6e-4 and 2.5e-4 before, 1.2e-4 at 3e-7, where the
    neglected beam mass and the arm's second-order geometry remain)."""
    channels = _run(tmp_path, DYNAMIC)
    t, z = channels["time"], channels["mass.z"]
    compliance = (L**3 / 3 + 0.1 * L**2 + 0.1**2 * L) / (E * IY)
    swing = z + 9.81 * compliance
    i = np.flatnonzero(np.diff(np.sign(swing)))
    crossings = t[i] - swing[i] * (t[i + 1] - t[i]) / (swing[i + 1] - swing[i])
    omega = np.pi / float(np.mean(np.diff(crossings)))
    assert len(crossings) >= 3
    assert omega * np.sqrt(compliance) == pytest.approx(1.0, rel=1e-3)
    assert abs(omega * np.sqrt(compliance) - 1.0) < 7e-4  # regression guard at the measured


def test_a_point_neither_at_a_node_nor_carried_by_one_is_an_input_error(
    tmp_path: Path,
) -> None:
    """The message names the key, the nearest interface point and how to attach to it."""
    with pytest.raises(InputError, match=r"name the body 'beam\.tip'") as error:
        _run(tmp_path, STATIC.replace("body: beam.tip, at", "body: beam, at"))
    assert "points.arm_end.at" in str(error.value.diagnostics[0])


def test_with_flexibility_off_the_node_names_the_rigid_body(tmp_path: Path) -> None:
    """`effects: {flexibility: false}`: `beam.tip` is the (clamped) rigid beam itself, so the
    arm's end stays at its design position (to round-off) while the load acts on it."""
    channels = _run(
        tmp_path, STATIC.replace("analysis:", "effects: {flexibility: false}\nanalysis:")
    )
    assert abs(channels["arm.z"][0]) < 1e-12 and channels["arm.y"][0] == pytest.approx(0.1)


def test_a_cable_loop_that_cannot_be_built_is_an_input_error(tmp_path: Path) -> None:
    """Regression: a request on a cable loop whose joints share two bodies was an internal
    error (KeyError while reading the request's units) instead of the loop's own message."""
    case = LIBRARY / "verification" / "elements" / "cable_loop.case.yaml"
    path = tmp_path / "ccl.case.yaml"
    path.write_text(case.read_text().replace("bodies: [yoke, ground]", "bodies: [yoke, panel]"))
    with pytest.raises(InputError, match="sharing exactly one body"):
        run_case(load_case(path))
