"""The Python step's differenced tangent made by the compiled kernel
(mechlib.solvers.genalpha.applied_tangent) equals the Python differences of System.forces
(mechlib.solvers.genalpha.tangent) it replaces, quadratic velocity terms and the joint
frictions' reaction rows at the moved positions included.

Model: a chain of three bars a, b, c (hinges j1 ground-a, j2 a-b, j3 b-c, axes z; b's
inertia tensor full, not diagonal) at a perturbed, unbalanced pose with rates, loaded by a
spring a-c, a torsion spring on j2, a damper on j3 and a friction on j2 loaded by its
joint's reaction (mu 0.3, radius 0.02 m, preload 1 N*m, v_threshold 100 rad/s; all packed:
mechlib.elements.compiled_forces). Reference: the Python differences. Tolerance: the
round-off of a difference quotient of the forces summed in another order,
4 eps sum_e |Q_e| / h (tests/mechlib/test_fd_columns.py's `roundoff`).
"""

from __future__ import annotations

from typing import cast

import numpy as np
import pytest

import mechlib as ml
from mechlib.core.outcome import SolverStats
from mechlib.solvers.genalpha.integrator import Integrator
from mechlib.solvers.genalpha.tangent import differenced_tangent
from mechlib.system.fd_columns import ColumnSkips
from mechlib.system.system import System
from tests.mechlib.test_fd_columns import _state, roundoff


def _chain() -> ml.Mechanism:
    mech = ml.Mechanism(name="chain", gravity=(0.0, -9.81, 0.0))
    for i, name in enumerate("abc"):
        inertia = [1e-3, 0.1, 0.1 + i, 0.01, 0.02, 0.03] if i == 1 else [1e-3, 0.1, 0.1]
        mech.add_body(name, mass=1.0 + i, cm=(i + 0.5, 0.0, 0.0), inertia=inertia)
    for i, (one, two) in enumerate((("a", "ground"), ("b", "a"), ("c", "b"))):
        mech.add_joint(f"j{i + 1}", "revolute", bodies=(one, two), at=(i, 0, 0), axis=(0, 0, 1))
    mech.add_force(ml.Spring("spring", (("a", (0.5, 0.2, 0)), ("c", (2.5, 0.3, 0))), 1e3, 5.0))
    mech.add_force(ml.TorsionSpring("torsion", "j2", 50.0, 2.0, angle0=0.1, preload=3.0))
    mech.add_force(ml.RotationalDamper("damper", "j3", 4.0))
    # a wide regularised band (rad/s): the rates are inside it, the law's slope is in C
    mech.add_force(ml.JointFriction("rub", "j2", 0.3, 0.02, 1.0, v_threshold=100.0))
    return mech


@pytest.fixture(scope="module")
def tangents():
    system = System(_chain())
    q, qd, lam = _state(system)
    k = system.kin(q, qd, 0.3)
    jac = system.phi_q(k)
    integrator = Integrator(system, ml.Dynamic(end=1.0, step=0.1), SolverStats())
    assert system.compiled_forces() is not None and integrator.arrays is not None
    compiled = integrator._differenced_tangent(k, [], lam, jac, 1e-3)
    python = differenced_tangent(system, k, ColumnSkips(system), lam, jac, 1e-3)
    return compiled, python, roundoff(system, k, lam)


def test_the_compiled_tangent_equals_the_python_differences(tangents):
    compiled, python, tol = tangents
    for mine, reference in zip(compiled, python):
        assert np.abs(mine - reference).max() <= tol


def test_the_check_sees_the_velocity_terms_and_the_reaction_rows(tangents):
    """The compiled tangent holds the velocity terms and the friction's reaction: leaving
    either out of the Python differences moves them far above the tolerance (the moved
    reaction rows the kernel evaluates, as the Python forces do, are the same as the base
    ones here: a revolute joint's force rows are constant in q)."""
    compiled, _, tol = tangents
    system = System(_chain())
    q, qd, lam = _state(system)
    k = system.kin(q, qd, 0.3)
    jac = system.phi_q(k)
    skips = ColumnSkips(system)
    # no velocity terms (inertia=False): C differs by the gyroscopic part
    without = differenced_tangent(cast(System, _Inertialess(system)), k, skips, lam, jac, 1e-3)
    assert np.abs(without[1] - compiled[1]).max() > 1e3 * tol
    # no multipliers: the friction's preload alone, C differs by its reaction's part (the
    # regularised law's slope in the slip rate scales with the capacity)
    unloaded = differenced_tangent(system, k, skips, 0.0 * lam, jac, 1e-3)
    assert np.abs(unloaded[1] - compiled[1]).max() > 1e3 * tol


class _Inertialess:
    """A system whose forces leave out the quadratic velocity terms."""

    def __init__(self, system: System):
        self._system = system

    def __getattr__(self, name):
        return getattr(self._system, name)

    def forces(self, k, **kwargs):
        return self._system.forces(k, inertia=False, **kwargs)
