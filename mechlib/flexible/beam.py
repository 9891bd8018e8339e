"""3-D Timoshenko beam element (12 DOF) and the assembly of beams into an `FEModel` (SI).

Bending uses the interdependent interpolation element (IIE) of Friedman & Kosmatka, Comput.
Struct. 47 (1993) 473-481: cubic deflection and quadratic rotation shape functions that solve
the static Timoshenko equations exactly, so that a cantilever's tip deflection
P L^3/(3 E I) + P L/(k G A) is exact with one element. Stiffness and consistent mass
(translation and rotary inertia) are integrated from the same shape functions by 4-point
Gauss quadrature, exact for these polynomials. Axial and torsion: linear elements.
Local DOF per node: ux, uy, uz, rx, ry, rz; local x along the beam, y, z its section axes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from mechlib.flexible.fe_model import BeamSet, FEModel

__all__ = ["Material", "Section", "assemble_beams", "beam_matrices", "section_axes"]

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(4)
_XI = 0.5 * (_GAUSS_X + 1.0)
_WEIGHT = 0.5 * _GAUSS_W


@dataclass(frozen=True)
class Material:
    """Isotropic material: Young's modulus E (Pa), Poisson's ratio nu, density rho (kg/m^3)."""

    E: float
    nu: float
    rho: float

    @property
    def G(self) -> float:
        """Shear modulus (Pa)."""
        return self.E / (2.0 * (1.0 + self.nu))


@dataclass(frozen=True)
class Section:
    """Beam section: area A (m^2), second moments Iy = int z^2 dA and Iz = int y^2 dA (m^4)
    about the local y and z axes, torsion constant J (m^4), shear coefficients ky, kz
    (None: rigid in shear, Euler-Bernoulli bending)."""

    A: float
    Iy: float
    Iz: float
    J: float
    ky: float | None = 5.0 / 6.0
    kz: float | None = 5.0 / 6.0

    @classmethod
    def rectangle(cls, width: float, height: float, shear: bool = True) -> Section:
        """Solid rectangle, `width` along local y and `height` along local z (m); shear
        coefficient 5/6; torsion constant of Roark (Table 10.7, case 4)."""
        a, b = max(width, height) / 2.0, min(width, height) / 2.0
        j = a * b**3 * (16.0 / 3.0 - 3.36 * b / a * (1.0 - b**4 / (12.0 * a**4)))
        k = 5.0 / 6.0 if shear else None
        return cls(width * height, width * height**3 / 12.0, height * width**3 / 12.0, j, k, k)


def _bending(L: float, EI: float, kGA: float | None, rhoA: float, rhoI: float):
    """(K, M) 4x4 of plane bending, DOF (v1, theta1, v2, theta2), theta = dv/dx for EB."""
    phi = 0.0 if kGA is None else 12.0 * EI / (kGA * L * L)
    mu = 1.0 / (1.0 + phi)
    k = np.zeros((4, 4))
    m = np.zeros((4, 4))
    for xi, w in zip(_XI, _WEIGHT):
        nv = mu * np.array(
            [
                2 * xi**3 - 3 * xi**2 - phi * xi + 1 + phi,
                L * (xi**3 - (2 + phi / 2) * xi**2 + (1 + phi / 2) * xi),
                -2 * xi**3 + 3 * xi**2 + phi * xi,
                L * (xi**3 - (1 - phi / 2) * xi**2 - phi / 2 * xi),
            ]
        )
        nt = mu * np.array(
            [6 / L * (xi**2 - xi), 3 * xi**2 - (4 + phi) * xi + 1 + phi]
            + [-6 / L * (xi**2 - xi), 3 * xi**2 - (2 - phi) * xi]
        )
        dnt = (mu / L) * np.array(
            [6 / L * (2 * xi - 1), 6 * xi - 4 - phi, -6 / L * (2 * xi - 1), 6 * xi - 2 + phi]
        )
        dnv = mu * np.array(
            [
                (6 * xi**2 - 6 * xi - phi) / L,
                3 * xi**2 - (4 + phi) * xi + 1 + phi / 2,
                (-6 * xi**2 + 6 * xi + phi) / L,
                3 * xi**2 - (2 - phi) * xi - phi / 2,
            ]
        )
        shear = dnv - nt
        k += w * L * EI * np.outer(dnt, dnt)
        if kGA is not None:
            k += w * L * kGA * np.outer(shear, shear)
        m += w * L * (rhoA * np.outer(nv, nv) + rhoI * np.outer(nt, nt))
    return k, m


def _rod(L: float, stiffness: float, inertia: float):
    """(K, M) 2x2 of a linear axial or torsion element: stiffness EA or GJ, inertia per
    length rho A or rho Ip."""
    return stiffness / L * np.array([[1.0, -1.0], [-1.0, 1.0]]), inertia * L / 6.0 * np.array(
        [[2.0, 1.0], [1.0, 2.0]]
    )


def beam_matrices(L: float, section: Section, material: Material):
    """(K, M) 12x12 in local axes of a beam of length L (m)."""
    s, E, G, rho = section, material.E, material.G, material.rho
    K = np.zeros((12, 12))
    M = np.zeros((12, 12))
    parts = [
        ([0, 6], _rod(L, E * s.A, rho * s.A)),
        ([3, 9], _rod(L, G * s.J, rho * (s.Iy + s.Iz))),
        ([1, 5, 7, 11], _bending(L, E * s.Iz, _kga(s.ky, G, s.A), rho * s.A, rho * s.Iz)),
    ]
    # bending in x-z: theta_y = -dw/dx, so the plane element's rotations change sign
    kz, mz = _bending(L, E * s.Iy, _kga(s.kz, G, s.A), rho * s.A, rho * s.Iy)
    flip = np.diag([1.0, -1.0, 1.0, -1.0])
    parts.append(([2, 4, 8, 10], (flip @ kz @ flip, flip @ mz @ flip)))
    for dofs, (k, m) in parts:
        K[np.ix_(dofs, dofs)] += k
        M[np.ix_(dofs, dofs)] += m
    return K, M


def _kga(k: float | None, G: float, A: float) -> float | None:
    return None if k is None else k * G * A


def section_axes(start: np.ndarray, end: np.ndarray, y_hint: np.ndarray) -> np.ndarray:
    """Rows: the local x (along the beam), y and z axes (global), y as close to `y_hint`
    as the beam allows."""
    ex = (end - start) / np.linalg.norm(end - start)
    ey = y_hint - (y_hint @ ex) * ex
    if np.linalg.norm(ey) < 1e-9:
        raise ValueError("a beam's section y axis is parallel to the beam")
    ey /= np.linalg.norm(ey)
    return np.array([ex, ey, np.cross(ex, ey)])


def assemble_beams(
    coordinates: np.ndarray,
    elements,
    *,
    node_ids=None,
    interface=(),
) -> FEModel:
    """An FEModel of beams between nodes (every node 6 DOF, SI).

    `elements`: iterable of (node a, node b, Section, Material, y_hint (3,)) with node
    indices into `coordinates` (n, 3) m; `interface`: node indices of the attachments."""
    xyz = np.asarray(coordinates, dtype=float)
    n = len(xyz)
    rows, cols, kv, mv, records = [], [], [], [], []
    for a, b, section, material, y_hint in elements:
        axes = section_axes(xyz[a], xyz[b], np.asarray(y_hint, dtype=float))
        length = float(np.linalg.norm(xyz[b] - xyz[a]))
        k, m = beam_matrices(length, section, material)
        records.append((a, b, material.E * section.A, length, axes))
        t = np.kron(np.eye(4), axes)
        dofs = np.r_[6 * a : 6 * a + 6, 6 * b : 6 * b + 6]
        rows.append(np.repeat(dofs, 12))
        cols.append(np.tile(dofs, 12))
        kv.append((t.T @ k @ t).ravel())
        mv.append((t.T @ m @ t).ravel())
    r, c = np.concatenate(rows), np.concatenate(cols)
    stiffness = sp.csr_matrix((np.concatenate(kv), (r, c)), shape=(6 * n, 6 * n))
    mass = sp.csr_matrix((np.concatenate(mv), (r, c)), shape=(6 * n, 6 * n))
    dof_map = np.column_stack([np.repeat(np.arange(n), 6), np.tile(np.arange(6), n)])
    ids = np.arange(1, n + 1) if node_ids is None else np.asarray(node_ids, dtype=int)
    beams = BeamSet(*(np.array(column) for column in zip(*records))) if records else None
    return FEModel(ids, xyz, dof_map, stiffness, mass, tuple(int(i) for i in interface), beams)
