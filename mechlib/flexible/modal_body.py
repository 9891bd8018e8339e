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
The tests check M and f against nodal sums over particles (the notes' oracle). The terms are
compiled (mechlib.flexible.kernels, their one definition); this class hands them the
invariants and the scratch arrays they write into.
"""

from __future__ import annotations

import numpy as np

from mechlib.flexible import kernels
from mechlib.flexible.modal_component import ModalComponent

__all__ = ["ModalBody"]

_NO_LOADS = np.zeros((0, 6))


class ModalBody:
    """The mass matrix and forces of one modal body in velocities w (see module docstring)."""

    def __init__(self, component: ModalComponent):
        self.component = component
        inv = component.invariants
        self.n = n = component.count
        c = np.ascontiguousarray
        i8s, i9s = kernels.symmetrised(inv.I8, inv.I9)
        self.arrays = (
            float(inv.I1),
            c(inv.I2, float),
            c(inv.I3, float),
            c(inv.I4, float),
            c(inv.I5, float),
            c(inv.I6, float),
            c(inv.I7, float),
            i8s,
            i9s,
        )  # fmt: skip  (I8, I9 symmetrised: mechlib.flexible.kernels)
        self.stiffness = c(component.stiffness, float)
        self.viscous = c(component.viscous, float)
        geometric = component.geometric
        self.spin = np.zeros((0, n, n)) if geometric is None else c(geometric.spin, float)
        self.nodal = np.zeros((0, 6, n, n)) if geometric is None else c(geometric.nodal, float)
        # kept nodes: positions (k, 3) m, translations and rotations (k, 3, n) per mode
        self.positions = c(component.positions, float)
        self.phi = c(component.phi, float)
        self.phi_star = c(component.phi_star, float)
        self.scratch = (np.empty((6 + n, 6 + n)), np.empty(6 + n))  # M_w, f_w

    def first_moment(self, zeta: np.ndarray) -> np.ndarray:
        """c = I2 + I3 zeta (3,) (kg m), body axes."""
        out = np.empty(3)
        kernels.first_moment(zeta, self.arrays[1], self.arrays[2], out)
        return out

    def theta(self, zeta: np.ndarray) -> np.ndarray:
        """Inertia tensor about the frame origin, body axes (kg m^2)."""
        i7, i8, i9 = self.arrays[6:]
        out = np.empty((3, 3))
        kernels.theta(zeta, i7, i8, i9, out)
        return out

    def mass(self, A: np.ndarray, zeta: np.ndarray) -> np.ndarray:
        """M (6 + n, 6 + n) in velocities w."""
        out = np.empty((6 + self.n, 6 + self.n))
        kernels.body_mass(A, zeta, *self.arrays, out)
        return out

    def quadratic(
        self, A: np.ndarray, omega: np.ndarray, zeta: np.ndarray, zeta_d: np.ndarray
    ) -> np.ndarray:
        """The quadratic velocity vector f_v (6 + n)."""
        _, i2, i3, i4, i5, _, i7, i8, i9 = self.arrays
        out = np.zeros(6 + self.n)
        kernels.quadratic(A, omega, zeta, zeta_d, i2, i3, i4, i5, i7, i8, i9, out)
        return out

    def applied(
        self, A: np.ndarray, zeta: np.ndarray, zeta_d: np.ndarray, gravity: np.ndarray
    ) -> np.ndarray:
        """Gravity, modal stiffness and damping forces (6 + n)."""
        i1, i2, i3, i4, i5, _, i7, i8, i9 = self.arrays
        out = np.empty(6 + self.n)
        kernels.body_forces(
            A, np.zeros(3), zeta, zeta_d, gravity, False, i1, i2, i3, i4, i5, i7, i8, i9,
            self.stiffness, self.viscous, self.spin[:0], self.nodal[:0], _NO_LOADS, out,
        )  # fmt: skip
        return out
