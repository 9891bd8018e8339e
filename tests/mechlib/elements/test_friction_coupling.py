"""dQ/dlam of joint friction (the reaction coupling of the iteration matrix): each joint
type's `reaction_jacobian` -- compiled for a moving revolute or cylindrical joint
(mechlib.elements.friction_kernel), Python at rest and on prismatic and spherical joints --
against forward differences of the friction loads over the multipliers
(mechlib.system.reaction_loads.differenced_coupling), at moving and resting states with
multipliers that load every joint (at rest: displaced from the last accepted equilibrium,
so that the friction opposes a slip)."""

from __future__ import annotations

import numpy as np
import pytest

import mechlib
from mechlib.system.reaction_loads import differenced_coupling

from .._models import Bar, hinged_bar


@pytest.mark.parametrize("joint_type", ["revolute", "cylindrical", "prismatic", "spherical"])
@pytest.mark.parametrize("moving", [True, False], ids=["moving", "at-rest"])
def test_friction_coupling_against_differences(joint_type: str, moving: bool) -> None:
    """Within 1e-6 of the largest entry (forward differences of 1e-7 relative; the loads
    are linear in the multipliers but for |F_r|, whose curvature the differences see)."""
    mech = hinged_bar(Bar(), joint_type=joint_type)
    mech.add_force(mechlib.JointFriction("rub", "hinge", 0.2, 0.01, 0.5))
    system = mechlib.System(mech)
    friction = mech.forces["rub"]
    rng = np.random.default_rng(3)
    q = system.design_q()
    friction.begin(system.view(system.kin(q, np.zeros(system.nq), 0.0)))
    if moving:
        k = system.kin(q, rng.normal(scale=0.3, size=system.nq), 0.0)
    else:  # displaced from where the slip is measured (the last accepted equilibrium)
        k = system.kin(q + rng.normal(scale=1e-3, size=system.nq), np.zeros(system.nq), 0.0)
    lam = rng.normal(scale=50.0, size=system.active.size)
    jac = system.phi_q(k)
    out = np.zeros((system.nq, lam.size))
    friction.reaction_jacobian(system.view(k, lam, jac), out)
    reference = differenced_coupling(system, k, lam, [friction], jac)
    scale = np.abs(reference).max()
    assert scale > 1e-3  # the friction is loaded by its reaction
    assert np.abs(out - reference).max() <= 1e-6 * scale
