"""The compiled constraint rows evaluate a coordinate equation only while it is active
(mechlib.kinematics.constraint_arrays: a joint friction's dormant hold row is not evaluated
at each Newton iteration while the joint slides). Reference: the grouped path (each
primitive group and the coordinate block by its own kernels,
System.grouped_phi_and_jacobian and the groups' gamma), with the hold row dormant and held;
the geometric rows by the same kernels (bit for bit), the coordinate row by the block's
(1e-12)."""

from __future__ import annotations

import numpy as np

import mechlib as ml
from mechlib.core import jit
from mechlib.kinematics import constraint_arrays as ca
from mechlib.system.system import System

TOL = 1e-12


def _arm() -> ml.Mechanism:
    mech = ml.Mechanism(gravity=(0.0, -9.81, 0.0))
    mech.add_body("arm", mass=1.0, cm=(1.0, 0, 0), inertia=[1e-3, 1e-3, 1e-3])
    mech.add_joint("hinge", "revolute", bodies=("arm", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    return mech


def _grouped(system: System, k) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(phi, phi_q, gamma) of the active rows by the grouped path."""
    phi, jac = system.grouped_phi_and_jacobian(k)
    parts = [g.gamma(k) for g in system.groups] + [system.coordinate_rows().gamma(k)]
    gamma = np.concatenate(parts)[np.asarray(system.active)]
    return phi, jac, gamma


def _packed(system: System, q, qd, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(phi, phi_q, gamma) of the active rows by the Newton loop's kernels."""
    arrays = system.packed_constraints()
    assert arrays is not None
    ints, floats = arrays.packed()
    nq = system.nq
    nall = ints[0] + 3 * ints[1] + ints[2] + ints[3] + ints[6]
    full, rows = np.full(nall, np.nan), np.zeros((nall, nq + 7))
    x, xd = ca.state_arrays(q, qd, nq // 7)
    functions, refs = arrays.functions(t), arrays.references()
    active, _ = ca.constraint_rows(x, ints, floats, functions, refs, full, rows)
    m = active.shape[0]
    nu, gamma = np.empty(m), np.empty(m)
    ca.unpacked_nu_and_gamma(x, xd, ca.unpack(ints, floats), functions, refs, nu, gamma)
    return full[active], rows[active, :nq], gamma


def test_a_dormant_hold_row_is_skipped_and_a_held_one_evaluated() -> None:
    jit.compile_all()  # the packed path serves compiled kernels only
    system = System(_arm())
    rng = np.random.default_rng(4)
    q = system.design_q()
    q[3:7] += 0.1 * rng.standard_normal(4)  # off the design state, not normalised
    qd = rng.standard_normal(system.nq)
    k = system.kin(q, qd, 0.3)
    row = system.held_coordinate("hinge", system.measure("hinge", "angle"))
    for held in (False, True):
        if held:
            system.hold(row, system.kin(system.design_q(), None, 0.0))
        assert system.is_active(row) == held
        packed, grouped = _packed(system, q, qd, 0.3), _grouped(system, k)
        for mine, reference in zip(packed, grouped):
            assert mine.shape == reference.shape
            assert np.all(np.isfinite(mine))
            assert np.abs(mine - reference).max() <= TOL * max(1.0, np.abs(reference).max())
        assert len(packed[0]) == len(system.active)
