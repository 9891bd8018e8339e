"""Door library: the jettison lever on a fuselage shaft (thesis seed 000, 3.1.5.2: "a little
lever on shaft attached to the fuselage is pushing on a roller attached to a shaft on the
door"), door_fuselage_lever.mech.yaml and lifting_fuselage_lever.case.yaml, against hand
statics of the lever and of the inner handle shaft (force x arm)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import estimate_off

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"
# design geometry in (y, z), mm (door.mech.yaml): pivots, roller centre, lever face normal
JETTISON_PIVOT = np.array([-80.0, 650.0])
INNER_PIVOT = np.array([-80.0, 700.0])
ROLLER = np.array([-120.958, 728.679])
FACE_NORMAL = np.array([0.887011, 0.461749])
# inner handle weight moment about its pivot: 0.6 kg x 9.81 m/s^2 x 0.06 m (cm 60 mm
# inboard of the pivot, door.mech.yaml)
HANDLE_WEIGHT_MOMENT = 0.6 * 9.81 * 0.060


def _arm(point: np.ndarray, pivot: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Lever arm about an axis along x of the line through point along direction (yz)."""
    r = point - pivot
    return np.abs(r[..., 0] * direction[..., 1] - r[..., 1] * direction[..., 0])


def _yz(ch, name: str) -> np.ndarray:
    return np.column_stack([ch[f"{name}.y"], ch[f"{name}.z"]])


def _moment(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Moment about -x (the positive sense of the handle joints) of force f at arm r (yz)."""
    return -(r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])


def test_design_lever_ratio_is_two_by_hand():
    """At design the roller's crank circle passes through the jettison pivot: the arms of the
    face normal through the roller centre about the two pivots are 88.70 and 44.35 mm, ratio
    2 (the inscribed angle; hand arithmetic on door.mech.yaml's numbers, 1e-3)."""
    arm_j = _arm(ROLLER, JETTISON_PIVOT, FACE_NORMAL)
    arm_i = _arm(ROLLER, INNER_PIVOT, FACE_NORMAL)
    assert arm_j == pytest.approx(88.70, abs=0.01) and arm_i == pytest.approx(44.35, abs=0.01)
    assert arm_j / arm_i == pytest.approx(2.0, rel=1e-3)


def test_fuselage_lever_ratio_by_hand_statics():
    """Lifting with the lever on its fuselage shaft, no airload, no pressure:
    - lever: handle effort = roller force x its arm about the fixed pivot (1e-6); the force
      lies along the face normal turned by the jettison angle (frictionless face, 1e-6);
    - inner handle shaft: roller force x its arm about the inner pivot = moment of rod P2P6
      at P2, up to the handle's own weight moment (0.6 kg x g x 60 mm = 0.353 N*m);
    - so effort = lever ratio x rod moment, the ratio = arm_j / arm_i from the positions.
    The ratio is 2 at design (test above) and grows as the roller rises with the door along
    the fixed face: 2.04 at 5 deg of latch, 3.28 lifted (measured; pinned 1.95-2.15 at the
    first contact state and 3.0-3.6 at the end). The latch reaches 110 deg."""
    ch = run_case(estimate_off(load_case(DOOR / "lifting_fuselage_lever.case.yaml"))).solution
    assert ch.ok, ch.message
    ch = ch.channels
    on = ch["roller.normal"] > 0.0
    assert not on[0] and on[1:].all()  # 0.2 mm clear at rest, in contact over the lift
    f = np.column_stack([ch["roller.fy"], ch["roller.fz"]])[on]  # on the roller
    c, pj = _yz(ch, "roller_point")[on], _yz(ch, "jettison_pivot")[on]
    pi = _yz(ch, "inner_pivot")[on]
    psi = ch["jettison_angle.value"][on]
    # the face normal turned by psi about -x
    n = np.column_stack(
        [
            FACE_NORMAL[0] * np.cos(psi) + FACE_NORMAL[1] * np.sin(psi),
            -FACE_NORMAL[0] * np.sin(psi) + FACE_NORMAL[1] * np.cos(psi),
        ]
    )
    size = np.linalg.norm(f, axis=1)
    assert np.allclose(f / size[:, None], n, atol=1e-6)
    arm_j, arm_i = _arm(c, pj, n), _arm(c, pi, n)
    effort = ch["handle_torque.value"][on]
    assert np.allclose(effort, size * arm_j, rtol=1e-6)
    assert np.allclose(effort, -_moment(c - pj, -f), rtol=1e-6)  # and in the pushing sense
    on_rod = np.column_stack([ch["rod_at_p2.fy"], ch["rod_at_p2.fz"]])[on]  # from the handle
    rod = _moment(_yz(ch, "p2")[on] - pi, -on_rod)  # the rod's moment on the inner handle
    assert np.all(np.abs(size * arm_i + rod) <= HANDLE_WEIGHT_MOMENT + 1e-6)
    ratio = arm_j / arm_i
    assert np.allclose(effort, -ratio * rod, atol=ratio * HANDLE_WEIGHT_MOMENT + 1e-6)
    assert 1.95 < ratio[0] < 2.15 and 3.0 < ratio[-1] < 3.6
    assert np.all(np.diff(ratio) > 0.0)
    assert np.degrees(ch["latch_angle.value"][-1]) == pytest.approx(110.0, abs=1.0)
