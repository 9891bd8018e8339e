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

from mechlib.core.jit import KERNEL, njit
from mechlib.elements import friction_kernel
from mechlib.elements.compiled_forces import differenced_forces
from mechlib.kinematics import constraint_arrays as ca

__all__ = ["applied_tangent"]


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
    Q (System.forces: the packed `elements`' loads, gravity (m/s^2) and the quadratic
    velocity terms) at (q, qd), multipliers `lam` of the packed constraints (ints, floats,
    functions at the state's time, refs: mechlib.kinematics.constraint_arrays), by
    compiled_forces.differenced_forces: forward differences of step 1e-7 max(1, |q_j|)
    and 1e-7 max(1, |qd_j|)."""
    nb = q.shape[0] // 7
    nall = ca.row_count(ints)
    full, rows = np.empty(nall), np.zeros((nall, q.shape[0] + 7))
    x, _ = ca.state_arrays(q, qd, nb)
    active, _ = ca.constraint_rows(x, ints, floats, functions, refs, full, rows)
    held = (np.empty(0), np.empty(0), 0.0, np.empty(0))  # no element states
    if _reads_reactions(elements):
        anew = (ints, floats, functions, refs, full, rows.copy())
        differenced_forces(q, qd, np.empty(0), elements, columns, masses, inertia, gravity,
                           True, rows, active, lam, held, anew, K, C)  # fmt: skip
    else:
        differenced_forces(q, qd, np.empty(0), elements, columns, masses, inertia, gravity,
                           True, rows, active, lam, held, None, K, C)  # fmt: skip


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
