"""Force elements of one type in one call (mechlib.element_groups): the motion two groups of
linear springs and torsion springs produce against closed forms, and a group's loads
against those its members give on their own, with members switched off or left out."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.element_groups import SpringGroup, TorsionSpringGroup

STIFFNESS = (30.0, 80.0, 55.0)  # N*m/rad (bars), N/m (blocks)


def _oscillators() -> ml.Mechanism:
    """Three bars on parallel hinges to ground, each held by its own linear torsion spring,
    and three blocks on prismatic joints, each on its own linear spring to ground; no
    gravity. The third of each is switched off (an inactive element)."""
    mech = ml.Mechanism(name="oscillators", gravity=(0.0, 0.0, 0.0))
    for i, k in enumerate(STIFFNESS):
        z = float(i)
        mech.add_body(f"bar{i}", mass=2.0, cm=(0.5, 0.0, z), inertia=[1e-3, 2 / 12, 2 / 12])
        mech.add_joint(f"h{i}", "revolute", bodies=(f"bar{i}", "ground"), at=(0, 0, z),
                       axis=(0, 0, 1))  # fmt: skip
        spring = ml.TorsionSpring(f"t{i}", f"h{i}", stiffness=k)
        spring.active = i < 2
        mech.add_force(spring)
        mech.add_body(f"block{i}", mass=1.5, cm=(3.0, 0.0, z), inertia=[1e-2] * 3)
        mech.add_joint(f"s{i}", "prismatic", bodies=(f"block{i}", "ground"), at=(3, 0, z),
                       axis=(1, 0, 0))  # fmt: skip
        ends = ((f"block{i}", (3.0, 0.0, z)), ("ground", (2.0, 0.0, z)))
        spring = ml.Spring(f"k{i}", ends, stiffness=k, free_length=1.0)
        spring.active = i < 2
        mech.add_force(spring)
    return mech


def test_grouped_springs_swing_at_their_own_frequencies() -> None:
    """Released at 0.3 rad and 0.02 m: theta_i = 0.3 cos(sqrt(k_i / I_end) t) and x_i =
    0.02 cos(sqrt(k_i / m) t) for the springs that act, the switched-off ones keep their
    start; over two periods of the slowest, to 3e-4 of the amplitude (generalized-alpha at
    tolerance 1e-8; measured 2.0e-4 at most, a phase error of the integrator: the same
    without groups, 1e-5 at tolerance 1e-10). The system holds one group of each type."""
    mech = _oscillators()
    system = ml.System(mech)
    assert sorted(type(g).__name__ for g in system._groups) == ["SpringGroup", "TorsionSpringGroup"]
    inertia, mass = 2.0 / 3.0, 1.5
    end = 2 * 2 * math.pi / math.sqrt(STIFFNESS[0] / inertia)
    sol = ml.solve(
        mech,
        ml.Dynamic(end=end, step=end / 400, tolerance=1e-8),
        requests=[ml.JointCoordinate(f"a{i}", f"h{i}") for i in range(3)]
        + [ml.JointCoordinate(f"x{i}", f"s{i}", "travel") for i in range(3)],
        initial=[ml.InitialValue(f"h{i}", value=0.3) for i in range(3)]
        + [ml.InitialValue(f"s{i}", value=0.02) for i in range(3)],
    )
    assert sol.ok, sol.message
    t = sol.time
    for i, k in enumerate(STIFFNESS):
        theta = 0.3 * (np.cos(math.sqrt(k / inertia) * t) if i < 2 else 1.0)
        travel = 0.02 * (np.cos(math.sqrt(k / mass) * t) if i < 2 else 1.0)
        assert np.abs(sol.channels[f"a{i}.value"] - theta).max() < 3e-4 * 0.3, i
        assert np.abs(sol.channels[f"x{i}.value"] - travel).max() < 3e-4 * 0.02, i


@pytest.mark.parametrize("damping", [0.0, 3.0])
def test_a_group_adds_what_its_members_add_on_their_own(damping: float) -> None:
    """At random turned and moving states, with members switched off and members left out
    (`skip`, as the differenced tangent does), each group's loads equal the sum of its
    active members' own `apply` (1e-13 of the largest)."""
    mech = _oscillators()
    for element in mech.forces.values():
        element.damping = damping
        element.active = True
    system = ml.System(mech)
    rng = np.random.default_rng(5)
    members = {type(g): g for g in system._groups}
    for trial in range(6):
        q = system.design_q() + rng.normal(scale=0.1, size=system.nq)
        qd = rng.normal(scale=0.5, size=system.nq)
        k = system.kin(q, qd, 0.0)
        for group in (members[SpringGroup], members[TorsionSpringGroup]):
            group.members[trial % 3].active = trial % 2 == 0
            skip = {id(group.members[(trial + 1) % 3])} if trial >= 3 else set()
            F, N = np.zeros((system.nb + 1, 3)), np.zeros((system.nb + 1, 3))
            group.apply(k.x, k.xd, skip, F, N)
            F1, N1 = np.zeros_like(F), np.zeros_like(N)
            view = system.view(k)
            for element in group.members:
                if element.active and id(element) not in skip:
                    element.apply(view, F1, N1)
            scale = max(np.abs(F1).max(), np.abs(N1).max(), 1.0)
            assert np.abs(F - F1).max() <= 1e-13 * scale
            assert np.abs(N - N1).max() <= 1e-13 * scale
