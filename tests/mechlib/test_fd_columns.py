"""Forward-difference columns that leave out the elements they cannot change
(mechlib.system.fd_columns): each element's `state_bodies`, and the static stiffness and the
dynamic tangent equal, column by column, those that evaluate every element in every column.

Model: a chain of three bars a, b, c (hinges j1 ground-a, j2 a-b, j3 b-c, axes z) at a
perturbed, unbalanced pose with rates, loaded by a spring a-c, a torsion spring on j2, a
damper on j3, a bushing c-ground, a seal c-ground, a cable loop over j2 and j3, a force on c
whose value reads angle(j1) (a joint that does not touch c: body a's columns must see it), a
torque on b in c's axes, and a force on b reading the effort of the motion on j1 (never
left out). Reference: the same differences with no element left out but the skips every
column shares. They agree to the round-off of a difference quotient, the element forces
being summed in another order: 4 eps sum_e |Q_e| / h at the step h = 1e-7 (measured: 6e-7,
a seventh of it, in entries up to 2e4).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.core.outcome import SolverStats
from mechlib.solvers.genalpha.integrator import Integrator
from mechlib.solvers.static.balance import FD_STEP, Balance
from mechlib.system.fd_columns import ColumnSkips, element_bodies
from mechlib.system.system import System
from tests.mechlib._models import Ramp


def _chain() -> ml.Mechanism:
    mech = ml.Mechanism(name="chain", gravity=(0.0, -9.81, 0.0))
    for i, name in enumerate("abc"):
        mech.add_body(name, mass=1.0 + i, cm=(i + 0.5, 0.0, 0.0), inertia=[1e-3, 0.1, 0.1])
    for i, (one, two) in enumerate((("a", "ground"), ("b", "a"), ("c", "b"))):
        mech.add_joint(f"j{i + 1}", "revolute", bodies=(one, two), at=(i, 0, 0), axis=(0, 0, 1))
    mech.add_motion("drive", joint="j1", function=Ramp(0.0, 1.0))
    mech.add_frame("c_axes", body="c", x=(1, 1, 0), y=(0, 0, 1))
    mech.add_force(ml.Spring("spring", (("a", (0.5, 0.2, 0)), ("c", (2.5, 0.3, 0))), 1e3, 5.0))
    mech.add_force(ml.TorsionSpring("torsion", "j2", 50.0, 2.0, angle0=0.1, preload=3.0))
    mech.add_force(ml.RotationalDamper("damper", "j3", 4.0))
    mech.add_force(ml.Bushing("bushing", ("c", "ground"), (3, 0, 0), (1e3, 2e3, 3e3), (5, 6, 7)))
    mech.add_force(ml.Seal("seal", ("c", "ground"), (2.2, 0.1, 0), (2.8, 0.1, 0), (0, 1, 0)))
    mech.forces["seal"].stiffness = 1e4
    mech.add_force(ml.CableLoop("loop", ("j2", "j3"), (0.05, 0.04), 1e4, 100.0))

    def third_body(t, view):  # reads the angle of j1, which joins a to ground, not c
        return (0.0, 10.0 * math.cos(view.angle("j1")) + t, 3.0 * math.sin(view.angle("j1")))

    def effort(t, view):
        return (0.0, 0.0, 0.01 * view.effort("drive"))

    reads_j1 = [("angle", ("j1",))]
    mech.add_force(ml.PointForce("third", "c", (3, 0, 0), third_body, reads=reads_j1))
    mech.add_force(ml.PointTorque("torque", "b", lambda t, v: (1.0, 2.0, 3.0), "c_axes", reads=()))
    mech.add_force(
        ml.PointForce("effort", "b", (1.5, 0, 0), effort, reads=[("effort", ("drive",))])
    )
    return mech


def _state(system: System) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, qd, lam): the design pose turned about the hinges, arbitrary rates and
    multipliers (the tangent is a derivative anywhere, balanced or not)."""
    rng = np.random.default_rng(7)
    q = system.design_q().copy()
    for b in range(system.nb):
        q[7 * b + 3 : 7 * b + 7] += 0.05 * rng.standard_normal(4)
        q[7 * b + 3 : 7 * b + 7] /= np.linalg.norm(q[7 * b + 3 : 7 * b + 7])
        q[7 * b : 7 * b + 3] += 0.01 * rng.standard_normal(3)
    qd = rng.standard_normal(system.nq)
    lam = rng.standard_normal(system.phi(system.kin(q)).size)
    return q, qd, lam


