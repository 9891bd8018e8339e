"""The closed-form 12-DOF Euler-Bernoulli beam element along x (Przemieniecki, Theory of
Matrix Structural Analysis, 1968, §5.6 stiffness and §11.4 consistent mass): the oracle of
the import tests, written independently of any reader.

DOF order per node: ux uy uz rx ry rz. Bending in the xz plane has the opposite sign of
the coupling terms (ry = -dw/dx).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Beam:
    """Section and material as products (consistent units): EA, EIy, EIz, GJ, rhoA (mass
    per length), rhoIp (torsional inertia per length), length L."""

    EA: float
    EIy: float
    EIz: float
    GJ: float
    rhoA: float
    rhoIp: float
    L: float


def _bending(EI: float, L: float, sign: float) -> np.ndarray:
    s = sign
    return (
        EI
        / L**3
        * np.array(
            [
                [12, s * 6 * L, -12, s * 6 * L],
                [s * 6 * L, 4 * L**2, -s * 6 * L, 2 * L**2],
                [-12, -s * 6 * L, 12, -s * 6 * L],
                [s * 6 * L, 2 * L**2, -s * 6 * L, 4 * L**2],
            ]
        )
    )


def _bending_mass(rhoA: float, L: float, sign: float) -> np.ndarray:
    s = sign
    return (
        rhoA
        * L
        / 420
        * np.array(
            [
                [156, s * 22 * L, 54, -s * 13 * L],
                [s * 22 * L, 4 * L**2, s * 13 * L, -3 * L**2],
                [54, s * 13 * L, 156, -s * 22 * L],
                [-s * 13 * L, -3 * L**2, -s * 22 * L, 4 * L**2],
            ]
        )
    )


def element(beam: Beam) -> tuple[np.ndarray, np.ndarray]:
    """(K, M) 12 x 12 of one element."""
    K, M = np.zeros((12, 12)), np.zeros((12, 12))
    pair = np.array([[1, -1], [-1, 1]])
    lumped_pair = np.array([[2, 1], [1, 2]]) / 6
    K[np.ix_([0, 6], [0, 6])] = beam.EA / beam.L * pair
    K[np.ix_([3, 9], [3, 9])] = beam.GJ / beam.L * pair
    M[np.ix_([0, 6], [0, 6])] = beam.rhoA * beam.L * lumped_pair
    M[np.ix_([3, 9], [3, 9])] = beam.rhoIp * beam.L * lumped_pair
    xy, xz = [1, 5, 7, 11], [2, 4, 8, 10]
    K[np.ix_(xy, xy)] = _bending(beam.EIz, beam.L, 1.0)
    K[np.ix_(xz, xz)] = _bending(beam.EIy, beam.L, -1.0)
    M[np.ix_(xy, xy)] = _bending_mass(beam.rhoA, beam.L, 1.0)
    M[np.ix_(xz, xz)] = _bending_mass(beam.rhoA, beam.L, -1.0)
    return K, M


def assembled(beam: Beam, elements: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(K, M, x) of `elements` equal elements of length beam.L in a row along x."""
    n = 6 * (elements + 1)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    k, m = element(beam)
    for e in range(elements):
        rows = slice(6 * e, 6 * e + 12)
        K[rows, rows] += k
        M[rows, rows] += m
    return K, M, beam.L * np.arange(elements + 1)


# The file-unit beam of the import tests (mm, N, s; mass unit t): every term of K and M is
# a short exact number, so that any field width keeps it exact.
FILE_BEAM = Beam(EA=2e6, EIy=4000.0, EIz=8000.0, GJ=3000.0, rhoA=210.0, rhoIp=3.0, L=2.0)
# The same beam in SI (m, N, kg): what the readers must produce.
MM, TONNE = 1e-3, 1e3
SI_BEAM = Beam(
    EA=2e6,
    EIy=4000.0 * MM**2,
    EIz=8000.0 * MM**2,
    GJ=3000.0 * MM**2,
    rhoA=210.0 * TONNE / MM,
    rhoIp=3.0 * TONNE * MM,
    L=2.0 * MM,
)


def relative_error(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b|."""
    a = a.toarray() if hasattr(a, "toarray") else np.asarray(a)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))
