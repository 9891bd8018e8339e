"""What `loads flex check` tells about an imported component: its rigid-body mass and centre
of mass (exact for any FE mass matrix, through the rigid-body fields of its nodes) and its
first free-free frequencies (generalised eigenproblem K x = w^2 M x)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from mechlib.flexible.fe_model import FEModel

__all__ = ["MassProperties", "free_free_frequencies", "mass_properties", "rigid_fields"]

DENSE_LIMIT = 600  # DOF: up to this size every mode comes from a dense solver
_RIGID = 1e-8  # |K r|, relative to max |K| |r|, below which a rigid-body field r is free


@dataclass(frozen=True)
class MassProperties:
    """Translational mass per direction (kg; equal for a complete mass matrix) and centre
    of mass (m, component frame)."""

    mass: np.ndarray
    centre: np.ndarray


def rigid_fields(model: FEModel) -> tuple[np.ndarray, np.ndarray]:
    """(Gamma, R0), each (ndof, 3): the DOF values of unit rigid translations along x, y, z
    and of unit rigid rotations about the axes through the origin (u = theta x s)."""
    ndof = len(model.dof_map)
    gamma, r0 = np.zeros((ndof, 3)), np.zeros((ndof, 3))
    for row, (node, component) in enumerate(model.dof_map):
        x, y, z = model.coordinates[node]
        if component < 3:
            gamma[row, component] = 1.0
            skew = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
            r0[row] = -skew[component]
        else:
            r0[row, component - 3] = 1.0
    return gamma, r0


def mass_properties(model: FEModel) -> MassProperties:
    """Mass per direction (diag Gamma^T M Gamma) and centre of mass (from Gamma^T M R0 =
    -m c~, with m their mean)."""
    gamma, r0 = rigid_fields(model)
    mass = sp.csr_matrix(model.mass)
    translational = gamma.T @ (mass @ gamma)
    moment = gamma.T @ (mass @ r0)  # = -m * skew(c)
    m = float(np.mean(np.diag(translational)))
    if m <= 0.0:
        return MassProperties(np.diag(translational), np.full(3, np.nan))
    centre = np.array(
        [moment[1, 2] - moment[2, 1], moment[2, 0] - moment[0, 2], moment[0, 1] - moment[1, 0]]
    ) / (2.0 * m)
    return MassProperties(np.diag(translational), centre)


def _scale(model: FEModel) -> float:
    """A stiffness-to-mass ratio (1/s^2) of the model's size: mean diagonals' ratio."""
    k = float(np.mean(np.abs(sp.csr_matrix(model.stiffness).diagonal())))
    m = float(np.mean(np.abs(sp.csr_matrix(model.mass).diagonal())))
    return k / m if m > 0.0 and k > 0.0 else 1.0


def free_free_frequencies(model: FEModel, count: int) -> tuple[np.ndarray, np.ndarray]:
    """The lowest `count` eigenvalues of K x = w^2 M x as frequencies (Hz; negative for a
    negative w^2, found only from rounding) and a flag per mode: rigid-body (the first
    `rigid_modes(model)` modes). Shift-invert about a small negative
    shift, so that K may be singular (free-free) and M semi-definite; dense below 600 DOF."""
    from scipy.linalg import eigh
    from scipy.sparse.linalg import eigsh

    scale = _scale(model)
    shift = -1e-6 * scale
    K, M = sp.csr_matrix(model.stiffness), sp.csr_matrix(model.mass)
    n = K.shape[0]
    count = min(count, n)
    if n <= DENSE_LIMIT or count >= n - 1:
        # M v = nu (K - shift M) v with nu = 1 / (w^2 - shift): the largest nu are wanted
        nu = eigh(M.toarray(), (K - shift * M).toarray(), eigvals_only=True)
        nu = np.sort(nu)[::-1][:count]
        squares = shift + 1.0 / nu
    else:
        squares = np.sort(
            eigsh(K, k=count, M=M, sigma=shift, which="LM", return_eigenvectors=False)
        )
    hertz = np.sign(squares) * np.sqrt(np.abs(squares)) / (2.0 * np.pi)
    return hertz, np.arange(count) < rigid_modes(model)


def rigid_modes(model: FEModel) -> int:
    """How many rigid-body motions the model has (6 when free-free, fewer when DOF are
    constrained): the rigid-body fields (translations, rotations about the nodes' centroid)
    that K leaves unloaded, |K r| <= 1e-8 max|K| max|r|."""
    gamma, r0 = rigid_fields(model)
    centroid = np.mean(model.coordinates, axis=0)
    r0 = r0 - gamma @ np.cross(np.eye(3), centroid).T  # rotations about the centroid
    fields = np.hstack([gamma, r0])
    K = sp.csr_matrix(model.stiffness)
    largest = float(abs(K).max()) if K.nnz else 0.0
    loads = np.max(np.abs(K @ fields), axis=0)
    sizes = np.max(np.abs(fields), axis=0)
    return int(np.count_nonzero((sizes > 0) & (loads <= _RIGID * largest * sizes)))
