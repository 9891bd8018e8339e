"""The condition estimate's shortcut in the dense flat factorisation
(mechlib.linalg.flat_lu.surely_regular, issue 40): the factors' bound of ||B^-1||_1 is an
upper bound (against numpy's inverse, and above LAPACK's estimate, which is a lower
bound), and refactor_dense's singular verdict equals the estimate's (mechlib.linalg.factor.factor,
scipy's dgecon) on matrices whose condition numbers span 1e1-1e19: the shortcut proves the
well-conditioned ones regular (so gecon is skipped) and leaves the ill-conditioned ones to
gecon. The modal run's iteration matrix of Kane's beam (n = 46) is proved: bound 3.4 times
LAPACK's estimate, reciprocal condition at least 4.6e-5 (`python -m benchmarks.modal_kernels`).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg.lapack as scipy_lapack

from mechlib.linalg.factor import SaddlePattern, augmented, factor
from mechlib.linalg.flat_lu import (
    DENSE,
    inverse_norm_bound,
    refactor_dense,
    surely_regular,
)

from .test_flat_lu import _chain_saddle

CONDITIONS = [1e1, 1e4, 1e8, 1e11, 1e13, 1e14, 1e15, 1e16, 1e19]


def _graded(n: int, condition: float, seed: int) -> np.ndarray:
    """A random n x n matrix of 2-norm condition number `condition`, rows of mixed scale."""
    rng = np.random.default_rng(seed)
    left, _ = np.linalg.qr(rng.standard_normal((n, n)))
    right, _ = np.linalg.qr(rng.standard_normal((n, n)))
    values = np.geomspace(1.0, 1.0 / condition, n)
    return (left * values) @ right.T * rng.uniform(0.1, 10.0, n)[:, None]


def _flat(matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """DENSE flat factors' arrays holding `matrix` by columns (refactor_dense's input)."""
    n = matrix.shape[0]
    ints = np.zeros(2 + n, dtype=np.int64)
    ints[:2] = DENSE, n
    floats = np.empty(n * n + n)
    floats[: n * n] = matrix.ravel(order="F")
    return ints, floats


def _scaled_lu(matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The row-equilibrated matrix B, its getrf factors and its 1-norm (factor()'s)."""
    scaled = matrix / np.abs(matrix).max(axis=1)[:, None]
    lu, _, info = scipy_lapack.dgetrf(scaled)
    assert info == 0
    return scaled, lu, float(np.abs(scaled).sum(axis=0).max())


@pytest.mark.parametrize("condition", CONDITIONS)
def test_the_bound_is_above_the_inverse_norm(condition: float) -> None:
    for seed in range(3):
        scaled, lu, norm = _scaled_lu(_graded(20, condition, seed))
        bound = inverse_norm_bound(lu.ravel(order="F"), 20)
        estimate = 1.0 / (norm * scipy_lapack.dgecon(lu, norm)[0])  # a lower bound
        assert bound >= estimate * (1.0 - 1e-12)
        if condition <= 1e11:  # numpy's inverse accurate to about 1e-5 relative
            exact = np.abs(np.linalg.inv(scaled)).sum(axis=0).max()
            assert bound >= exact * (1.0 - 1e-4)


@pytest.mark.parametrize("n", [10, 40])
@pytest.mark.parametrize("condition", CONDITIONS)
def test_the_verdict_is_the_condition_estimates(condition: float, n: int) -> None:
    """Random dense matrices: the bound is loose for large ones (random L's comparison
    matrix grows its inverse about 2^n: 6e9 times the estimate at n = 40, 50 at n = 10,
    condition 10), so at n = 40 gecon decides almost always; at n = 10 the well-conditioned
    ones are proved."""
    for seed in range(3):
        matrix = _graded(n, condition, seed)
        ints, floats = _flat(matrix)
        assert refactor_dense(ints, floats) == (factor(matrix) is not None)
        _, lu, norm = _scaled_lu(matrix)
        proved = surely_regular(lu.ravel(order="F"), n, norm)
        if condition <= 1e4 and n == 10:
            assert proved  # gecon skipped
        if condition >= 1e14:
            assert not proved  # gecon decides


def test_a_saddle_matrix_is_proved_regular() -> None:
    """A chain's mass and constraint saddle matrix (the rigid runs' dense factors, n = 44):
    the bound 1.0e5 times LAPACK's estimate (measured), still far inside the threshold, so
    gecon is skipped."""
    top, jac, _ = _chain_saddle(4)
    assert SaddlePattern(top, jac).layout is not None
    scaled, lu, norm = _scaled_lu(augmented(top, jac))
    bound = inverse_norm_bound(lu.ravel(order="F"), scaled.shape[0])
    estimate = 1.0 / (norm * scipy_lapack.dgecon(lu, norm)[0])
    assert estimate <= bound * (1.0 + 1e-12) < 1e6 * estimate
    assert surely_regular(lu.ravel(order="F"), scaled.shape[0], norm)
