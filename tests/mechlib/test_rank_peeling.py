"""Redundant equations and degrees of freedom of large mechanisms (issue 39 item 6): the
rows set aside as independent (`peel_independent`) and the sparse constraint Jacobian
(`System.phi_q_sparse`) leave every answer as the dense test gives it, and a chain's check
grows as its number of bodies.

Reference: a row is dependent exactly when it does not raise the rank of the rows before
it (numpy.linalg.matrix_rank, SVD, of each prefix in the order examined).
"""

from __future__ import annotations

import time

import numpy as np
import pytest

from benchmarks.planar import fourbar_chain
from mechlib.checks.model_check import check_model, inspect_mechanism
from mechlib.linalg import rank
from mechlib.linalg.sparse_rows import SparseRows
from mechlib.model.analysis import Dynamic
from mechlib.system.planar import PlanarSystem, make_system
from mechlib.system.system import System
from tests.mechlib._models import falling_chain, falling_slider_crank, slider_crank


def _prefix_rank_dependent(matrix: np.ndarray) -> list[int]:
    """The rows that do not raise the rank of those before them (SVD of each prefix)."""
    found, previous = [], 0
    for i in range(matrix.shape[0]):
        now = np.linalg.matrix_rank(matrix[: i + 1], tol=1e-9)
        if now == previous:
            found.append(i)
        previous = now
    return found


def _tree_with_loops(seed: int) -> np.ndarray:
    """Block rows of a tree of 'bodies' (3 columns each) with loops closed by rows that
    combine earlier ones, and a repeated row: dependent rows planted among independent."""
    rng = np.random.default_rng(seed)
    bodies = 12
    rows = []
    for b in range(bodies):
        parent = rng.integers(0, b) if b else None
        for _ in range(2):
            row = np.zeros(3 * bodies)
            row[3 * b : 3 * b + 3] = rng.standard_normal(3)
            if parent is not None:
                row[3 * parent : 3 * parent + 3] = rng.standard_normal(3)
            rows.append(row)
    rows.insert(9, 0.5 * rows[2] - 2.0 * rows[7])  # a loop: a combination of earlier rows
    rows.append(rows[4].copy())  # a repeated equation
    rows.append(np.zeros(3 * bodies))  # an equation of nothing
    return np.array(rows)


@pytest.mark.parametrize("seed", range(6))
def test_peeled_rows_and_dense_test_find_the_prefix_rank_dependents(seed: int) -> None:
    matrix = _tree_with_loops(seed)
    expected = _prefix_rank_dependent(matrix)
    labels = [f"r{i}" for i in range(matrix.shape[0])]
    found = rank.find_redundant(matrix, labels, labels)
    assert [r.row for r in found] == expected
    assert {9, matrix.shape[0] - 2, matrix.shape[0] - 1} <= set(expected)
    loop = next(r for r in found if r.row == 9)
    assert loop.depends_on == ("r2", "r7")  # the rows it combines, by least squares
    assert rank.degrees_of_freedom(matrix) == matrix.shape[1] - np.linalg.matrix_rank(matrix)
    # the rows of a loop are never set aside; the dependent ones never are
    assert not rank.peel_independent(matrix)[expected].any()


def test_a_chain_is_set_aside_whole_and_a_redundant_loop_is_not() -> None:
    """An open chain's rows all go to the peeled side (no dense work left); a loop with a
    redundant joint keeps its rows for the dense test, which finds the redundancy."""
    system = System(falling_chain(30))
    k = system.kin(system.design_q())
    assert rank.peel_independent(system.phi_q_sparse(k)).all()
    mech, _ = slider_crank()
    mech.add_joint("A2", "revolute", bodies=("crank", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    closed = System(mech)
    k = closed.kin(closed.design_q())
    assert not rank.peel_independent(closed.phi_q_sparse(k)).all()


@pytest.mark.parametrize("make", [lambda: falling_chain(8), falling_slider_crank])
def test_sparse_jacobian_is_the_dense_one(make) -> None:
    system = System(make())
    rng = np.random.default_rng(3)
    q = system.design_q() + 0.05 * rng.standard_normal(system.nq)
    k = system.kin(q)
    sparse = system.phi_q_sparse(k)
    assert sparse.shape == system.phi_q(k).shape
    np.testing.assert_array_equal(sparse.toarray(), system.phi_q(k))
    assert np.array_equal(SparseRows.from_dense(system.phi_q(k)).values, sparse.values)


def test_planar_sparse_jacobian_is_the_dense_one() -> None:
    """The planar reduction of the non-zeros (a few rows at a time) equals the dense one."""
    system = make_system(fourbar_chain(3))
    assert isinstance(system, PlanarSystem)
    rng = np.random.default_rng(5)
    k = system.kin(system.design_q() + 0.05 * rng.standard_normal(system.nq))
    np.testing.assert_array_equal(system.phi_q_sparse(k).toarray(), system.phi_q(k))


def test_redundant_loop_named_as_before() -> None:
    """A second revolute on the crank's axis: redundant rows named by joint, as the dense
    test named them (the checks' message of a four-bar-like loop)."""
    mech, _ = slider_crank()
    mech.add_joint("A2", "revolute", bodies=("crank", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    found = inspect_mechanism(mech).redundant
    assert found and all("A2" in text and "dependent on A" in text for text in found)


def _chain_check(links: int, calls: list[int]) -> float:
    """Seconds of `check_model` of a chain of `links` bodies; appends its SVD calls."""
    system = System(falling_chain(links))
    svd = np.linalg.svd
    count = [0]

    def counted(*args, **kwargs):
        count[0] += 1
        return svd(*args, **kwargs)

    start = time.perf_counter()
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(np.linalg, "svd", counted)
        patch.setattr(System, "phi_q", lambda *_: pytest.fail("dense Jacobian built"))
        assert check_model(system, Dynamic(end=1.0, step=1e-3)) == []
    calls.append(count[0])
    return time.perf_counter() - start


def test_chain_check_is_linear_in_its_bodies() -> None:
    """2000 spherical links (8000 equations, 14000 coordinates; the dense Jacobian alone
    would be 0.9 GB): no dense Jacobian; the small blocks examined (SVDs) grow exactly as
    the bodies (4 more per link: its joint's x, y, z equations, then its normalisation;
    measured 3996 and 7996); the check of 2000 links measured 0.6-1.1 s here, capped at
    10 s."""
    calls: list[int] = []
    _chain_check(1000, calls)
    seconds = _chain_check(2000, calls)
    assert calls[1] - calls[0] == 4 * 1000
    assert calls[0] <= 4 * 1000
    assert seconds < 10.0


def test_values_that_are_not_finite_are_left_to_the_dense_test() -> None:
    """A failing step's Jacobian (inf, NaN: factor.singular_failure explains it): no block
    with them is set aside and nothing raises (an SVD of inf does not converge)."""
    matrix = _tree_with_loops(0)
    matrix[3, 4], matrix[20, 30] = np.inf, np.nan
    labels = [f"r{i}" for i in range(matrix.shape[0])]
    peeled = rank.peel_independent(matrix)
    assert not peeled[3] and not peeled[20]
    with np.errstate(invalid="ignore"):  # NaN through the dense test's products, as before
        rank.find_redundant(matrix, labels, labels)
        rank.degrees_of_freedom(matrix)
