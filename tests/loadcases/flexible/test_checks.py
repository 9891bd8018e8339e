"""The mass-matrix check above the dense limit (LDL^T pivots, Sylvester's law of inertia)
agrees with the eigenvalues; rigid-body modes are counted from the stiffness."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from loadcases.flexible.checks import definiteness_problem, negative_pivots
from loadcases.flexible.summary import rigid_modes
from mechlib.flexible.fe_model import FEModel
from tests.loadcases.flexible.beam import FILE_BEAM, assembled


@pytest.fixture(scope="module")
def long_beam() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return assembled(FILE_BEAM, 300)  # 1806 DOF: above the dense limit of 1500


def test_large_consistent_mass_is_semi_definite(long_beam: tuple[np.ndarray, ...]) -> None:
    assert definiteness_problem(sp.csr_matrix(long_beam[1]), "M") is None


def test_large_indefinite_mass_is_found(long_beam: tuple[np.ndarray, ...]) -> None:
    M = long_beam[1].copy()
    M[600, 606] = M[606, 600] = 2.0 * M[600, 600]  # positive diagonal, x^T M x < 0
    problem = definiteness_problem(sp.csr_matrix(M), "M")
    assert problem is not None and "1 eigenvalues below" in problem
    assert int(np.count_nonzero(np.linalg.eigvalsh(M) < 0)) == 1  # what the pivots say


def test_pivots_count_negative_eigenvalues() -> None:
    matrix = sp.csr_matrix(
        np.diag([3.0, -1.0, 2.0, -5.0]) + 0.1 * np.eye(4, k=1) + 0.1 * np.eye(4, k=-1)
    )
    assert negative_pivots(matrix) == int(
        np.count_nonzero(np.linalg.eigvalsh(matrix.toarray()) < 0)
    )


def test_rigid_modes_free_and_clamped() -> None:
    K, M, x = assembled(FILE_BEAM, 3)
    n = len(x)
    dof_map = np.column_stack([np.repeat(np.arange(n), 6), np.tile(np.arange(6), n)])
    xyz = np.column_stack([x, np.zeros(n), np.zeros(n)])
    free = FEModel(np.arange(n), xyz, dof_map, sp.csr_matrix(K), sp.csr_matrix(M), ())
    assert rigid_modes(free) == 6
    kept = np.arange(6, 6 * n)  # node 0 clamped: its DOF left out
    clamped = FEModel(
        np.arange(n),
        xyz,
        dof_map[kept],
        sp.csr_matrix(K[np.ix_(kept, kept)]),
        sp.csr_matrix(M[np.ix_(kept, kept)]),
        (),
    )
    assert rigid_modes(clamped) == 0
