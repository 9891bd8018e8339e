"""The coordinate equations evaluated as one block (mechlib.kinematics.coordinate_block) against the
same equations evaluated one by one (mechlib.kinematics.coordinates,
mechlib.kinematics.curve_joint): phi,
gradient rows and gamma at generic states with rates, past +-pi for the unwrapping, and
after a lock adds an equation. Same arithmetic in another order: agreement to 1e-12."""

from __future__ import annotations

import numpy as np
import pytest

import mechlib
from mechlib.system.system import System

from ._models import Ramp
from .test_joints import AT, KEYS

TOL = 1e-12


def _mechanism() -> mechlib.Mechanism:
    """A screw, a point on a curve, two cranks coupled by a gear and one driven: every
    kind of coordinate equation, angle and travel measures, one measure in two equations."""
    mech = mechlib.Mechanism()
    for name, cm in (("nut", (0.3, -0.2, 0.5)), ("bead", (0.2, 0.1, 0.0))):
        mech.add_body(name, mass=1.0, cm=cm, inertia=[0.1, 0.2, 0.3])
    mech.add_joint("S", "screw", bodies=("nut", "ground"), at=AT, **KEYS["screw"])
    mech.add_joint(
        "C", "point_on_curve", bodies=("bead", "ground"), at=AT, **KEYS["point_on_curve"]
    )
    for i, z in ((1, 0.0), (2, 1.0)):
        mech.add_body(f"b{i}", mass=1.0, cm=(0.5, 0.0, z), inertia=[0.1, 0.2, 0.3])
        mech.add_joint(
            f"R{i}", "revolute", bodies=(f"b{i}", "ground"), at=(0.0, 0.0, z), axis=(0.0, 0.0, 1.0)
        )
    mech.add_joint("K", "gear", bodies=("b1", "b2"), joints=("R1", "R2"), ratio=2.0)
    mech.add_motion("drive", joint="R1", function=Ramp(0.3, 2.0))
    return mech


def _one_by_one(system: System, k) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    eqs = system.coordinates
    return (
        np.array([e.phi(k) for e in eqs]),
        np.array([e.gradient(k) for e in eqs]),
        np.array([e.gamma(k) for e in eqs]),
    )


def _block(system: System, k) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    block = system.coordinate_rows()
    rows = np.zeros((block.size, k.ncol))
    block.jacobian(k, rows)
    return block.phi(k), rows, block.gamma(k)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_block_matches_equations(seed: int) -> None:
    system = System(_mechanism())
    rng = np.random.default_rng(seed)
    q = system.design_q() + 0.3 * rng.standard_normal(system.nq)
    qd = rng.standard_normal(system.nq)
    k = system.kin(q, qd, 0.7)
    for m in system.angle_measures:  # unwrap against references a turn or more away
        m.reference = float(rng.choice([-7.0, 0.0, 7.0]))
    for one, block in zip(_one_by_one(system, k), _block(system, k)):
        assert block.shape == one.shape
        assert np.abs(block - one).max() < TOL * max(1.0, np.abs(one).max())


def test_block_follows_a_lock() -> None:
    """A lock appends an equation: the block is rebuilt and includes it."""
    system = System(_mechanism())
    k = system.kin(system.design_q(), np.zeros(system.nq), 0.0)
    before = system.coordinate_rows().size
    system.lock("R2", k)
    assert system.coordinate_rows().size == before + 1
    q = system.design_q() + 0.1
    k = system.kin(q, np.ones(system.nq), 0.2)
    for one, block in zip(_one_by_one(system, k), _block(system, k)):
        assert np.abs(block - one).max() < TOL * max(1.0, np.abs(one).max())


def test_system_rows_use_the_block() -> None:
    """phi, phi_q and gamma of the system carry the block's rows last."""
    system = System(_mechanism())
    k = system.kin(system.design_q() + 0.05, np.ones(system.nq), 0.1)
    phi, rows, gamma = _one_by_one(system, k)
    n = len(phi)
    assert np.abs(system.phi(k)[-n:] - phi).max() < TOL
    assert np.abs(system.phi_q(k)[-n:] - system.body_columns(rows)).max() < TOL
    assert np.abs(system.gamma(k)[-n:] - gamma).max() < TOL
    both = system.phi_and_jacobian(k)
    assert np.abs(both[0] - system.phi(k)).max() == 0.0
    assert np.abs(both[1] - system.phi_q(k)).max() == 0.0
