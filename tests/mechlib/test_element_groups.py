"""Force elements of one type in one call (mechlib.elements.groups): the motion two groups of
linear springs and torsion springs produce against closed forms, and a group's loads
against those its members give on their own, with members switched off or left out."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.elements.groups import SpringGroup, TorsionSpringGroup

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


def _hanging(driven: bool) -> ml.Mechanism:
    """Two bars (2 kg, 1 m) on hinges to ground, each held up by its own linear torsion
    spring, and two blocks (1.5 kg) on vertical slides, each hung on its own vertical spring
    from ground (free length 1 m); gravity -y. With `driven`, ramps drive every joint."""
    from ._models import Ramp

    mech = ml.Mechanism(name="hanging", gravity=(0.0, -9.81, 0.0))
    for i, k in enumerate(STIFFNESS[:2]):
        z = float(i)
        mech.add_body(f"bar{i}", mass=2.0, cm=(0.5, 0.0, z), inertia=[1e-3, 2 / 12, 2 / 12])
        mech.add_joint(f"h{i}", "revolute", bodies=(f"bar{i}", "ground"), at=(0, 0, z),
                       axis=(0, 0, 1))  # fmt: skip
        mech.add_force(ml.TorsionSpring(f"t{i}", f"h{i}", stiffness=k))
        mech.add_body(f"block{i}", mass=1.5, cm=(3.0, 0.0, z), inertia=[1e-2] * 3)
        mech.add_joint(f"s{i}", "prismatic", bodies=(f"block{i}", "ground"), at=(3, 0, z),
                       axis=(0, 1, 0))  # fmt: skip
        ends = ((f"block{i}", (3.0, 0.0, z)), ("ground", (3.0, 1.0, z)))
        mech.add_force(ml.Spring(f"k{i}", ends, stiffness=10 * k, free_length=1.0))
        if driven:
            mech.add_motion(f"m{i}", joint=f"h{i}", function=Ramp(-0.1, 0.3))
            mech.add_motion(f"n{i}", joint=f"s{i}", function=Ramp(-0.2, 0.1))
    return mech


def test_grouped_springs_hold_the_static_equilibrium() -> None:
    """Static: each bar rests where k theta = -m g L/2 cos(theta) (brentq), each block
    where 10 k (-travel) = m g (the spring stretched by the weight); to 1e-8. One group of
    each type."""
    from scipy.optimize import brentq

    mech = _hanging(driven=False)
    assert len(ml.System(mech)._groups) == 2
    sol = ml.solve(
        mech,
        ml.Static(),
        requests=[ml.JointCoordinate(f"a{i}", f"h{i}") for i in range(2)]
        + [ml.JointCoordinate(f"x{i}", f"s{i}", "travel") for i in range(2)],
    )
    assert sol.ok, sol.message
    for i, k in enumerate(STIFFNESS[:2]):
        theta = brentq(lambda a, k=k: k * a + 2.0 * 9.81 * 0.5 * math.cos(a), -1.5, 0.0, xtol=1e-14)
        assert sol.channels[f"a{i}.value"][0] == pytest.approx(theta, abs=1e-8)
        assert sol.channels[f"x{i}.value"][0] == pytest.approx(-1.5 * 9.81 / (10 * k), abs=1e-8)


@pytest.mark.parametrize("analysis", ["kinematic", "quasi-static"])
def test_grouped_springs_load_the_motions_that_drive_them(analysis: str) -> None:
    """Ramps at constant rate drive every joint: a bar's motion carries k theta + m g L/2
    cos(theta) (constant rate: no angular acceleration, the centripetal force passes
    through the hinge), a block's 10 k travel + m g (constant speed); to 1e-8 of the
    largest (kinematic: inverse dynamics; quasi-static: equilibria along the ramps)."""
    mech = _hanging(driven=True)
    spec = (ml.Kinematic if analysis == "kinematic" else ml.QuasiStatic)(end=1.0, step=0.25)
    requests = [ml.MotionEffort(f"m{i}", f"m{i}") for i in range(2)]
    requests += [ml.MotionEffort(f"n{i}", f"n{i}") for i in range(2)]
    sol = ml.solve(mech, spec, requests=requests)
    assert sol.ok, sol.message
    t = sol.time
    for i, k in enumerate(STIFFNESS[:2]):
        theta, travel = -0.1 + 0.3 * t, -0.2 + 0.1 * t
        torque = k * theta + 2.0 * 9.81 * 0.5 * np.cos(theta)
        force = 10 * k * travel + 1.5 * 9.81
        np.testing.assert_allclose(sol.channels[f"m{i}.value"], torque, rtol=0, atol=1e-8 * 30)
        np.testing.assert_allclose(sol.channels[f"n{i}.value"], force, rtol=0, atol=1e-8 * 200)
