"""Factors of a rigid system's saddle matrix [[M, phi_q^T], [phi_q, 0]] gathered on its
sparsity pattern in one compiled call.

`factor_saddle(system.mass(k), system.phi_q(k), pattern)` forms the dense M (nq^2 entries)
and phi_q (m nq) only to pick the pattern's few nonzeros out of them: at 200 links that is
16 MB and 9 MB per factorisation, more than the sparse LU itself. Here the mass blocks and
the constraint rows' column blocks (mechlib.constraint_arrays) are evaluated and the values
taken straight from them. Used by the generalized-alpha iteration matrix of a system with no
active force element and by the consistent states; the same values, so the same factors.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from mechlib import constraint_arrays as ca
from mechlib import kernels as kr
from mechlib.jit import njit
from mechlib.kin import Kin
from mechlib.linalg import SPARSE_FROM, augmented, factor_saddle, sparse_saddle_factors

__all__ = ["rigid_saddle_factors"]


def rigid_saddle_factors(system, k: Kin):
    """LU factors of [[M, phi_q^T], [phi_q, 0]] at state k (as mechlib.linalg.factor_saddle
    gives them, None when singular): gathered on the pattern by `saddle_values` for a
    packed system with a sparse saddle matrix, else from the dense M and phi_q."""
    arrays = system.packed_constraints()
    pattern = system.saddle_pattern()
    if arrays is None or system.nq + system.active.size < SPARSE_FROM:
        return factor_saddle(system.mass(k), system.phi_q(k), pattern)
    ints, floats = arrays.packed()
    values = np.empty(pattern.rows.size)
    saddle_values(
        k.x, ints, floats, arrays.functions(k.t, "value"), arrays.references(), arrays.bodies(),
        pattern.rows, pattern.cols, values,
    )  # fmt: skip
    matrix = sp.csc_matrix((values, pattern.indices, pattern.indptr), shape=pattern.shape)
    return sparse_saddle_factors(matrix, lambda: augmented(system.mass(k), system.phi_q(k)))


@njit(cache=True, nogil=True)
def saddle_values(x, ints, floats, functions, refs, body, prow, pcol, out):
    """The saddle matrix's entries at the pattern's (row, column) pairs: M's from its
    diagonal blocks, phi_q's (and its transpose's) from the constraint rows' blocks."""
    nb = ints[0]
    nq = 7 * nb
    nall = ints[0] + 3 * ints[1] + ints[2] + ints[3] + ints[6]
    masses, pscale = body[3 : 3 + nb], body[3 + nb : 3 + 2 * nb]
    inertia = body[3 + 2 * nb : 3 + 11 * nb].reshape((nb, 3, 3))
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
