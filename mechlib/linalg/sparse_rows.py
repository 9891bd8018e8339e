"""A matrix kept as its non-zero entries, by row: what the checks of a large mechanism read
(a constraint Jacobian of N bodies has O(N) non-zeros among its O(N^2) entries).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["SparseRows"]


@dataclass(frozen=True)
class SparseRows:
    """Entries `values[e]` at (`rows[e]`, `cols[e]`), sorted by row then column, of a matrix
    of `shape`; no explicit zeros."""

    rows: np.ndarray
    cols: np.ndarray
    values: np.ndarray
    shape: tuple[int, int]

    @classmethod
    def of(
        cls, rows: np.ndarray, cols: np.ndarray, values: np.ndarray, shape: tuple[int, int]
    ) -> SparseRows:
        """Entries in any order, repeats summed (as `+=` into a dense matrix), zeros left out."""
        rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
        values = np.asarray(values, dtype=float)
        key = rows * shape[1] + cols
        unique, where = np.unique(key, return_inverse=True)
        summed = np.zeros(unique.size)
        np.add.at(summed, where, values)
        kept = summed != 0.0
        return cls(unique[kept] // shape[1], unique[kept] % shape[1], summed[kept], shape)

    @classmethod
    def from_dense(cls, matrix: np.ndarray) -> SparseRows:
        """The non-zeros of a dense 2-D array."""
        matrix = np.asarray(matrix, dtype=float)
        rows, cols = np.nonzero(matrix)
        return cls(rows, cols, matrix[rows, cols], (matrix.shape[0], matrix.shape[1]))

    @functools.cached_property
    def bounds(self) -> np.ndarray:
        """Row i's entries are at positions bounds[i]:bounds[i + 1] (m + 1,)."""
        return np.searchsorted(self.rows, np.arange(self.shape[0] + 1))

    def row_cols(self, row: int) -> np.ndarray:
        """The columns of row `row`'s entries, sorted."""
        return self.cols[self.bounds[row] : self.bounds[row + 1]]

    def scale(self) -> float:
        """The largest magnitude of an entry (0 for an empty matrix)."""
        return float(np.abs(self.values).max(initial=0.0))

    def row_norms(self) -> np.ndarray:
        """The Euclidean norm of each row (m,)."""
        return np.sqrt(np.bincount(self.rows, self.values**2, minlength=self.shape[0]))

    def block(
        self, rows: Sequence[int] | np.ndarray, cols: Sequence[int] | np.ndarray
    ) -> np.ndarray:
        """The dense block of the given rows and (sorted) columns."""
        cols = np.asarray(cols)
        out = np.zeros((len(rows), cols.size))
        for i, r in enumerate(np.asarray(rows).tolist()):
            span = slice(self.bounds[r], self.bounds[r + 1])
            chosen = np.isin(self.cols[span], cols)
            out[i, np.searchsorted(cols, self.cols[span][chosen])] = self.values[span][chosen]
        return out

    def toarray(self) -> np.ndarray:
        """The dense matrix (small matrices and tests only)."""
        out = np.zeros(self.shape)
        out[self.rows, self.cols] = self.values
        return out
