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
    "shape_problem",
    "symmetry_problem",
]

SYMMETRY_TOLERANCE = 1e-9  # max |A - A^T| relative to max |A|
DEFINITENESS_TOLERANCE = 1e-9  # lowest eigenvalue of M relative to its largest, at least
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
    """The lowest eigenvalue of a symmetric matrix (dense solver up to 1500 rows, else
    Lanczos on the low end of the spectrum)."""
    from scipy.linalg import eigvalsh
    from scipy.sparse.linalg import eigsh

    if matrix.shape[0] <= _DENSE_LIMIT:
        dense = sp.csr_matrix(matrix).toarray()
        return float(eigvalsh(0.5 * (dense + dense.T), subset_by_index=[0, 0])[0])
    values = eigsh(
        sp.csr_matrix(matrix, dtype=float), k=1, which="SA", tol=1e-10, return_eigenvectors=False
    )
    return float(values[0])


def definiteness_problem(mass: sp.spmatrix, what: str) -> str | None:
    """Why the (symmetric) mass matrix is not positive semi-definite, or None: its lowest
    eigenvalue must not be below -1e-9 of its largest term. A zero matrix is refused too."""
    mass = sp.csr_matrix(mass)
    scale = abs(mass).max() if mass.nnz else 0.0
    if scale == 0.0:
        return f"{what} is zero: the component has no mass"
    lowest = lowest_eigenvalue(mass)
    if lowest >= -DEFINITENESS_TOLERANCE * scale:
        return None
    return (
        f"{what} is not positive semi-definite: eigenvalue {lowest:.6g}, against its largest "
        f"term {scale:.6g} (a negative mass or inertia)"
    )
