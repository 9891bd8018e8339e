"""Dense linear solves that report singularity by name instead of returning garbage."""
from __future__ import annotations

import numpy as np
from scipy.linalg.lapack import dgetrf as _getrf, dgetrs as _getrs

from mechlib.check import find_redundant
from mechlib.solution import SolverFailure

__all__ = ["augmented", "factor", "solve_factored", "singular_failure", "SINGULAR_RATIO"]

SINGULAR_RATIO = 1e-13


def augmented(top: np.ndarray, jac: np.ndarray) -> np.ndarray:
    """[[top, jac^T], [jac, 0]]: the saddle-point matrix of constrained equations."""
    n, m = top.shape[0], jac.shape[0]
    out = np.zeros((n + m, n + m))
    out[:n, :n] = top
    out[:n, n:] = jac.T
    out[n:, :n] = jac
    return out


def factor(matrix: np.ndarray):
    """LU factors of a square matrix, or None when it is numerically singular."""
    lu, piv, _ = _getrf(matrix, overwrite_a=True)
    diag = np.abs(np.diag(lu))
    if diag.size and (diag.min() <= SINGULAR_RATIO * diag.max() or not np.isfinite(diag).all()):
        return None
    return lu, piv


def solve_factored(lu, rhs: np.ndarray, *, transpose: bool = False) -> np.ndarray:
    """Solve with LU factors; `transpose` solves with the transposed matrix."""
    x, info = _getrs(lu[0], lu[1], rhs, trans=1 if transpose else 0)
    return x


def singular_failure(system, phi_q: np.ndarray, t: float, what: str) -> SolverFailure:
    """A failure naming the dependent equations of phi_q at time t (toggle positions)."""
    found = find_redundant(phi_q, system.labels, system.owners, set(system.body_names),
                           owner_rank=system.owner_rank)
    if found:
        detail = "; ".join(r.describe() for r in found[:4])
        where = tuple(r.owner for r in found)
        return SolverFailure(f"{what} at t = {t:.6g} s: singular configuration (toggle or "
                             f"dead point): {detail}", time=t, where=where)
    return SolverFailure(f"{what} at t = {t:.6g} s: singular system matrix (a body with no "
                         "mass or stiffness in some direction, or a free degree of freedom "
                         "without load path)", time=t)
