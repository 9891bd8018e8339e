"""Door library (loadcases/library/door) against the spreadsheet-style hand checks of the
thesis (seed 000, sections 4.2, 4.4, 4.5): lever ratio of the jammed rod, moment balance of
the opened door, initial angular acceleration of the jettison. Tolerances are stated per test."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import estimate_off

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"
G = 9.81  # m/s^2, as door.mech.yaml
HINGE_YZ = np.array([-0.06, 0.0])  # m: hinge line (y, z)


def _run(name: str):
    outcome = run_case(estimate_off(load_case(DOOR / name)))
    assert outcome.solution.ok, outcome.solution.message
    return outcome.solution.channels


def test_jammed_rod_p2p6_is_the_lever_ratio():
    """No gravity: rod force = F r_handle / (moment arm of the rod line about the inner
    handle pivot), at every latch angle; source: statics of the handle; tolerance 0.1 %."""
    ch = _run("jam_outer_handle_no_gravity.case.yaml")
    pivot = np.column_stack([ch[f"inner_pivot.{c}"] for c in "xyz"])  # moves with the door
    p2 = np.column_stack([ch[f"p2.{c}"] for c in "xyz"])
    p6 = np.column_stack([ch[f"p6.{c}"] for c in "xyz"])
    u = (p2 - p6) / np.linalg.norm(p2 - p6, axis=1)[:, None]
    arm = np.linalg.norm(np.cross(p2 - pivot, u), axis=1)
    expected = 1334.0 * 0.200 / arm
    assert np.allclose(ch["rod_p2p6.f"], expected, rtol=1e-3)


def test_opened_door_hinge_moment_balance():
    """Opened door: the moments about the hinge line of gravity (door 120 kg and yoke 8 kg;
    links and shafts 4 kg lumped at the door cm), the man (1000 N on step 2), the wire and
    the CB rod vanish; the hinge resultant balances all forces. Source: hand statics of the
    opened door (thesis 4.4); tolerance 2 % (the 4 kg lumped)."""
    ch = _run("opened.case.yaml")
    theta = float(ch["hinge_angle.value"][0])
    assert np.degrees(theta) == pytest.approx(102.0, abs=1.5)

    def moment(point_yz, force_yz):  # about the hinge line, axis -x (opening sense)
        r = np.asarray(point_yz) - HINGE_YZ
        return -(r[0] * force_yz[1] - r[1] * force_yz[0])

    cm = np.array([ch["door_cm.y"][0], ch["door_cm.z"][0]])
    wire_pt = np.array([ch["wire_door.y"][0], ch["wire_door.z"][0]])
    frame = np.array([0.0, 1.65])
    u = (frame - wire_pt) / np.linalg.norm(frame - wire_pt)
    tension = float(ch["wire.value"][0])
    cb_pt = np.array([ch["cb_door_point.y"][0], ch["cb_door_point.z"][0]])
    cb = np.array([ch["cb_rod.fy"][0], ch["cb_rod.fz"][0]])  # on the rod from the door
    step2 = cm  # step 2 is at the door cm height, 10 mm inboard: arm as the cm
    gravity = moment(cm, [0.0, -124.0 * G]) + moment(step2, [0.0, -1000.0])
    wire = moment(wire_pt, tension * u)
    rod = moment(cb_pt, -cb)
    assert gravity + wire + rod == pytest.approx(0.0, abs=0.02 * abs(gravity))


def test_jettison_initial_angular_acceleration():
    """alpha(0) = (aero moment 2400 N*m + gravity moment) / inertia about the hinge line
    (aero moment: the CFD table's force normal to the door at 0 deg, 2699 N, at the lifted
    centre of airload 0.889 m above the hinge line: 2399.6 N*m)
    of the door, yoke and the parts on the door, door lifted 49.15 mm. Source: thesis 4.5
    (spreadsheet alpha = M / I); tolerance 3 % (small parts lumped)."""
    ch = _run("jettison.case.yaml")
    lift = 0.04915
    door_r2 = (-0.04 + 0.06) ** 2 + (0.84 + lift) ** 2
    yoke_r2 = (-0.07 + 0.06) ** 2 + 0.6**2
    inertia = 25.7 + 124.0 * door_r2 + 1.2 + 8.0 * yoke_r2  # kg*m^2
    gravity = 124.0 * G * 0.02 - 8.0 * G * 0.01  # N*m, opening sense
    alpha = (2400.0 + gravity) / inertia
    k = int(np.searchsorted(ch["time"], 0.003)) if "time" in ch else 2
    assert ch["top_acceleration.y"][k] == pytest.approx(alpha, rel=0.03)
