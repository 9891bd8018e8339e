"""Factors of a rigid system's saddle matrix [[M, phi_q^T], [phi_q, 0]] gathered on its
sparsity pattern in one compiled call.

`factor_saddle(system.mass(k), system.phi_q(k), pattern)` forms the dense M (nq^2 entries)
and phi_q (m nq) only to pick the pattern's few nonzeros out of them: at 200 links that is
16 MB and 9 MB per factorisation, more than the sparse LU itself. Here the mass blocks and
the constraint rows' column blocks (mechlib.kinematics.constraint_arrays) are evaluated and the
values taken straight from them. Used by the generalized-alpha iteration matrix of a system with no
active force element and by the consistent states; the same values, so the same factors.
Small matrices too are gathered so (their dense LU then follows the same kernel as the
compiled runs').
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics import kernels as kr
from mechlib.kinematics.kin import Kin
from mechlib.linalg.factor import SaddlePattern, augmented, factor_saddle, pattern_factors

__all__ = ["coupled_pattern", "rigid_saddle_factors"]


def coupled_pattern(system, columns: np.ndarray):
    """The sparsity of [[M + T, phi_q^T], [phi_q, 0]] (mechlib.linalg.factor.SaddlePattern),
    T full over the coordinates `columns` (a force element's tangent couples them: the
    compiled runs' iteration matrix, mechlib.solvers.genalpha.run)."""
    rigid = system.saddle_pattern()
    nq = system.nq
    top = np.zeros((nq, nq))
    top[np.ix_(columns, columns)] = 1.0
    inner = (rigid.rows < nq) & (rigid.cols < nq)
    top[rigid.rows[inner], rigid.cols[inner]] = 1.0
    jac = np.zeros((rigid.shape[0] - nq, nq))
    lower = (rigid.rows >= nq) & (rigid.cols < nq)
    jac[rigid.rows[lower] - nq, rigid.cols[lower]] = 1.0
    return SaddlePattern(top, jac)


def rigid_saddle_factors(system, k: Kin):
    """LU factors of [[M, phi_q^T], [phi_q, 0]] at state k (as mechlib.linalg.factor.factor_saddle
    gives them, None when singular): for a packed system, its values gathered on the
    pattern by `saddle_values` and factored by the pattern's layout (the same kernels as
    the compiled runs' refactorisations: mechlib.solvers.genalpha.run), else from the dense M and
    phi_q."""
    arrays = system.packed_constraints()
    pattern = system.saddle_pattern()
    if arrays is None:
        return factor_saddle(system.mass(k), system.phi_q(k), pattern)
    ints, floats = arrays.packed()
    values = np.empty(pattern.rows.size)
    saddle_values(
        k.x, ints, floats, arrays.functions(k.t, "value"), arrays.references(), arrays.bodies(),
        pattern.rows, pattern.cols, values,
    )  # fmt: skip
    return pattern_factors(pattern, values, lambda: augmented(system.mass(k), system.phi_q(k)))


@njit(**KERNEL)
def saddle_values(x, ints, floats, functions, refs, body, prow, pcol, out):
    """The saddle matrix's entries at the pattern's (row, column) pairs: M's from its
    diagonal blocks, phi_q's (and its transpose's) from the constraint rows' blocks."""
    nb = ints[0]
    nq = 7 * nb
    nall = ca.row_count(ints)
    _, masses, pscale, inertia = ca.body_terms(body, nb)
    blocks = np.empty((nb, 7, 7))
    kr.mass_blocks(x, masses, inertia, pscale, blocks)
    full = np.empty(nall)
    rows = np.empty((nall, nq + 7))
    active, _ = ca.constraint_rows(x, ints, floats, functions, refs, full, rows)
    for e in range(prow.shape[0]):
        r, c = prow[e], pcol[e]
        if r < nq and c < nq:
            out[e] = blocks[r // 7, r % 7, c % 7] if r // 7 == c // 7 else 0.0
        elif r < nq:
            out[e] = rows[active[c - nq], r]
        elif c < nq:
            out[e] = rows[active[r - nq], c]
        else:
            out[e] = 0.0
