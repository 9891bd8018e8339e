"""System.is_active follows every change of the active equations: a held coordinate's
hold and let-go (a joint friction sticking and slipping), a lock (a latch), a snapshot
restored. Reference: membership of the row in `system.active` itself."""

from __future__ import annotations

import mechlib as ml
from mechlib.system.planar import make_system


def _arm() -> ml.Mechanism:
    mech = ml.Mechanism(gravity=(0.0, -9.81, 0.0))
    mech.add_body("arm", mass=1.0, cm=(1.0, 0, 0), inertia=[1e-3, 1e-3, 1e-3])
    mech.add_joint("hinge", "revolute", bodies=("arm", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    return mech


def test_is_active_follows_the_active_equations() -> None:
    system = make_system(_arm())
    k = system.kin(system.design_q(), None, 0.0)
    row = system.held_coordinate("hinge", system.measure("hinge", "angle"))  # dormant
    rows = range(row + 1)

    def agrees() -> bool:
        return [system.is_active(r) for r in rows] == [r in set(system.active) for r in rows]

    assert not system.is_active(row) and agrees()
    before = system.snapshot()
    system.hold(row, k)
    assert system.is_active(row) and agrees()
    system.let_go(row)
    assert not system.is_active(row) and agrees()
    system.hold(row, k)
    system.restore_snapshot(before)  # the rows of the snapshot, without the held one
    assert not system.is_active(row) and agrees()
    system.lock("hinge", k)
    assert system.is_active(row + 1) and agrees()
    assert not system.is_active(row + 5)  # no such equation
