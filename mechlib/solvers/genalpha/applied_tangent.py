"""The differenced tangent of the applied forces as one compiled kernel, for a Python step
of a rigid system whose active force elements are all packed and hold no states.

It differences what mechlib.solvers.genalpha.tangent.differenced_tangent differences,
System.forces: gravity, the packed elements' loads (mechlib.elements.compiled_forces, the
contacts that give their own tangent left out) and the bodies' quadratic velocity terms,
column by column with the same steps; the constraint rows the frictions read their joint's
reaction through are evaluated anew at each moved position, as the Python forces do (the
velocity columns keep the base rows, as they are given phi_q). The whole run's tangent
(run._differenced) differences the elements alone."""

from __future__ import annotations

import numpy as np

from mechlib.core.differences import fd_step
from mechlib.core.jit import KERNEL, njit
from mechlib.elements import friction_kernel
from mechlib.elements.compiled_forces import element_wrenches
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics import kernels

__all__ = ["applied_tangent"]


@njit(**KERNEL)
def _applied(x, xd, elements, masses, inertia, gravity, rows, active, lam, out):
    """out (nq,) = System.forces of the packed `elements` at x, xd: their loads, gravity
    `gravity` (m/s^2) and the quadratic velocity terms."""
    F, N = np.empty((x.shape[0], 3)), np.empty((x.shape[0], 3))
    element_wrenches(x, xd, np.empty(0), elements, rows, active, lam, F, N)
    kernels.body_forces(x, xd, masses, inertia, gravity, F, N, True, out)


@njit(**KERNEL)
def _reads_reactions(elements) -> bool:
    """A packed friction is loaded by its joint's reaction (reads constraint rows)."""
    counts = elements[5][:, friction_kernel.INTS]
    return counts.shape[0] > 0 and counts.max() > 0


@njit(**KERNEL)
def applied_tangent(
    q, qd, elements, columns, masses, inertia, gravity, ints, floats, functions, refs, lam, K, C
):  # fmt: skip
    """K = -dQ/dq and C = -dQ/dqd (nq, nq; zero outside `columns`) of the applied forces
    Q (`_applied`) at (q, qd), multipliers `lam` of the packed constraints (ints, floats,
    functions at the state's time, refs: mechlib.kinematics.constraint_arrays), by
    forward differences of step 1e-7 max(1, |q_j|) and 1e-7 max(1, |qd_j|)."""
    nq = q.shape[0]
    nb = nq // 7
    K[:] = 0.0
    C[:] = 0.0
    nall = ca.row_count(ints)
    full, rows = np.empty(nall), np.zeros((nall, nq + 7))
    x, xd = ca.state_arrays(q, qd, nb)
    active, _ = ca.constraint_rows(x, ints, floats, functions, refs, full, rows)
    base, moved = np.empty(nq), np.empty(nq)
    _applied(x, xd, elements, masses, inertia, gravity, rows, active, lam, base)
    reads = _reads_reactions(elements)
    moved_rows = rows.copy() if reads else rows
    qp, qdp = q.copy(), qd.copy()
    for j in columns:
        eps = fd_step(q[j])
        qp[j] = q[j] + eps
        x, xd = ca.state_arrays(qp, qd, nb)
        if reads:
            ca.constraint_rows(x, ints, floats, functions, refs, full, moved_rows)
        _applied(x, xd, elements, masses, inertia, gravity, moved_rows, active, lam, moved)
        for i in range(nq):
            K[i, j] = -(moved[i] - base[i]) / eps
        qp[j] = q[j]
        eps = fd_step(qd[j])
        qdp[j] = qd[j] + eps
        x, xd = ca.state_arrays(q, qdp, nb)
        _applied(x, xd, elements, masses, inertia, gravity, rows, active, lam, moved)
        for i in range(nq):
            C[i, j] = -(moved[i] - base[i]) / eps
        qdp[j] = qd[j]


def packed_tangent(system, arrays, k, skips, own: list, lam: np.ndarray):
    """(K, C) (nq, nq) of System.forces at state k and multipliers `lam` by
    `applied_tangent`, the columns ColumnSkips `skips` finds inert left zero, as
    differenced_tangent makes them (to round-off); None where the kernel does not cover
    the system: modal bodies, element states, an active element not packed (`arrays`: its
    packed constraints, None on the Python path), or an element with its own tangent
    (`own`) that is not a packed contact."""
    if arrays is None or system.flexible or system.states or system.per_body != 7:
        return None
    packed = system.compiled_forces()
    if packed is None or {id(c) for c in packed.contacts} != {id(e) for e in own}:
        return None
    packed.refresh(system)
    nq = system.nq
    columns = np.array([j for j in range(nq) if not skips.inert(skips.body(j))], np.int64)
    stiffness, damping = np.empty((nq, nq)), np.empty((nq, nq))
    ints, floats = arrays.packed()
    q, qd = system.state_of(k)
    applied_tangent(
        q, qd, packed.rest, columns, system.masses, system.inertia, system.gravity, ints, floats,
        arrays.functions(k.t), arrays.references(), lam, stiffness, damping,
    )  # fmt: skip
    return stiffness, damping
