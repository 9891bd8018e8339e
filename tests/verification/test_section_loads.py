"""Section loads (`sections:` of a mechanism, `{section: NAME}` requests) against the
split-body model an analyst builds by hand (seed 000, 5.5): the shaft cut in two bodies
joined by a fixed joint at the section, the joint's reaction in the shaft's axes. The shaft
turns about x on a revolute at its root (gravity along -z, its cm off the axis), a force at
its tip, swinging freely (dynamic). Part a (root side, x < 0.3 m): 1 kg, cm (0.15, 0, 0) m;
part b (tip side): 2 kg, cm (0.45, 0.01, 0) m. The shaft as one body has their sum (mass 3
kg, cm (0.35, 0.02/3, 0) m, the inertia about it by the parallel axis theorem, written out
below). Section loads = split-body reaction to 1e-9 of the peak; the one-body shaft swings
as the split one (angle to 1e-5 rad, measured 1.6e-6: both are integrated to the same
tolerance but with other unknowns)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import estimate_off

from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from loadcases.sets.precheck import file_problems

I_A = np.diag([0.001, 0.008, 0.008])
I_B = np.array([[0.002, 0.001, 0.0], [0.001, 0.015, 0.0], [0.0, 0.0, 0.016]])
C_A, C_B = np.array([0.15, 0.0, 0.0]), np.array([0.45, 0.01, 0.0])
M_A, M_B = 1.0, 2.0
C = (M_A * C_A + M_B * C_B) / 3.0


def _shift(m, d):
    return m * (d @ d * np.eye(3) - np.outer(d, d))


I_SHAFT = I_A + _shift(M_A, C_A - C) + I_B + _shift(M_B, C_B - C)  # about C, kg*m^2


def _six(t):
    six = (t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2])
    return "[" + ", ".join(repr(float(x)) for x in six) + "]"


def _vec(v):
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


COMMON = """\
gravity: [0, 0, -9.81]
points:
  tip: {body: %(tip)s, at: [0.6, 0, 0]}
joints:
  root: {type: revolute, bodies: [%(root)s, ground], at: [0, 0, 0], axis: [1, 0, 0]}
%(weld)sforces:
  push: {type: force, point: tip, value: [0, "20*sin(8*t)", -15], frame: ground}
"""
ONE = (
    "name: one\nbodies:\n"
    f"  shaft: {{mass: 3.0, cm: {_vec(C)}, inertia: {_six(I_SHAFT)}}}\n"
    + COMMON
    % {"tip": "shaft", "root": "shaft", "weld": ""}
    + "sections:\n  hole: {body: shaft, at: [0.3, 0, 0], normal: [1, 0, 0], side: [0.5, 0, 0],\n"
    f"         mass: {M_B}, cm: {_vec(C_B)}, inertia: {_six(I_B)}}}\n"
)
SPLIT = (
    "name: split\nbodies:\n"
    f"  a: {{mass: {M_A}, cm: {_vec(C_A)}, inertia: {_six(I_A)}}}\n"
    f"  b: {{mass: {M_B}, cm: {_vec(C_B)}, inertia: {_six(I_B)}}}\n"
    + COMMON
    % {"tip": "b", "root": "a", "weld": "  weld: {type: fixed, bodies: [b, a], at: [0.3, 0, 0]}\n"}
)
CASE = """\
case: %(name)s
mechanism: %(name)s.mech.yaml
initial: {root: {value: 20 deg, rate: 3 rad/s}}
analysis: {type: dynamic, end: 0.6, step: 0.01, tolerance: 1e-8}
requests:
  angle: {joint: root, quantity: angle}
  cut: %(request)s