def roundoff(system: System, k, lam: np.ndarray) -> float:
    """4 eps sum_e max |Q_e| / h: the round-off bound of a difference quotient of a sum of
    the element and modal-body forces Q_e (N or N*m) taken in another order (modal bodies'
    forces are left out of the columns that cannot change them, as elements are)."""
    view, total = system.view(k, lam), 0.0
    for element in system.elements:
        F, N = np.zeros((system.nb + 1, 3)), np.zeros((system.nb + 1, 3))
        element.apply(view, F, N)
        total += np.abs(system.generalized(k, F, N)).max()
    for body in system.flexible:
        total += np.abs(body.forces(k, system.gravity, False, None)).max()
    return 4.0 * np.finfo(float).eps * total / FD_STEP


class EveryColumn(ColumnSkips):
    """The reference: every column leaves out only `always` (and `extra`: a wrong skip)."""

    def __init__(self, system: System, always=frozenset(), extra=frozenset()):
        super().__init__(system, always)
        self._every = frozenset(always) | frozenset(extra)

    def skip(self, body: int) -> frozenset[int]:
        return self._every

    def inert(self, body: int) -> bool:
        return False  # every column evaluated


@pytest.fixture(scope="module")
def system() -> System:
    return System(_chain())


def test_state_bodies_of_each_element(system):
    a, b, c, ground = (system.body_index(n) for n in ("a", "b", "c", "ground"))
    expected = {
        "spring": {a, c},
        "torsion": {a, b},
        "damper": {b, c},
        "bushing": {c, ground},
        "seal": {c, ground},
        "loop": {a, b, c},
        "third": {a, c, ground},  # its body and j1's two bodies
        "torque": {b, c},  # its body and its frame's
        "effort": None,  # the multipliers and the whole Jacobian
    }
    found = {name: element_bodies(e) for name, e in system.mechanism.forces.items()}
    assert found == {n: None if v is None else frozenset(v) for n, v in expected.items()}


def test_the_third_body_and_the_effort_are_never_left_out(system):
    skips = ColumnSkips(system)
    forces = system.mechanism.forces
    a, b = system.body_index("a"), system.body_index("b")
    assert id(forces["third"]) not in skips.skip(a)  # angle(j1): a's columns change it
    assert id(forces["third"]) in skips.skip(b)
    assert id(forces["torque"]) in skips.skip(a)
    assert all(id(forces["effort"]) not in skips.skip(body) for body in (0, 1, 2, -1))
    assert {id(e) for e in system.elements if element_bodies(e) is not None} <= skips.skip(-1)


def test_static_stiffness_equals_every_element_in_every_column(system, monkeypatch):
    import mechlib.solvers.static.balance

    q, _, lam = _state(system)
    fast = Balance(system, 0.3, q).stiffness(q, lam)
    monkeypatch.setattr(mechlib.solvers.static.balance, "ColumnSkips", EveryColumn)
    full = Balance(system, 0.3, q).stiffness(q, lam)
    tol = roundoff(system, system.kin(q, None, 0.3), lam)
    assert np.abs(fast - full).max() <= tol
    # the check can fail: leaving the third-body force out of a's columns is seen there
    third = {id(system.mechanism.forces["third"])}
    monkeypatch.setattr(
        mechlib.solvers.static.balance, "ColumnSkips", lambda s, a: EveryColumn(s, a, third)
    )
    wrong = Balance(system, 0.3, q).stiffness(q, lam)
    a = system.body_index("a")
    assert np.abs(wrong - full)[:, 7 * a : 7 * a + 7].max() > 1e3 * tol


def test_dynamic_tangent_equals_every_element_in_every_column(system, monkeypatch):
    import mechlib.solvers.genalpha.integrator

    q, qd, lam = _state(system)
    k = system.kin(q, qd, 0.3)
    jac = system.phi_q(k)
    integrator = Integrator(system, ml.Dynamic(end=1.0, step=0.1), SolverStats())
    fast = integrator._differenced_tangent(k, [], lam, jac, 1e-3)
    monkeypatch.setattr(mechlib.solvers.genalpha.integrator, "ColumnSkips", EveryColumn)
    full = integrator._differenced_tangent(k, [], lam, jac, 1e-3)
    tol = roundoff(system, k, lam)
    for mine, reference in zip(fast, full):
        assert np.abs(mine - reference).max() <= tol
