"""Door library: the side loads on the CB arm and the CB handle of the opened door
(door_opened.set.yaml rows 13-16, thesis seed 000, 1.5.4; 300 N fwd / aft, a chosen value:
the thesis gives none) and the path they take: the CB arm's pivot on the fuselage (a
revolute about x) takes the side force and its moment (force x arm); no door force changes,
because the side load has no moment about the pivot axis and the CB rod (spherical at the
arm, universal at the door, both in the plane x = 300 mm) carries no force along x."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"
SIDE = 300.0  # N (door.mech.yaml side_load)
PIVOT = np.array([0.300, -0.300, 0.200])  # m, cb_pivot (fuselage)
# hand arms: distance of the load point from the pivot axis (x), design values of
# door.mech.yaml (the arm turns about x, so its distance from the axis does not change):
# arm mid (300, -450, 300): sqrt(150^2 + 100^2) = 180.28 mm; grip (300, -700, 150):
# sqrt(400^2 + 50^2) = 403.11 mm
ARMS = {"cb_arm_mid": np.hypot(0.150, 0.100), "cb_grip": np.hypot(0.400, 0.050)}
DOOR_FORCES = ("hinge_fwd", "hinge_aft", "cb_rod")


def _opened(**overrides: float):
    outcome = run_case(load_case(DOOR / "opened.case.yaml", overrides=overrides))
    assert outcome.solution.ok, outcome.solution.message
    return outcome.solution.channels


@pytest.mark.parametrize(
    ("where", "point", "base"),
    [
        ("side_arm", "cb_arm_mid", {"man_step": 1.0, "man_load": 900.0}),  # one man on step 1
        ("side_handle", "cb_grip", {"man_step": 0.0, "man_load": 0.0}),
    ],
)
def test_side_load_goes_into_the_cb_pivot_as_force_times_arm(where, point, base):
    """Fwd (+1) and aft (-1): at the CB pivot (reaction on the arm from the fuselage)
    fx = -side x 300 N; moment = -(r x F) about the pivot with r to the load point, of size
    300 N x the hand arm (54.08 N*m on the arm, 120.93 N*m at the grip, 1e-6); no moment
    about the pivot axis; hinges, CB rod and wire as without the side load (1e-9)."""
    plain = _opened(**base)
    for side in (1.0, -1.0):
        ch = _opened(**base, **{where: side})
        assert ch["cb_pivot.fx"][0] == pytest.approx(-side * SIDE, rel=1e-9)
        r = np.array([ch[f"{point}.{c}"][0] for c in "xyz"]) - PIVOT
        expected = -np.cross(r, [side * SIDE, 0.0, 0.0])
        moment = np.array([ch[f"cb_pivot.t{c}"][0] for c in "xyz"])
        assert moment == pytest.approx(expected, abs=1e-6)
        assert np.linalg.norm(moment) == pytest.approx(SIDE * ARMS[point], rel=1e-6)
        assert abs(moment[0]) < 1e-9
        for name in DOOR_FORCES:
            for c in ("fx", "fy", "fz"):
                key = f"{name}.{c}"
                assert ch[key][0] == pytest.approx(plain[key][0], rel=1e-9, abs=1e-9)
        assert ch["wire.value"][0] == pytest.approx(plain["wire.value"][0], rel=1e-9)
        # the pivot's other components are those of the plain case (the CB rod force)
        for c in ("fy", "fz"):
            key = f"cb_pivot.{c}"
            assert ch[key][0] == pytest.approx(plain[key][0], rel=1e-9)
