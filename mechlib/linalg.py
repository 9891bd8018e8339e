"""Linear solves that report singularity by name instead of returning garbage.

Saddle-point matrices [[top, phi_q^T], [phi_q, 0]] of more than SPARSE_FROM rows are
factored by SuperLU on their fixed sparsity pattern (a body couples only to its joints),
smaller ones by dense LAPACK, which is faster there.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dgecon as _gecon
from scipy.linalg.lapack import dgetrf as _getrf
from scipy.linalg.lapack import dgetrs as _getrs
from scipy.sparse.linalg import splu

from mechlib.check import find_redundant
from mechlib.contract import Status
from mechlib.solution import SolverFailure
from mechlib.work import count

__all__ = [
    "SINGULAR_RATIO",
    "SPARSE_FROM",
    "SaddlePattern",
    "augmented",
    "factor",
    "factor_saddle",
    "singular_failure",
    "solve_factored",
    "sparse_saddle_factors",
]

SINGULAR_RATIO = 1e-14
SPARSE_FROM = 100


class SaddlePattern:
    """Structural nonzeros of a saddle matrix in CSC order, found once."""

    def __init__(self, top: np.ndarray, jac: np.ndarray):
        n = top.shape[0] + jac.shape[0]
        mask = augmented(top != 0.0, jac != 0.0).astype(bool)
        cols, rows = np.nonzero(mask.T)  # column-major order = CSC order
        self.rows, self.cols, self.shape = rows, cols, (n, n)
        self.indptr = np.searchsorted(cols, np.arange(n + 1)).astype(np.int32)
        self.indices = rows.astype(np.int32)

        # where each structural nonzero comes from: top, jac^T (upper right), jac (lower left)
        nq = top.shape[0]
        self._top = np.flatnonzero((rows < nq) & (cols < nq))
        self._upper = np.flatnonzero((rows < nq) & (cols >= nq))
        self._lower = np.flatnonzero((rows >= nq) & (cols < nq))
        self._nq = nq

    def saddle_csc(self, top: np.ndarray, jac: np.ndarray) -> sp.csc_matrix:
        """[[top, jac^T], [jac, 0]] on the pattern, gathered from `top` and `jac` without
        forming the dense saddle matrix ((nq + m)^2 entries: 10 MB for a 100-link chain)."""
        rows, cols, nq = self.rows, self.cols, self._nq
        values = np.zeros(rows.size)
        values[self._top] = top[rows[self._top], cols[self._top]]
        values[self._upper] = jac[cols[self._upper] - nq, rows[self._upper]]
        values[self._lower] = jac[rows[self._lower] - nq, cols[self._lower]]
        return sp.csc_matrix((values, self.indices, self.indptr), shape=self.shape)


class _Sparse:
    """SuperLU factors with the dense-LU solve interface."""

    def __init__(self, lu):
        self.lu = lu

    def solve(self, rhs: np.ndarray, transpose: bool = False) -> np.ndarray:
        return self.lu.solve(rhs, trans="T" if transpose else "N")


def factor_saddle(
    top: np.ndarray,
    jac: np.ndarray,
    pattern: SaddlePattern | None = None,
    *,
    coupling: np.ndarray | None = None,
):
    """Factors of [[top, jac^T - coupling], [jac, 0]] (None when singular). `pattern`
    must cover the nonzeros of every matrix given with it; large systems without a
    `coupling` (dQ/dlam of reaction-dependent loads) then use sparse LU."""
    if coupling is not None:
        matrix = augmented(top, jac)
        matrix[: top.shape[0], top.shape[0] :] -= coupling
        return factor(matrix)
    if pattern is not None and top.shape[0] + jac.shape[0] >= SPARSE_FROM:
        return sparse_saddle_factors(pattern.saddle_csc(top, jac), lambda: augmented(top, jac))
    return factor(augmented(top, jac))


def sparse_saddle_factors(matrix: sp.csc_matrix, dense: Callable[[], np.ndarray]):
    """SuperLU factors of a saddle matrix; where they are singular or badly pivoted, the
    dense path's (`dense()`: the same matrix dense), which names the culprits."""
    count(factorizations=1)
    try:
        factors = splu(matrix, permc_spec="COLAMD")
    except RuntimeError:  # exactly singular: the dense path names the culprits
        return factor(dense())
    diag = np.abs(factors.U.diagonal())
    if diag.min() > SINGULAR_RATIO * diag.max() and np.isfinite(diag).all():
        return _Sparse(factors)
    return factor(dense())


def augmented(top: np.ndarray, jac: np.ndarray) -> np.ndarray:
    """[[top, jac^T], [jac, 0]]: the saddle-point matrix of constrained equations."""
    n, m = top.shape[0], jac.shape[0]
    out = np.zeros((n + m, n + m))
    out[:n, :n] = top
    out[:n, n:] = jac.T
    out[n:, :n] = jac
    return out


def factor(matrix: np.ndarray):
    """LU factors of a square matrix, rows equilibrated (each scaled by 1/max|row|, so that
    a quaternion row of mass 1e-5 beside contact stiffnesses of 1e10 is not taken for a
    singularity), or None when it is numerically singular: reciprocal condition number
    (LAPACK dgecon, 1-norm) of the equilibrated matrix below SINGULAR_RATIO."""
    if matrix.size == 0:
        return matrix, np.zeros(0, dtype=np.int32), np.ones(0)
    big = np.abs(matrix).max(axis=1)
    if not np.all(big > 0.0) or not np.isfinite(big).all():
        return None
    rows = 1.0 / big
    scaled = matrix * rows[:, None]
    norm = float(np.abs(scaled).sum(axis=0).max())
    count(factorizations=1)
    lu, piv, info = _getrf(scaled, overwrite_a=True)
    if info > 0 or not np.isfinite(lu).all():
        return None
    rcond, _ = _gecon(lu, norm)
    return None if rcond <= SINGULAR_RATIO else (lu, piv, rows)


def solve_factored(lu, rhs: np.ndarray, *, transpose: bool = False) -> np.ndarray:
    """Solve with LU factors; `transpose` solves with the transposed matrix."""
    if isinstance(lu, _Sparse):
        return lu.solve(rhs, transpose)
    factors, piv, rows = lu
    if transpose:  # A^T x = b with (R A)^T = A^T R: solve for y = R^-1 x
        y, _ = _getrs(factors, piv, rhs, trans=1)
        return rows * y
    x, _ = _getrs(factors, piv, rows * rhs, trans=0)
    return x


def singular_failure(system, phi_q: np.ndarray, t: float, what: str) -> SolverFailure:
    """A failure naming the dependent equations of phi_q at time t (toggle positions)."""
    found = find_redundant(
        phi_q, system.labels, system.owners, set(system.body_names), owner_rank=system.owner_rank
    )
    if found:
        detail = "; ".join(r.describe() for r in found[:4])
        where = tuple(r.owner for r in found)
        return SolverFailure(
            f"{what} at t = {t:.6g} s: singular configuration (toggle or dead point): {detail}",
            time=t,
            where=where,
            status=Status.SINGULAR,
        )
    return SolverFailure(
        f"{what} at t = {t:.6g} s: singular system matrix (a body with no "
        "mass or stiffness in some direction, or a free degree of freedom "
        "without load path)",
        time=t,
        status=Status.SINGULAR,
    )
