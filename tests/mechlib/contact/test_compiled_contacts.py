"""Primitive contacts packed for the compiled Newton loop (mechlib.elements.contact.group in
mechlib.elements.compiled_forces): the packed loads and wear rates equal the elements' own
(the Python path) to round-off, and a ball rattling in its socket takes the same steps with
the same results on both paths."""

from __future__ import annotations

import numpy as np
import pytest

from mechlib.elements import compiled_forces as cf
from mechlib.elements.compiled_forces import CompiledForces, element_rates, element_wrenches
from mechlib.elements.contact import (
    Contact,
    HertzLaw,
    ImpactLaw,
    SpherePlane,
    revolute_clearance,
    spherical_clearance,
)
from mechlib.kinematics import constraint_arrays as ca
from tests.mechlib.contact._contact_models import FRICTION, K_STEEL, posed_pair

_NO_ROWS, _NO_ACTIVE = np.zeros((0, 21)), np.zeros(0, dtype=np.int64)


def _elements():
    return [
        spherical_clearance(
            "c", ("ball", "socket"), center=(0, 0, 0), radius=0.01, clearance=5e-4,
            law=HertzLaw(K_STEEL, 1.5, 0.5), friction=FRICTION,
        ),
        revolute_clearance(
            "c", ("ball", "socket"), center=(0, 0, 0), axis=(0, 0, 1), radius=0.01,
            clearance=5e-4, law=HertzLaw(K_STEEL, 1.5, 0.5),
        ),
        Contact(
            "c", ("ball", "socket"), SpherePlane((0, 0, 0), 0.01, (0, -0.01, 0), (0, 1, 0)),
            ImpactLaw(1e9, 1.5, damping=1e3, depth=1e-5), FRICTION,
        ),
    ]  # fmt: skip


@pytest.mark.parametrize("which", range(3))
@pytest.mark.parametrize("moving", [True, False])
def test_packed_contact_loads_equal_the_elements_own(which: int, moving: bool) -> None:
    """A ball in its socket (Hertz, Stribeck friction), a pin in its hole (Hertz), a sphere
    on a plane (impact law with its damping ramp, Stribeck): the packed wrench equals
    System.wrenches within 1e-12 of the largest load, moving and at rest (the static
    friction from the anchor of the last accepted state), and a clearance joint's packed
    wear rate equals its state_rates."""
    element = _elements()[which]
    system, q, qd = posed_pair(element, gravity=9.81, seed=5)
    element.approach = 0.05
    element.commit(system.view(system.kin(q - 1e-6, qd, 0.0)))  # an anchor to slip from
    if not moving:
        qd = np.zeros_like(qd)
    k = system.kin(q, qd, 0.0)
    packed = CompiledForces.of(system)
    assert packed is not None and packed.contacts == [element]
    packed.refresh(system)
    F, N = system.wrenches(k)
    x, xd = ca.state_arrays(q, qd, system.nb)
    F2, N2 = np.empty_like(F), np.empty_like(N)
    z = system.states.z
    element_wrenches(x, xd, z, packed.args, _NO_ROWS, _NO_ACTIVE, np.zeros(0), F2, N2)
    scale = np.abs(F).max() + np.abs(N).max()
    assert scale > 1e-3
    np.testing.assert_allclose(F2[:-1], F[:-1], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(N2[:-1], N[:-1], rtol=0, atol=1e-12 * scale)
    if system.states:
        mine = np.zeros(system.states.z.size)
        element_rates(x, xd, z, packed.args, mine)
        own = system.states.rates(system.view(k), z)
        assert (own[0] > 0.0) == moving
        np.testing.assert_allclose(mine, own, rtol=1e-13, atol=0.0)


def test_profile_contacts_keep_the_python_path() -> None:
    """A contact without a primitive geometry has no packed form: `of` gives None."""
    element = _elements()[2]
    system, _, _ = posed_pair(element, gravity=9.81, seed=5)
    element._kernel = None  # as a profile contact's bind leaves it
    assert CompiledForces.of(system) is None


def _python_of(original):
    def of(cls, system):
        packed = original(cls, system)
        return None if packed is not None and packed.contacts else packed

    return classmethod(of)


def test_socket_rattle_equals_the_python_path(tmp_path, monkeypatch) -> None:
    """The bench's steel ball rattling in its socket (Hertz, restitution 0.8, 0.02 s at
    tolerance 1e-7: impacts against the wall): the compiled Newton loop takes the same
    steps, rejections and Newton iterations as the Python step (the contacts unpacked),
    and its signals agree to 1e-9 of their range (round-off of the Newton iterates)."""
    from benchmarks.models import model_by_name
    from benchmarks.suite import _case_copy
    from loadcases.run import run_file

    case = _case_copy(model_by_name("socket_rattle"), 0.02, 1e-7, tmp_path, "steps")
    solutions = []
    for python in (False, True):
        if python:
            original = cf.CompiledForces.of.__func__
            monkeypatch.setattr(cf.CompiledForces, "of", _python_of(original))
        sol = run_file(case, output_dir=tmp_path / str(python))[0].solution
        assert sol.ok, sol.message
        solutions.append(sol)
    fast, slow = solutions
    for field in ("steps", "rejected_steps", "newton_iterations"):
        assert getattr(fast.stats, field) == getattr(slow.stats, field), field
    assert fast.stats.rejected_steps > 0  # the impacts are in the run
    np.testing.assert_array_equal(fast.time, slow.time)
    for name, values in slow.channels.items():
        values = np.asarray(values)
        span = np.ptp(values) if values.size else 0.0
        np.testing.assert_allclose(fast.channels[name], values, rtol=0, atol=1e-9 * span + 1e-300)
