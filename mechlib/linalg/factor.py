"""Linear solves that report singularity by name instead of returning garbage.

Saddle-point matrices [[top, phi_q^T], [phi_q, 0]] of SPARSE_FROM rows or more are factored
on their fixed sparsity pattern (a body couples only to its joints): by LAPACK's band LU
in the reverse Cuthill-McKee order where that order leaves a narrow band (chains, chains
of loops: 3-4 times faster than SuperLU at 200-2000 rows), else by SuperLU. Smaller ones
by dense LAPACK, which is faster there.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dgecon as _gecon
from scipy.linalg.lapack import dgetrf as _getrf
from scipy.linalg.lapack import dgetrs as _getrs
from scipy.sparse.linalg import splu

from mechlib.core.outcome import SolverFailure, Status
from mechlib.core.work import count
from mechlib.linalg.flat_lu import SINGULAR_RATIO, Banded, FlatLayout, factors, refactor
from mechlib.linalg.rank import find_redundant

__all__ = [
    "SINGULAR_RATIO",
    "SPARSE_FROM",
    "SaddlePattern",
    "augmented",
    "factor",
    "factor_saddle",
    "pattern_factors",
    "singular_failure",
    "solve_factored",
    "sparse_saddle_factors",
]

SPARSE_FROM = 100
BAND_SHARE = 0.25  # the band LU where the band's width (kl + ku + 1) is at most this of n


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

    @cached_property
    def layout(self) -> FlatLayout | None:
        """How the compiled kernels store and factor the matrix (mechlib.linalg.flat_lu): dense
        below SPARSE_FROM rows, banded in reverse Cuthill-McKee order where its band is
        narrow (at most BAND_SHARE of the rows wide), else None (SuperLU's)."""
        from scipy.sparse.csgraph import reverse_cuthill_mckee  # here: `validate` needs none

        n = self.shape[0]
        if n < SPARSE_FROM:
            return FlatLayout.dense(self.rows, self.cols, n)
        both = np.concatenate([self.rows, self.cols]), np.concatenate([self.cols, self.rows])
        graph = sp.csr_matrix((np.ones(2 * self.rows.size), both), shape=self.shape)
        perm = reverse_cuthill_mckee(graph, symmetric_mode=True).astype(np.int64)
        order = np.empty(n, dtype=np.int64)
        order[perm] = np.arange(n)
        rows, cols = order[self.rows], order[self.cols]  # in P A P^T
        kl, ku = int(max((rows - cols).max(), 0)), int(max((cols - rows).max(), 0))
        if kl + ku + 1 > BAND_SHARE * n:
            return None
        return FlatLayout.band(rows, cols, perm, kl, ku)

    def values(self, top: np.ndarray, jac: np.ndarray) -> np.ndarray:
        """[[top, jac^T], [jac, 0]]'s values on the pattern (CSC order), gathered from
        `top` and `jac` without forming the dense saddle matrix ((nq + m)^2 entries: 10 MB
        for a 100-link chain)."""
        rows, cols, nq = self.rows, self.cols, self._nq
        values = np.zeros(rows.size)
        values[self._top] = top[rows[self._top], cols[self._top]]
        values[self._upper] = jac[cols[self._upper] - nq, rows[self._upper]]
        values[self._lower] = jac[rows[self._lower] - nq, cols[self._lower]]
        return values

    def csc(self, values: np.ndarray) -> sp.csc_matrix:
        """The sparse matrix of the pattern's values."""
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
    `coupling` (dQ/dlam of reaction-dependent loads) then use band or sparse LU."""
    if coupling is not None:
        matrix = augmented(top, jac)
        matrix[: top.shape[0], top.shape[0] :] -= coupling
        return factor(matrix)
    if pattern is not None and top.shape[0] + jac.shape[0] >= SPARSE_FROM:
        return pattern_factors(pattern, pattern.values(top, jac), lambda: augmented(top, jac))
    return factor(augmented(top, jac))


def pattern_factors(pattern: SaddlePattern, values: np.ndarray, dense: Callable[[], np.ndarray]):
    """Factors of the saddle matrix of the pattern's `values` (CSC order) by the pattern's
    layout (mechlib.linalg.flat_lu: dense or band LU), or SuperLU's where it has none; where they
    are singular, the dense path's (`dense()`: the same matrix dense), which names the
    culprits."""
    layout = pattern.layout
    if layout is None:
        return sparse_saddle_factors(pattern.csc(values), dense)
    count(factorizations=1)
    ints, floats = layout.new()
    if refactor(values, *layout.kernel_args(), ints, floats):
        return factors(ints, floats)
    return factor(dense())


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
    if isinstance(lu, (_Sparse, Banded)):
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
