"""The normal force of a contact split into its elastic and damping parts (seed 004 fig.
5.13), against the Hertz / Lankarani-Nikravesh law by hand.

Case (written here): a ball driven along x at the constant speed v = 1 mm/s from the
centre of its socket (clearance c = 0.5 mm, kinematic analysis), so that it enters the
wall at t0 = c / v = 0.5 s and the penetration is delta = v (t - t0), its rate v, and the
approach speed the law divides by is v too. Closed form (seed 004 eqs. 3.6-3.8, A.16):
elastic = K delta^1.5, damping = K delta^1.5 * 3 (1 - e^2) / 4 * (v / v) = 0.5625 x
elastic at e = 0.5, and normal = elastic + damping. Tolerance 1e-9 relative (the motion is
prescribed: nothing is integrated); apart (t < t0) both parts are 0.
"""

from __future__ import annotations

import numpy as np
import pytest

K, R, C, V, E = 1.0e10, 0.01, 5.0e-4, 1.0e-3, 0.5

CASE = f"""
case: split-closed-form
mechanism:
  name: pushed-ball
  gravity: [0, 0, 0]
  bodies:
    ball:   {{mass: 0.2, cm: [0, 0, 0], inertia: [8.0e-6, 8.0e-6, 8.0e-6]}}
    socket: {{mass: 0.3, cm: [0, 0, 0], inertia: [3.0e-5, 3.0e-5, 3.0e-5]}}
  joints:
    hold:  {{type: fixed, bodies: [socket, ground], at: [0, 0, 0]}}
    slide: {{type: prismatic, bodies: [ball, ground], at: [0, 0, 0], axis: [1, 0, 0]}}
  contacts:
    rod_end:
      type: hertz
      bodies: [ball, socket]
      geometry: {{shape: sphere_in_sphere, center: [0, 0, 0], radius: {R}, clearance: {C}}}
      stiffness: {K}
      restitution: {E}
motions:
  push: {{joint: slide, value: "{V} * t"}}
analysis: {{type: kinematic, end: 0.6, step: 0.01}}
requests:
  contact: {{contact: rod_end, quantity: force}}
  split:   {{contact: rod_end, quantity: force_split}}
  depth:   {{contact: rod_end, quantity: penetration}}
"""


@pytest.fixture(scope="module")
def outcome(tmp_path_factory: pytest.TempPathFactory):
    from conftest import estimate_off

    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    path = tmp_path_factory.mktemp("split") / "split.case.yaml"
    path.write_text(CASE)
    result = run_case(estimate_off(load_case(path)))
    assert result.solution.ok, result.solution.message
    return result


def test_split_closed_form(outcome) -> None:
    ch = outcome.solution.channels
    t = np.asarray(outcome.solution.time)
    delta = np.maximum(V * t - C, 0.0)
    assert np.asarray(ch["depth.value"]) == pytest.approx(delta, rel=1e-9, abs=1e-15)
    elastic = K * delta**1.5
    damping = 0.75 * (1 - E * E) * elastic
    assert np.asarray(ch["split.elastic"]) == pytest.approx(elastic, rel=1e-9, abs=1e-9)
    assert np.asarray(ch["split.damping"]) == pytest.approx(damping, rel=1e-9, abs=1e-9)
    assert np.asarray(ch["contact.normal"]) == pytest.approx(elastic + damping, rel=1e-9)
    assert elastic[-1] == pytest.approx(1.0e4, rel=1e-6)  # 0.1 mm in: the case bites
    assert outcome.column_units["split.elastic"] == "N"
    assert outcome.column_units["split.damping"] == "N"


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        (  # a wear depth without a wear law
            "  depth:   {contact: rod_end, quantity: penetration}",
            "  depth:   {contact: rod_end, quantity: wear_depth}",
            "requests.depth.quantity: contact 'rod_end' has no wear law",
        ),
        (  # a wear law on a contact that is not a clearance joint
            "geometry: {shape: sphere_in_sphere, center: [0, 0, 0], radius: 0.01, "
            "clearance: 0.0005}",
            "geometry: {shape: sphere_plane, center: [0, 0, 0], radius: 0.01, "
            "plane_point: [0, -0.02, 0], normal: [0, 1, 0]}\n"
            "      wear: {coefficient: 1.0e-4, hardness: 2 GPa, track_width: 2 mm}",
            "contacts.rod_end.wear: a wear law needs a clearance joint",
        ),
    ],
)
def test_wear_input_errors_name_the_key(tmp_path, old: str, new: str, expected: str) -> None:
    """Bad wear input is an input error at its file, line and key (exit 2 in the CLI)."""
    from loadcases.foundation.diagnostics import InputError
    from loadcases.inputs.loader import load_case

    assert old in CASE, old
    path = tmp_path / "bad.case.yaml"
    path.write_text(CASE.replace(old, new))
    with pytest.raises(InputError) as caught:
        load_case(path)
    messages = [d.format() for d in caught.value.diagnostics if d.severity == "error"]
    assert any(expected in m and "bad.case.yaml:" in m for m in messages), messages