"""


def _run(folder, name, mech, request):
    (folder / f"{name}.mech.yaml").write_text(mech, encoding="utf-8")
    path = folder / f"{name}.case.yaml"
    path.write_text(CASE % {"name": name, "request": request}, encoding="utf-8")
    outcome = run_case(estimate_off(load_case(path)))
    assert outcome.solution.ok, outcome.solution.message
    assert outcome.request_kinds["cut"] == "reaction"  # charted among the loads, as the weld's
    return outcome.solution.channels, outcome.column_units


def test_section_loads_are_the_split_body_reaction(tmp_path):
    one, units = _run(tmp_path, "one", ONE, "{section: hole}")
    split, _ = _run(tmp_path, "split", SPLIT, "{joint: weld, quantity: force, frame: a}")
    assert units["cut.fx"] == "N" and units["cut.tx"] == "N*m"
    assert np.allclose(one["angle.value"], split["angle.value"], rtol=0.0, atol=1e-9)
    for group in (("fx", "fy", "fz"), ("tx", "ty", "tz")):
        peak = max(np.abs(split[f"cut.{c}"]).max() for c in group)
        for c in group:
            assert np.allclose(one[f"cut.{c}"], split[f"cut.{c}"], rtol=0.0, atol=1e-9 * peak), c
    assert np.abs(one["cut.ty"]).max() > 1.0  # a real bending moment, not a trivial zero


def test_one_body_swings_as_the_split_one(tmp_path):
    """The one-body shaft's inertia (the parts' sum above) moves as the two parts welded."""
    one, _ = _run(tmp_path, "one", ONE, "{joint: root, quantity: force}")
    split, _ = _run(tmp_path, "split", SPLIT, "{joint: root, quantity: force}")
    # measured 1.6e-6 rad after 4 rad (each run's own integration error at tolerance 1e-8);
    # 1e-3 of the shaft's moment of inertia about x wrong would move it by ~4e-3 rad
    assert np.abs(one["angle.value"] - split["angle.value"]).max() < 1e-5
    assert np.ptp(one["angle.value"]) > 0.5


@pytest.mark.parametrize(
    ("old", "new", "wanted", "expected"),
    [
        ("mass: 2.0,", "mass: 3.5,", "{section: hole}", "sections.hole.mass: the kept part's"),
        ("", "", "{section: hol}", "requests.cut.section: unknown section 'hol'"),
        (
            "forces:\n",
            "forces:\n  spin: {type: torque, body: shaft, value: [1, 0, 0]}\n",
            "{section: hole}",
            "forces.spin: holds body 'shaft' without a point",
        ),
    ],
)
def test_bad_sections_are_input_errors(tmp_path, old, new, wanted, expected):
    (tmp_path / "one.mech.yaml").write_text(ONE.replace(old, new, 1), encoding="utf-8")
    path = tmp_path / "one.case.yaml"
    path.write_text(CASE % {"name": "one", "request": wanted}, encoding="utf-8")
    messages = [d.format() for d in file_problems(path) if d.severity == "error"]
    assert any(expected in m for m in messages), messages


def test_door_latch_shaft_at_its_bolt_hole():
    """The door's example (door.mech.yaml `latch_bolt_hole`, 50 mm fwd of the shaft centre;
    kept: the fwd end, 0.5 kg at 100 mm, carrying P6), closed (t = 0: rod P2P6 vertical, its
    crank 34.4 mm from the latch axis horizontally), by the statics of the kept end: axial
    and shear from the rod and the end's weight, torsion = rod x 34.4 mm (the torque the
    shaft carries), bending about y = rod and weight x 50 mm. Tolerance 1e-9 relative."""
    door = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"
    cf = estimate_off(load_case(door / "jam_outer_handle.case.yaml"))
    outcome = run_case(cf)
    assert outcome.solution.ok, outcome.solution.message
    ch = {k: v[0] for k, v in outcome.solution.channels.items()}
    rod, weight = ch["rod_p2p6.f"], 0.5 * 9.81
    assert ch["shaft_hole.fz"] == pytest.approx(rod + weight, rel=1e-9)
    assert ch["shaft_hole.tx"] == pytest.approx(rod * 0.0344, rel=1e-9)
    assert ch["shaft_hole.ty"] == pytest.approx(-0.05 * (rod + weight), rel=1e-9)
    assert abs(ch["shaft_hole.fx"]) + abs(ch["shaft_hole.tz"]) < 1e-6
