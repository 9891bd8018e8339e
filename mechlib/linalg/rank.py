"""Well-posedness before numerics: degrees of freedom and redundant equations, by name.

Rows are examined in the order the mechanism defines them (normalisation, joints, then
couplers and motions); a row whose gradient lies in the span of the rows before it is
redundant, and the rows it depends on are found by least squares, so the report reads
"C: rotation about x, dependent on A, B, D".

Large mechanisms: before that dense test, blocks of rows that are independent of every
other row are set aside (`peel_independent`), so that the dense test sees only the core
(the loops) and the cost of a tree of N bodies (a chain) grows as N, not N^3.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass

import numpy as np

from mechlib.core.by_value import ByValue, value_key
from mechlib.linalg.sparse_rows import SparseRows

__all__ = [
    "RANK_TOLERANCE",
    "Redundancy",
    "degrees_of_freedom",
    "find_redundant",
    "peel_independent",
]

RANK_TOLERANCE = 1e-8
_COEFFICIENT_FLOOR = 1e-6
_PEEL_ROWS = 12  # rows a block set aside at once has at most (a body's joints, small SVDs)
# A block is set aside only when its smallest singular value clears the dense test's own
# threshold (tol x the larger of its row norm and the matrix scale) by this factor: a row
# near the threshold is left to the dense test, which decides it as it always has.
_PEEL_MARGIN = 1e3
# a sweep's runs in one worker: the Jacobians at their starts (a few models at a time)
_FOUND: ByValue[tuple[Redundancy, ...]] = ByValue(size=8)


@dataclass(frozen=True)
class Redundancy:
    """A dependent equation: its row index, label, owner and the owners it depends on."""

    row: int
    label: str
    owner: str
    depends_on: tuple[str, ...]

    def describe(self) -> str:
        others = ", ".join(self.depends_on) if self.depends_on else "itself"
        return f"{self.label}, dependent on {others}"


Jacobian = np.ndarray | SparseRows


def _sparse(phi_q: Jacobian) -> SparseRows:
    return phi_q if isinstance(phi_q, SparseRows) else SparseRows.from_dense(phi_q)


def _scale(phi_q: SparseRows) -> float:
    return max(phi_q.scale(), 1.0)


def peel_independent(phi_q: Jacobian, tol: float = RANK_TOLERANCE) -> np.ndarray:
    """The rows of `phi_q` proven independent of all the others, as a boolean mask.

    A set S of rows is independent of the rest when the columns G that only S touches
    carry a block S|G of full row rank: no combination of S's rows vanishes on G, and the
    other rows are zero there. Set S aside and the rest decides alone (the dependence of
    another row never needs S). Taken from the leaves inwards, the rows of a tree (a
    chain, an open linkage) all go; the rows of loops remain. Each block has at most
    `_PEEL_ROWS` rows: the work grows with the non-zeros, not with the matrix's size.
    """
    sparse = _sparse(phi_q)
    m = sparse.shape[0]
    row_cols = [sparse.row_cols(r).tolist() for r in range(m)]
    col_rows: list[set[int]] = [set() for _ in range(sparse.shape[1])]
    for r, c in zip(sparse.rows.tolist(), sparse.cols.tolist()):
        col_rows[c].add(r)
    scale = _scale(sparse)
    norms = sparse.row_norms()
    peeled = np.zeros(m, dtype=bool)
    queue = deque(c for c in range(len(col_rows)) if col_rows[c])
    queued = {*queue}
    while queue:
        c = queue.popleft()
        queued.discard(c)
        support = col_rows[c]
        if not support or len(support) > _PEEL_ROWS:
            continue
        rows = sorted(support)
        cols = sorted({j for r in rows for j in row_cols[r] if col_rows[j] <= support})
        if len(cols) < len(rows):
            continue
        if not _full_rank(
            sparse.block(rows, cols), _PEEL_MARGIN * tol * max(norms[rows].max(), scale)
        ):
            continue
        peeled[rows] = True
        for r in rows:
            for j in row_cols[r]:
                col_rows[j].discard(r)
                if col_rows[j] and j not in queued:
                    queue.append(j)
                    queued.add(j)
    return peeled


def _full_rank(block: np.ndarray, threshold: float) -> bool:
    """Whether `block` has full row rank with its smallest singular value above
    `threshold`; a block with values that are not finite (a failing step's matrix, where the
    dense test takes over, as before) never has."""
    if not np.isfinite(block).all() or not np.isfinite(threshold):
        return False
    try:
        return float(np.linalg.svd(block, compute_uv=False)[-1]) > threshold
    except np.linalg.LinAlgError:  # SVD did not converge: left to the dense test
        return False


def _core(phi_q: SparseRows, rows: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """The dense block of `rows` over the columns they touch, and those columns."""
    columns = np.unique(np.concatenate([phi_q.row_cols(r) for r in rows] or [np.empty(0, int)]))
    return phi_q.block(rows, columns), columns


def _independent_rows(
    phi_q: SparseRows, tol: float, peeled: np.ndarray, order: Sequence[int] | None = None
) -> tuple[list[int], list[int]]:
    """The rows not `peeled`, in `order` (default: as given), split into independent and
    dependent ones by Gram-Schmidt against the rows kept before them."""
    core = [i for i in (range(phi_q.shape[0]) if order is None else order) if not peeled[i]]
    independent: list[int] = []
    dependent: list[int] = []
    dense, _ = _core(phi_q, core)
    basis = np.empty_like(dense)
    kept = 0
    scale = _scale(phi_q)
    for i, row in zip(core, dense):
        v = row.copy()
        if kept:
            b = basis[:kept]
            v -= b.T @ (b @ v)
            v -= b.T @ (b @ v)  # second pass: Gram-Schmidt loses orthogonality otherwise
        norm = np.linalg.norm(v)
        if norm <= tol * max(float(np.linalg.norm(row)), scale):
            dependent.append(i)
        else:
            basis[kept] = v / norm
            kept += 1
            independent.append(i)
    return independent, dependent


def find_redundant(
    phi_q: Jacobian,
    labels: list[str],
    owners: list[str],
    body_names: AbstractSet[str] = frozenset(),
    tol: float = RANK_TOLERANCE,
    owner_rank: dict[str, int] | None = None,
) -> list[Redundancy]:
    """Dependent rows of `phi_q`, each with the joints/motions it depends on.

    Rows are taken owner by owner in `owner_rank` order (default: first appearance), so
    that the later joint of a loop is the one named. Kept per process by the values of
    every argument (mechlib.core.by_value): a sweep's runs that start with the same
    Jacobian (bit for bit) and names find its rows once.
    """
    sparse = _sparse(phi_q)
    inputs = (labels, owners, frozenset(body_names), tol, owner_rank or {})
    key = value_key(sparse.rows, sparse.cols, sparse.values, sparse.shape, *inputs)
    return list(_FOUND.get(key, lambda: _redundant_rows(sparse, *inputs)))


def _redundant_rows(
    sparse: SparseRows,
    labels: list[str],
    owners: list[str],
    body_names: AbstractSet[str],
    tol: float,
    owner_rank: dict[str, int],
) -> tuple[Redundancy, ...]:
    """find_redundant, computed."""
    rank = dict(owner_rank)
    for o in owners:
        rank.setdefault(o, len(rank) + 10**6)
    order = sorted(range(len(owners)), key=lambda i: (rank[owners[i]], i))
    # the peeled rows are independent of every other: no dependent row needs them
    independent, dependent = _independent_rows(sparse, tol, peel_independent(sparse, tol), order)
    found = []
    for i in dependent:
        block, _ = _core(sparse, [*independent, i])
        coef, *_ = np.linalg.lstsq(block[:-1].T, block[-1], rcond=None)
        big = np.abs(coef) > _COEFFICIENT_FLOOR * max(np.abs(coef).max(initial=0.0), 1e-300)
        names = []
        for j in np.asarray(independent)[big]:
            owner = owners[j]
            if owner not in names and owner != owners[i] and owner not in body_names:
                names.append(owner)
        found.append(Redundancy(i, labels[i], owners[i], tuple(names)))
    return tuple(found)


def degrees_of_freedom(phi_q: Jacobian, tol: float = RANK_TOLERANCE) -> int:
    """nq - rank(phi_q): the number of independent motions the constraints allow."""
    sparse = _sparse(phi_q)
    peeled = peel_independent(sparse, tol)
    independent, _ = _independent_rows(sparse, tol, peeled)
    return phi_q.shape[1] - int(peeled.sum()) - len(independent)
