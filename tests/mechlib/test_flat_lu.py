"""LU factors in flat arrays (mechlib.linalg.flat_lu) and the LAPACK routines the kernels call
(mechlib.linalg.lapack), against scipy's LAPACK and numpy's dense solve.

- The band ordering of a spherical-joint chain's saddle matrix (reverse Cuthill-McKee) has
  13 sub- and 13 superdiagonals at 12, 20 and 50 links (132-550 rows): the band LU's cost
  grows with the length only; a pattern without a narrow band keeps SuperLU.
- `refactor` gives bit for bit the factors of scipy's dgetrf (dense, the arithmetic of
  mechlib.linalg.factor.factor) and dgbtrf (band) of the same row-equilibrated matrix, and the
  kernel's condition estimate equals scipy's dgecon.
- Band factors solve the saddle matrix, its transpose and several right sides as numpy's
  dense solve does, to 1e-11 relative (measured 1e-13); the compiled band solve equals the
  Python one exactly (the same dgbtrs).
- A zero row, a repeated row and a non-finite entry are refused (the caller then takes the
  dense path, which names the culprits).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg.lapack as scipy_lapack

from mechlib.linalg import lapack
from mechlib.linalg.factor import (
    SaddlePattern,
    augmented,
    factor,
    factor_saddle,
    solve_factored,
)
from mechlib.linalg.flat_lu import (
    BAND,
    DENSE,
    Banded,
    FlatLayout,
    factor_data,
    factors,
    lu_solve,
    refactor,
    refactor_dense,
)
from mechlib.system.system import System

from ._models import falling_chain

TOL_SOLVE = 1e-11  # of the solution's size; measured 1e-13


def _chain_saddle(links: int, seed: int = 3) -> tuple[np.ndarray, np.ndarray, SaddlePattern]:
    """M and phi_q of a falling chain at a generic state, and their pattern."""
    system = System(falling_chain(links))
    rng = np.random.default_rng(seed)
    k = system.kin(system.design_q() + 0.1 * rng.standard_normal(system.nq), None, 0.0)
    top, jac = system.mass(k), system.phi_q(k)
    return top, jac, SaddlePattern(top, jac)


@pytest.mark.parametrize("links", [12, 20, 50])
def test_a_chain_has_a_band_of_fixed_width(links: int) -> None:
    _, _, pattern = _chain_saddle(links)
    layout = pattern.layout
    assert layout is not None and layout.ints[0] == BAND
    assert tuple(layout.ints[1:4]) == (11 * links, 13, 13)  # 7 + 4 rows per link


def test_a_pattern_without_a_narrow_band_keeps_superlu() -> None:
    rng = np.random.default_rng(160)
    n = 160
    top = np.eye(n)
    jac = (rng.random((n // 3, n)) < 0.1) * rng.standard_normal((n // 3, n))
    jac[np.arange(n // 3), np.arange(n // 3)] += 1.0
    pattern = SaddlePattern(top, jac)
    assert pattern.layout is None
    lu = factor_saddle(top, jac, pattern)
    assert not isinstance(lu, (tuple, Banded))


def test_small_patterns_are_dense() -> None:
    top, jac, _ = _chain_saddle(3)
    layout = SaddlePattern(top, jac).layout
    assert layout is not None and layout.ints[0] == DENSE


def test_dense_refactor_equals_scipy() -> None:
    top, jac, _ = _chain_saddle(4)
    pattern = SaddlePattern(top, jac)
    layout = pattern.layout
    assert layout is not None
    ints, floats = layout.new()
    assert refactor(pattern.values(top, jac), *layout.kernel_args(), ints, floats)
    got_lu, got_piv, got_rows = factors(ints, floats)
    want = factor(augmented(top, jac))
    assert want is not None
    want_lu, want_piv, want_rows = want
    np.testing.assert_array_equal(got_rows, want_rows)
    np.testing.assert_array_equal(got_lu, want_lu)
    np.testing.assert_array_equal(got_piv, want_piv)
    norm = float(np.abs(got_lu).sum(axis=0).max())
    assert lapack.gecon(floats, len(got_rows), norm) == scipy_lapack.dgecon(want_lu, norm)[0]


def test_band_refactor_equals_scipy() -> None:
    top, jac, pattern = _chain_saddle(20)
    layout = pattern.layout
    assert layout is not None
    ints, floats = layout.new()
    assert refactor(pattern.values(top, jac), *layout.kernel_args(), ints, floats)
    n, kl, ku = (int(v) for v in ints[1:4])
    perm = ints[4 : 4 + n]
    matrix = augmented(top, jac)[np.ix_(perm, perm)]
    scaled = matrix * (1.0 / np.abs(matrix).max(axis=1))[:, None]  # as factor() scales
    lead = 2 * kl + ku + 1
    band = np.zeros((lead, n), order="F")
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            band[kl + ku + i - j, j] = scaled[i, j]
    want, want_piv, info = scipy_lapack.dgbtrf(band, kl, ku)
    assert info == 0
    got = factors(ints, floats)
    assert isinstance(got, Banded)
    np.testing.assert_array_equal(got.band, want)
    np.testing.assert_array_equal(got.piv, want_piv)


def test_band_factors_solve_as_numpy() -> None:
    top, jac, pattern = _chain_saddle(20)
    lu = factor_saddle(top, jac, pattern)
    assert isinstance(lu, Banded)
    matrix = augmented(top, jac)
    rng = np.random.default_rng(5)
    b = rng.standard_normal(matrix.shape[0])
    several = rng.standard_normal((matrix.shape[0], 3))
    for got, want in [
        (solve_factored(lu, b), np.linalg.solve(matrix, b)),
        (solve_factored(lu, b, transpose=True), np.linalg.solve(matrix.T, b)),
        (solve_factored(lu, several), np.linalg.solve(matrix, several)),
        (lu_solve(*factor_data(lu), b), np.linalg.solve(matrix, b)),
    ]:
        assert np.abs(got - want).max() < TOL_SOLVE * np.abs(want).max()
    np.testing.assert_array_equal(lu_solve(*factor_data(lu), b), solve_factored(lu, b))


@pytest.mark.parametrize("links", [4, 20])  # dense, band
@pytest.mark.parametrize("defect", ["zero row", "repeated row", "not finite"])
def test_singular_matrices_are_refused(links: int, defect: str) -> None:
    top, jac, _ = _chain_saddle(links)
    if defect == "zero row":
        jac[2] = 0.0
    elif defect == "repeated row":
        jac[3] = jac[2]
    else:
        top[0, 0] = np.nan
    pattern = SaddlePattern(*_chain_saddle(links)[:2])  # the generic structure
    layout = pattern.layout
    assert isinstance(layout, FlatLayout)
    ints, floats = layout.new()
    assert not refactor(pattern.values(top, jac), *layout.kernel_args(), ints, floats)
    assert factor_saddle(top, jac, pattern) is None  # the dense path's verdict


@pytest.mark.parametrize("defect", ["none", "zero row", "repeated row", "not finite"])
def test_dense_refactor_in_place_equals_refactor(defect: str) -> None:
    """refactor_dense (the matrix already in the factors' store, by columns: the modal
    runs' factorisation) gives refactor's factors bit for bit, and its singular verdicts."""
    top, jac, _ = _chain_saddle(4)
    if defect == "zero row":
        jac[2] = 0.0
    elif defect == "repeated row":
        jac[3] = jac[2]
    elif defect == "not finite":
        top[0, 0] = np.nan
    pattern = SaddlePattern(*_chain_saddle(4)[:2])
    layout = pattern.layout
    assert layout is not None and layout.ints[0] == DENSE
    ints, floats = layout.new()
    ok = refactor(pattern.values(top, jac), *layout.kernel_args(), ints, floats)
    assert ok == (defect == "none")
    matrix = augmented(top, jac)
    n = matrix.shape[0]
    ints_in, floats_in = np.zeros(2 + n, dtype=np.int64), np.empty(n * n + n)
    ints_in[1] = n
    floats_in[: n * n] = matrix.ravel(order="F")
    assert refactor_dense(ints_in, floats_in) == ok
    if ok:
        np.testing.assert_array_equal(ints_in, ints)
        np.testing.assert_array_equal(floats_in, floats)
