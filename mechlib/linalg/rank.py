"""Well-posedness before numerics: degrees of freedom and redundant equations, by name.

Rows are examined in the order the mechanism defines them (normalisation, joints, then
couplers and motions); a row whose gradient lies in the span of the rows before it is
redundant, and the rows it depends on are found by least squares, so the report reads
"C: rotation about x, dependent on A, B, D".
"""

from __future__ import annotations

from collections.abc import Set as AbstractSet
from dataclasses import dataclass

import numpy as np

__all__ = ["RANK_TOLERANCE", "Redundancy", "degrees_of_freedom", "find_redundant"]

RANK_TOLERANCE = 1e-8
_COEFFICIENT_FLOOR = 1e-6


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


def _independent_rows(phi_q: np.ndarray, tol: float, order=None) -> tuple[list[int], list[int]]:
    basis: list[np.ndarray] = []
    independent, dependent = [], []
    scale = max(np.abs(phi_q).max(initial=0.0), 1.0)
    for i in range(phi_q.shape[0]) if order is None else order:
        row = phi_q[i]
        v = row.copy()
        if basis:
            b = np.array(basis)
            v -= b.T @ (b @ v)
            v -= b.T @ (b @ v)  # second pass: Gram-Schmidt loses orthogonality otherwise
        norm = np.linalg.norm(v)
        if norm <= tol * max(np.linalg.norm(row), scale):
            dependent.append(i)
        else:
            basis.append(v / norm)
            independent.append(i)
    return independent, dependent


def find_redundant(
    phi_q: np.ndarray,
    labels: list[str],
    owners: list[str],
    body_names: AbstractSet[str] = frozenset(),
    tol: float = RANK_TOLERANCE,
    owner_rank: dict[str, int] | None = None,
) -> list[Redundancy]:
    """Dependent rows of `phi_q`, each with the joints/motions it depends on.

    Rows are taken owner by owner in `owner_rank` order (default: first appearance), so
    that the later joint of a loop is the one named.
    """
    rank = dict(owner_rank or {})
    for o in owners:
        rank.setdefault(o, len(rank) + 10**6)
    order = sorted(range(len(owners)), key=lambda i: (rank[owners[i]], i))
    independent, dependent = _independent_rows(phi_q, tol, order)
    found = []
    for i in dependent:
        coef, *_ = np.linalg.lstsq(phi_q[independent].T, phi_q[i], rcond=None)
        big = np.abs(coef) > _COEFFICIENT_FLOOR * max(np.abs(coef).max(initial=0.0), 1e-300)
        names = []
        for j in np.asarray(independent)[big]:
            owner = owners[j]
            if owner not in names and owner != owners[i] and owner not in body_names:
                names.append(owner)
        found.append(Redundancy(i, labels[i], owners[i], tuple(names)))
    return found


def degrees_of_freedom(phi_q: np.ndarray, tol: float = RANK_TOLERANCE) -> int:
    """nq - rank(phi_q): the number of independent motions the constraints allow."""
    independent, _ = _independent_rows(phi_q, tol)
    return phi_q.shape[1] - len(independent)
