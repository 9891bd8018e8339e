"""Equations of motion of a modal body in the floating frame of reference (SI).

Velocities w = [xd (global, m/s), omega (body axes, rad/s), zeta_d]; the frame origin is
the undeformed centre of mass. Kinetic energy T = 1/2 w^T M(zeta) w with (first mass moment
c = I2 + I3 zeta, Theta = I7 - sum_j zeta_j (I8_j + I8_j^T) - sum_jk zeta_j zeta_k I9_jk,
Iwz = I4 + sum_j zeta_j I5_j):

    M = [[m I, -A c~, A I3], [., Theta, Iwz], [., ., I6]]

The quadratic velocity vector comes from T alone (Kirchhoff's equations on SE(3) with body
velocities v' = A^T xd, Lagrange's for zeta; the v' terms cancel), so it holds for any FE
mass matrix, rotary inertia included:

    f_t = -A (w~ w~ c + 2 w~ I3 zeta_d)
    f_w = -w~ (Theta w + Iwz zeta_d) - Theta_d w - (sum_j zeta_d_j I5_j) zeta_d
    f_z,j = 1/2 w^T dTheta/dzeta_j w + w^T I5_j zeta_d - [(sum_k zeta_d_k I5_k)^T w]_j

with Theta_d = sum_j zeta_d_j dTheta/dzeta_j. Elastic and damping forces -K zeta - D zeta_d,
K = diag(omega_i^2), D = diag(2 xi_i omega_i); gravity g: m g, c~ A^T g, I3^T A^T g.
The tests check M and f against nodal sums over particles (the notes' oracle).
"""

from __future__ import annotations

import numpy as np

from mechlib.core.rotation import skew
from mechlib.flexible.modal_component import ModalComponent

__all__ = ["ModalBody"]


class ModalBody:
    """The mass matrix and forces of one modal body in velocities w (see module docstring)."""

    def __init__(self, component: ModalComponent):
        self.component = component
        inv = component.invariants
        self.n = component.count
        self._i8s = inv.I8 + inv.I8.transpose(0, 2, 1)  # (n, 3, 3)
        self._i9s = inv.I9 + inv.I9.transpose(1, 0, 2, 3)  # (n, n, 3, 3)

    def first_moment(self, zeta: np.ndarray) -> np.ndarray:
        inv = self.component.invariants
        return inv.I2 + inv.I3 @ zeta

    def theta(self, zeta: np.ndarray) -> np.ndarray:
        """Inertia tensor about the frame origin, body axes (kg m^2)."""
        inv = self.component.invariants
        out = inv.I7 - np.einsum("j,jab->ab", zeta, inv.I8 + inv.I8.transpose(0, 2, 1))
        return out - np.einsum("j,k,jkab->ab", zeta, zeta, inv.I9)

    def d_theta(self, zeta: np.ndarray) -> np.ndarray:
        """dTheta/dzeta_j (n, 3, 3)."""
        return -self._i8s - np.einsum("k,jkab->jab", zeta, self._i9s)

    def coupling(self, zeta: np.ndarray) -> np.ndarray:
        """Iwz = I4 + sum_j zeta_j I5_j (3, n)."""
        inv = self.component.invariants
        return inv.I4 + np.einsum("j,jan->an", zeta, inv.I5)

    def mass(self, A: np.ndarray, zeta: np.ndarray) -> np.ndarray:
        """M (6 + n, 6 + n) in velocities w."""
        inv, n = self.component.invariants, self.n
        out = np.zeros((6 + n, 6 + n))
        out[:3, :3] = inv.I1 * np.eye(3)
        out[:3, 3:6] = -A @ skew(self.first_moment(zeta))
        out[:3, 6:] = A @ inv.I3
        out[3:6, 3:6] = self.theta(zeta)
        out[3:6, 6:] = self.coupling(zeta)
        out[6:, 6:] = inv.I6
        out[3:, :3] = out[:3, 3:].T
        out[6:, 3:6] = out[3:6, 6:].T
        return out

    def quadratic(
        self, A: np.ndarray, omega: np.ndarray, zeta: np.ndarray, zeta_d: np.ndarray
    ) -> np.ndarray:
        """The quadratic velocity vector f_v (6 + n)."""
        inv = self.component.invariants
        c, theta, iwz = self.first_moment(zeta), self.theta(zeta), self.coupling(zeta)
        dtheta = self.d_theta(zeta)
        i5_rate = np.einsum("j,jan->an", zeta_d, inv.I5)  # sum_j zeta_d_j I5_j (3, n)
        wx = skew(omega)
        f_t = -A @ (wx @ (wx @ c) + 2.0 * wx @ (inv.I3 @ zeta_d))
        f_w = -wx @ (theta @ omega + iwz @ zeta_d)
        f_w -= np.einsum("j,jab->ab", zeta_d, dtheta) @ omega + i5_rate @ zeta_d
        f_z = 0.5 * np.einsum("a,jab,b->j", omega, dtheta, omega)
        f_z += np.einsum("a,jan,n->j", omega, inv.I5, zeta_d) - i5_rate.T @ omega
        return np.concatenate([f_t, f_w, f_z])

    def applied(
        self, A: np.ndarray, zeta: np.ndarray, zeta_d: np.ndarray, gravity: np.ndarray
    ) -> np.ndarray:
        """Gravity, modal stiffness and damping forces (6 + n)."""
        comp = self.component
        g_body = A.T @ gravity
        return np.concatenate(
            [
                comp.mass * gravity,
                skew(self.first_moment(zeta)) @ g_body,
                comp.invariants.I3.T @ g_body - comp.stiffness * zeta - comp.viscous * zeta_d,
            ]
        )
