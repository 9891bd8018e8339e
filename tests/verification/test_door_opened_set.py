"""Door library: the opened-door load sweep (door_opened.set.yaml, thesis seed 000 sections
1.5.4, 4.4, appendix A). Hand statics of one of its loads, three men standing (900 N on
each step): moment balance about the hinge line gives the wire, force balance of the door
and yoke gives the hinge resultant."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from loadcases.sets.specs import load_and_compile_set

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"
G = 9.81
HINGE_YZ = np.array([-0.06, 0.0])
MASS = 132.2  # kg: door 120, yoke 8 and the 4.2 kg of links, shafts, handles, rods


def test_opened_set_has_the_sixteen_loads():
    runs = load_and_compile_set(DOOR / "door_opened.set.yaml").runs
    assert len(runs) == 16  # 9 running + 3 men + 2 wind + 2 CB arm + 2 CB handle
    assert len({r.name for r in runs}) == 16


def test_three_men_standing_hinge_and_wire_by_hand_statics():
    """Door pose from two door points (cm and wire point); steps 1-3 at (y, z) = (-50,
    1240 / 840 / 440) mm in door axes. Wire tension from the moment balance about the
    hinge line of gravity (132.2 kg lumped at the door cm), the three 900 N loads and the
    CB rod (model force): tolerance 2 % (the lumping). Hinge fwd + aft = -(weights + men +
    wire + CB rod on the door) in y and z: tolerance 0.5 %."""
    ch = run_case(
        load_case(
            DOOR / "opened.case.yaml",
            overrides={"man_load": 0.0, "man_step": 0.0, "three_men": 1.0},
        )
    ).solution.channels
    yz = lambda name: np.array([ch[f"{name}.y"][0], ch[f"{name}.z"][0]])  # noqa: E731
    cm, wire_pt, cb_pt = yz("door_cm"), yz("wire_door"), yz("cb_door_point")
    local_cm, local_wire = np.array([-0.040, 0.840]), np.array([-0.050, 1.200])
    d_g, d_l = wire_pt - cm, local_wire - local_cm
    a = np.arctan2(d_g[1], d_g[0]) - np.arctan2(d_l[1], d_l[0])
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    steps = [cm + rot @ (np.array([-0.050, z]) - local_cm) for z in (1.240, 0.840, 0.440)]

    def moment(p, f):  # about the hinge line, axis -x (opening sense)
        r = np.asarray(p) - HINGE_YZ
        return -(r[0] * f[1] - r[1] * f[0])

    u = (np.array([0.0, 1.65]) - wire_pt) / np.linalg.norm(np.array([0.0, 1.65]) - wire_pt)
    cb = np.array([ch["cb_rod.fy"][0], ch["cb_rod.fz"][0]])  # on the rod from the door
    loads = moment(cm, [0.0, -MASS * G]) + sum(moment(s, [0.0, -900.0]) for s in steps)
    loads += moment(cb_pt, -cb)
    tension = -loads / moment(wire_pt, u)
    assert ch["wire.value"][0] == pytest.approx(tension, rel=0.02)

    hinge = np.array(
        [
            ch["hinge_fwd.fy"][0] + ch["hinge_aft.fy"][0],
            ch["hinge_fwd.fz"][0] + ch["hinge_aft.fz"][0],
        ]
    )
    applied = np.array([0.0, -MASS * G - 3 * 900.0]) + ch["wire.value"][0] * u - cb
    assert hinge == pytest.approx(-applied, rel=0.005, abs=0.005 * np.linalg.norm(applied))
