"""The nine inertia invariants of a modal body (Adams' numbering, seed 003 Table 1.1).

Field form (exact for any FE mass matrix, lumped or consistent, with or without rotational
DOF): Gamma (translation field), R0 (rotation field about the frame origin) and R_j (the
rotation field of mode j's translations) are (ndof, 3) matrices, see
`FEModel.skew_field`; then I1 = m, I2 = m c (first moment about the origin), I3 = Gamma^T M
Psi, I4 = R0^T M Psi, I5_j = R_j^T M Psi, I6 = Psi^T M Psi, I7 = R0^T M R0,
I8_j = -R0^T M R_j, I9_jk = -R_j^T M R_k. Units: SI with mass-normalised modes (a modal
coordinate in kg^0.5 m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechlib.flexible.fe_model import FEModel

__all__ = ["Invariants", "field_invariants"]


@dataclass(frozen=True)
class Invariants:
    """I1 (kg), I2 (3,), I3 (3, n), I4 (3, n), I5 (n, 3, n), I6 (n, n), I7 (3, 3),
    I8 (n, 3, 3), I9 (n, n, 3, 3) for n modes."""

    I1: float
    I2: np.ndarray
    I3: np.ndarray
    I4: np.ndarray
    I5: np.ndarray
    I6: np.ndarray
    I7: np.ndarray
    I8: np.ndarray
    I9: np.ndarray

    @property
    def count(self) -> int:
        """Number of modes."""
        return self.I3.shape[1]


def field_invariants(model: FEModel, psi: np.ndarray, origin: np.ndarray) -> Invariants:
    """The invariants of modes `psi` (ndof, n) about the frame `origin` (3,) m."""
    gamma = model.translation_field()
    r0 = model.skew_field(model.coordinates - origin, rotations=True)
    mass = model.mass
    m_gamma, m_r0, m_psi = mass @ gamma, mass @ r0, mass @ psi
    moment = gamma.T @ m_r0  # -skew(I2)
    n, nodes = psi.shape[1], model.dof_map[:, 0]
    trans = model.dof_map[:, 1] < 3
    r_modes, mr_modes = [], []
    for j in range(n):
        shape = np.zeros((len(model.node_ids), 3))
        shape[nodes[trans], model.dof_map[trans, 1]] = psi[trans, j]
        r_j = model.skew_field(shape, rotations=False)
        r_modes.append(r_j)
        mr_modes.append(mass @ r_j)
    i9 = np.zeros((n, n, 3, 3))
    for j in range(n):
        for k in range(n):
            i9[j, k] = -r_modes[j].T @ mr_modes[k]
    return Invariants(
        I1=float(gamma[:, 0] @ m_gamma[:, 0]),
        I2=np.array([moment[1, 2], moment[2, 0], moment[0, 1]]),
        I3=gamma.T @ m_psi,
        I4=r0.T @ m_psi,
        I5=np.array([r.T @ m_psi for r in r_modes]).reshape(n, 3, n),
        I6=psi.T @ m_psi,
        I7=r0.T @ m_r0,
        I8=np.array([-m_r0.T @ r for r in r_modes]).reshape(n, 3, 3),
        I9=i9,
    )
