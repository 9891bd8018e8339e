"""The checks made before any eigen-solver sees an imported model (loadcases.flexible
.solvable), on both sides of the dense limit: a valid beam passes, a singular one is named
at the DOF that carries its zero-energy deformation, and the verdict agrees with the
eigenvalues of the matrix itself (numpy's eigvalsh, the independent reference)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from loadcases.flexible.solvable import (
    SINGULAR,
    interior_problem,
    rigid_body_problem,
    translation_mass_problem,
)
from mechlib.flexible.fe_model import FEModel
from tests.loadcases.flexible.beam import SI_BEAM, assembled


def _model(elements: int, K: np.ndarray | None = None, M: np.ndarray | None = None) -> FEModel:
    """A free-free beam of `elements` elements held at its first node (the interface)."""
    K0, M0, x = assembled(SI_BEAM, elements)
    n = len(x)
    return FEModel(
        np.arange(1, n + 1),
        np.column_stack([x, np.zeros(n), np.zeros(n)]),
        np.column_stack([np.repeat(np.arange(n), 6), np.tile(np.arange(6), n)]),
        sp.csr_matrix(K0 if K is None else K),
        sp.csr_matrix(M0 if M is None else M),
        (0,),
    )


def _lowest_interior(model: FEModel, matrix: sp.spmatrix) -> float:
    """The lowest eigenvalue of the interior block scaled to a unit diagonal (eigvalsh)."""
    block = matrix.toarray()[6:, 6:]
    d = 1.0 / np.sqrt(np.diag(block))
    return float(np.linalg.eigvalsh(d[:, None] * block * d[None, :])[0])


@pytest.mark.parametrize("elements", [3, 260])  # 18 and 1566 DOF: dense, then LDL^T pivots
def test_valid_beam_passes(elements: int) -> None:
    model = _model(elements)
    assert interior_problem(model, model.stiffness, "K") is None
    assert interior_problem(model, model.mass, "M") is None
    assert rigid_body_problem(model) is None
    assert translation_mass_problem(model) is None
    if elements == 3:
        assert _lowest_interior(model, model.stiffness) > SINGULAR


@pytest.mark.parametrize("elements", [3, 260])
def test_torsion_free_interior_is_named(elements: int) -> None:
    """The torsion terms of the interior nodes replaced by an all-ones block: positive
    diagonal, rank one, so singular with two or more interior nodes (x = e_a - e_b)."""
    K, _, _ = assembled(SI_BEAM, elements)
    rx = np.arange(3, K.shape[0], 6)
    K[np.ix_(rx, rx)] = 0.0
    K[rx[0], rx[0]] = 1.0
    K[np.ix_(rx[1:], rx[1:])] = 1.0
    model = _model(elements, K=K)
    problem = interior_problem(model, model.stiffness, "K")
    assert problem is not None and "with the interface nodes held" in problem
    if elements == 3:
        assert "rx" in problem
        assert _lowest_interior(model, model.stiffness) < SINGULAR


def test_rigid_and_mass_scale() -> None:
    K, M, _ = assembled(SI_BEAM, 3)
    grounded = K.copy()
    grounded[0, 0] *= 2.0
    assert "5 rigid-body modes" in (rigid_body_problem(_model(3, K=grounded)) or "")
    assert "outside" in (translation_mass_problem(_model(3, M=M * 1e-300)) or "")
    rotations = np.tile([False] * 3 + [True] * 3, 4)
    only = np.where(np.outer(rotations, rotations), M, 0.0)
    assert "no mass on translations" in (translation_mass_problem(_model(3, M=only)) or "")


def test_rigid_rotation_without_inertia() -> None:
    """A beam along x without torsional inertia: every node on the axis, so the rigid
    rotation about x has no kinetic energy (x^T M x = 0 for x the rotation field)."""
    _, M, _ = assembled(SI_BEAM, 3)
    rx = np.arange(3, M.shape[0], 6)
    M[rx, :] = M[:, rx] = 0.0
    problem = translation_mass_problem(_model(3, M=M))
    assert problem is not None and "rotation about x no inertia" in problem
