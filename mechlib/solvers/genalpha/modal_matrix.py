"""The iteration matrix of a system with modal bodies and no force elements
(mechlib.flexible.packed.modal_arrays) factored in one compiled call, with the tangent kept:
the one factorisation of modal_step (a step from Python) and of modal_run (whole runs), the
matrix Integrator._iteration_matrix factors (M and phi_q from modal_newton.modal_matrices,
the geometric stiffening's dQ/dlam beside phi_q^T as mechlib.system.reaction_loads'
reaction_coupling adds it), the factors those of mechlib.linalg.factor.factor.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.flexible.kernels import load_maps, weld_coupling
from mechlib.kinematics import constraint_arrays as ca
from mechlib.linalg.flat_lu import DENSE, refactor_dense
from mechlib.solvers.genalpha.modal_newton import modal_matrices_into

__all__ = ["factored"]


@njit(**KERNEL)
def factored(q1, bp, gp, system, tangent, fi, ff, lent):
    """[[M + (K + gamma' C) / beta', phi_q^T - dQ/dlam], [phi_q, 0]] at q1 factored into
    the DENSE flat factors (fi, ff) (mechlib.linalg.flat_lu.refactor_dense, written in
    place of the factors: mechlib.linalg.factor.factor's arithmetic), M and phi_q by
    modal_matrices, (K, C) = `tangent` (nq, nq each, kept from the last differenced
    tangent), dQ/dlam of the geometric stiffening (`_coupled`); what
    Integrator._iteration_matrix factors. False where it is singular. `system`: (ints,
    floats, functions, refs, body, bodies, welds, active) as modal_step passes them to
    modal_newton; beta' (1/s^2), gamma' (1/s). False too for factors not DENSE of this
    size (Python's factorisation then makes them). `lent`: modal_newton.row_arrays', the
    rows at q1 left there and flagged for Newton's first residual where it returns True."""
    ints, floats, functions, refs, body, bodies, welds, active = system
    nq, m = q1.shape[0], active.shape[0]
    n = nq + m
    if fi[0] != DENSE or fi[1] != n or ff.shape[0] != n * n + n:
        return False  # not DENSE factors of this matrix: Python's factorisation makes them
    mass, jac = np.empty((nq, nq)), np.empty((m, nq))
    full, rows, fresh = lent
    modal_matrices_into(
        q1, ints, floats, functions, refs, body, bodies, welds, active, mass, jac, full, rows
    )  # fmt: skip
    stiffness, damping = tangent
    values = ff[: n * n]  # by columns
    for c in range(nq):
        for r in range(nq):
            values[r + n * c] = mass[r, c] + (stiffness[r, c] + gp * damping[r, c]) / bp
        for i in range(m):
            values[nq + i + n * c] = jac[i, c]
            values[c + n * (nq + i)] = jac[i, c]
    for c in range(nq, n):
        values[nq + n * c : n * (c + 1)] = 0.0
    _coupled(q1, system, n, values)
    if not refactor_dense(fi, ff):
        return False
    fresh[0] = 1.0
    return True


@njit(**KERNEL)
def _coupled(q1, system, n, values):
    """The iteration matrix's values (n x n by columns) with dQ/dlam of the stiffened
    bodies' geometric stiffening taken from their phi_q^T columns
    (mechlib.system.reaction_loads.reaction_coupling; System.stiffening_coupling)."""
    _, _, _, _, _, bodies, _, active = system
    nq = q1.shape[0]
    nb = system[0][0]
    x, _ = ca.state_arrays(q1, q1, nb)
    column = np.full(active.max() + 1 if active.shape[0] else 0, -1)
    for i in range(active.shape[0]):
        column[active[i]] = i
    for body in bodies:
        ints, nodes = body[0], body[1]
        if not ints[4]:
            continue
        frame, offset, modes, w0 = ints[0], ints[1], ints[2], ints[3]
        z0 = 7 * nb + offset
        zeta, maps = q1[z0 : z0 + modes], body[23]
        p_nodes = np.empty((nodes.shape[0], 4))
        for k in range(nodes.shape[0]):
            p_nodes[k, :] = x[nodes[k], 3:]
        load_maps(x[frame, 3:], p_nodes, body[17], zeta, maps)
        block = np.zeros((modes, nodes.shape[0], 6))
        weld_coupling(body[14], zeta, maps, block)
        for k in range(nodes.shape[0]):
            for j in range(6):
                row = w0 + 6 * k + j
                at = column[row] if row < column.shape[0] else -1
                if at < 0:
                    continue
                for i in range(modes):
                    values[z0 + i + n * (nq + at)] -= block[i, k, j]
