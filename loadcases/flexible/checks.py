"""Checks of imported stiffness and mass matrices before they become an FEModel: square,
of the size of the DOF map, finite, symmetric (relative 1e-9), non-negative diagonals and
a positive semi-definite mass matrix. Each returns the problems found as texts."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = [
    "SYMMETRY_TOLERANCE",
    "definiteness_problem",
    "diagonal_problem",
    "lowest_eigenvalue",
    "negative_pivots",
    "shape_problem",
    "symmetry_problem",
]

SYMMETRY_TOLERANCE = 1e-9  # max |A - A^T| relative to max |A|
DEFINITENESS_TOLERANCE = 1e-9  # lowest eigenvalue of M scaled to a unit diagonal, at least
_DENSE_LIMIT = 1500  # up to this size the lowest eigenvalue is found by a dense solver
_COMPONENT_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")


def shape_problem(matrix: sp.spmatrix, ndof: int, what: str) -> str | None:
    """Why `matrix` is not ndof x ndof with finite terms, or None."""
    rows, cols = matrix.shape
    if rows != cols:
        return f"{what} is {rows} x {cols}: not square"
    if rows != ndof:
        return f"{what} is {rows} x {cols} but the DOF map has {ndof} DOF"
    data = sp.csr_matrix(matrix).data
    if not np.all(np.isfinite(data)):
        return f"{what} has {int(np.count_nonzero(~np.isfinite(data)))} non-finite terms"
    return None


def symmetry_problem(matrix: sp.spmatrix, what: str) -> str | None:
    """Why `matrix` is not symmetric to SYMMETRY_TOLERANCE (relative), or None."""
    matrix = sp.csr_matrix(matrix)
    scale = abs(matrix).max() if matrix.nnz else 0.0
    if scale == 0.0:
        return None
    difference = abs(matrix - matrix.T).max()
    if difference <= SYMMETRY_TOLERANCE * scale:
        return None
    return (
        f"{what} is not symmetric: max |A - A^T| = {difference:.3g}, {difference / scale:.1e} of "
        f"its largest term (at most {SYMMETRY_TOLERANCE:g})"
    )


def diagonal_problem(matrix: sp.spmatrix, dofs: np.ndarray, what: str) -> str | None:
    """Why `matrix` has a negative diagonal term (naming its node id and component), or
    None; `dofs[i]` = (node id, component 1-6) of row i."""
    diagonal = sp.csr_matrix(matrix).diagonal()
    negative = np.flatnonzero(diagonal < 0.0)
    if negative.size == 0:
        return None
    node, component = dofs[negative[0]]
    return (
        f"{what} has {negative.size} negative diagonal terms, the first at node {node} "
        f"{_COMPONENT_NAMES[component - 1]} ({diagonal[negative[0]]:.6g})"
    )


def lowest_eigenvalue(matrix: sp.spmatrix) -> float:
    """The lowest eigenvalue of a symmetric matrix (dense solver)."""
    from scipy.linalg import eigvalsh

    dense = sp.csr_matrix(matrix).toarray()
    return float(eigvalsh(0.5 * (dense + dense.T), subset_by_index=[0, 0])[0])


def negative_pivots(matrix: sp.spmatrix) -> int | None:
    """How many eigenvalues of a symmetric matrix are negative, by Sylvester's law of
    inertia: the signs of the pivots of its LDL^T factorisation (SuperLU with symmetric
    ordering and diagonal pivots). None when the factorisation had to pivot off the
    diagonal or failed (the count would not be the inertia)."""
    from scipy.sparse.linalg import splu

    try:
        lu = splu(
            sp.csc_matrix(matrix),
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError:  # exactly singular
        return None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return None
    return int(np.count_nonzero(lu.U.diagonal() < 0.0))


def definiteness_problem(mass: sp.spmatrix, what: str, quantity: str = "mass") -> str | None:
    """Why the (symmetric) mass (or stiffness: `quantity`) matrix is not positive
    semi-definite, or None. Scaled to a
    unit diagonal (S = D^-1/2 M D^-1/2, rows without mass left out), S + 1e-9 I must be
    positive definite: no eigenvalue of S below -1e-9. A zero matrix, or a row with
    coupling terms but no diagonal term, is refused too. Up to 1500 DOF the lowest
    eigenvalue is computed; above, the pivots of S + 1e-9 I are counted.
    RuntimeError if the larger check cannot be done (the caller warns)."""
    mass = sp.csr_matrix(mass)
    diagonal = mass.diagonal()
    if not np.any(diagonal != 0.0):
        return f"{what} has no diagonal term: the component has no {quantity}"
    empty = diagonal == 0.0
    coupled = np.flatnonzero(empty & (np.asarray(abs(mass).sum(axis=1)).ravel() > 0.0))
    if coupled.size:
        return f"{what} has coupling terms in row {coupled[0] + 1} but no diagonal term"
    kept = np.flatnonzero(~empty)
    scale = sp.diags(1.0 / np.sqrt(np.abs(diagonal[kept])))
    scaled = scale @ mass[kept][:, kept] @ scale
    if len(kept) <= _DENSE_LIMIT:
        lowest = lowest_eigenvalue(scaled)
        if lowest >= -DEFINITENESS_TOLERANCE:
            return None
        return (
            f"{what} is not positive semi-definite: eigenvalue {lowest:.6g} of the matrix "
            f"scaled to a unit diagonal (a negative {quantity})"
        )
    negative = negative_pivots(scaled + DEFINITENESS_TOLERANCE * sp.identity(len(kept)))
    if negative is None:
        raise RuntimeError("its LDL^T factorisation needed off-diagonal pivots")
    if negative == 0:
        return None
    return (
        f"{what} is not positive semi-definite: {negative} eigenvalues below "
        f"{-DEFINITENESS_TOLERANCE:g} of the matrix scaled to a unit diagonal"
    )
