"""LU factors as two flat arrays, the form the compiled kernels solve with and refactor in.

Three kinds, by ints[0]:
- DENSE (0): LAPACK getrf factors of the row-equilibrated matrix R A (mechlib.linalg.factor.factor);
  ints [0, n, piv (0-based)], floats [LU by columns (n^2), row scales R (n)].
- SUPERLU (1): SuperLU's (mechlib.linalg.factor.sparse_saddle_factors); ints [1, n, nnz(L), nnz(U),
  L's column starts and rows, U's, perm_r, perm_c], floats [L, U].
- BAND (2): LAPACK gbtrf factors of R P A P^T, P the band ordering of the saddle pattern
  (reverse Cuthill-McKee: a chain's saddle matrix has a band of 27 diagonals whatever its
  length); ints [2, n, kl, ku, perm (n), piv (n, 0-based)], floats [band storage ((2 kl +
  ku + 1) n), row scales R (n)].

`refactor` makes DENSE and BAND factors in place from a matrix's values on its pattern
(`FlatLayout`: where each value goes), with the arithmetic of mechlib.linalg.factor.factor
(equilibrated rows, LAPACK's LU and condition estimate): the Python path and the compiled
generalized-alpha runs (mechlib.solvers.genalpha.run) use the same kernel, so the same factors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dgbtrs as _gbtrs

from mechlib.core.jit import KERNEL, njit
from mechlib.linalg import lapack

__all__ = [
    "BAND",
    "DENSE",
    "SUPERLU",
    "Banded",
    "FlatLayout",
    "factor_data",
    "factors",
    "inverse_norm_bound",
    "lu_solve",
    "refactor",
    "refactor_dense",
    "surely_regular",
]

DENSE, SUPERLU, BAND = 0, 1, 2
SINGULAR_RATIO = 1e-14  # mechlib.linalg.factor.SINGULAR_RATIO (imported there from here)


class Banded:
    """BAND factors with the dense-LU solve interface (mechlib.linalg.factor.solve_factored)."""

    def __init__(self, ints: np.ndarray, floats: np.ndarray):
        self.ints, self.floats = ints, floats
        n, kl, ku = int(ints[1]), int(ints[2]), int(ints[3])
        size = (2 * kl + ku + 1) * n
        self.kl, self.ku = kl, ku
        self.band = floats[:size].reshape((2 * kl + ku + 1, n), order="F")
        self.rows = floats[size : size + n]
        self.perm = ints[4 : 4 + n]
        self.piv = ints[4 + n : 4 + 2 * n].astype(np.int32)

    def solve(self, rhs: np.ndarray, transpose: bool = False) -> np.ndarray:
        """x with A x = rhs (A^T x = rhs with `transpose`); rhs (n) or (n, k)."""
        rows = self.rows if rhs.ndim == 1 else self.rows[:, None]
        x = np.empty_like(rhs, dtype=float)
        if transpose:  # (R B)^T z = P rhs, P x = R z
            z, _ = _gbtrs(self.band, self.kl, self.ku, rhs[self.perm], self.piv, trans=1)
            x[self.perm] = rows * z
        else:
            y, _ = _gbtrs(self.band, self.kl, self.ku, rows * rhs[self.perm], self.piv)
            x[self.perm] = y
        return x


@dataclass(frozen=True)
class FlatLayout:
    """Where a saddle pattern's values go in DENSE or BAND factors: `ints` the factors'
    ints with the pivots still to come, `size` the floats' length, and per structural
    nonzero its place in the stored matrix (`place`), its row and column there."""

    ints: np.ndarray
    size: int
    place: np.ndarray
    row: np.ndarray
    col: np.ndarray

    @classmethod
    def dense(cls, rows: np.ndarray, cols: np.ndarray, n: int) -> FlatLayout:
        """The n x n matrix by columns."""
        ints = np.zeros(2 + n, dtype=np.int64)
        ints[:2] = DENSE, n
        return cls(ints, n * n + n, (rows + n * cols).astype(np.int64), rows, cols)

    @classmethod
    def band(cls, r: np.ndarray, c: np.ndarray, perm: np.ndarray, kl: int, ku: int) -> FlatLayout:
        """P A P^T (row i of it: row perm[i] of A) in band storage; `r`, `c` the
        nonzeros' rows and columns in P A P^T."""
        n = len(perm)
        lead = 2 * kl + ku + 1
        ints = np.zeros(4 + 2 * n, dtype=np.int64)
        ints[:4] = BAND, n, kl, ku
        ints[4 : 4 + n] = perm
        return cls(ints, lead * n + n, kl + ku + r - c + lead * c, r, c)

    def new(self) -> tuple[np.ndarray, np.ndarray]:
        """Arrays for `refactor` to fill."""
        return self.ints.copy(), np.empty(self.size)

    def kernel_args(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(place, row, col): `refactor`'s arguments after the values."""
        return self.place, self.row, self.col


def factors(ints: np.ndarray, floats: np.ndarray):
    """The Python factors object of DENSE or BAND flat factors (views of the arrays)."""
    n = int(ints[1])
    if ints[0] == BAND:
        return Banded(ints, floats)
    return floats[: n * n].reshape((n, n), order="F"), ints[2 : 2 + n], floats[n * n : n * n + n]


def factor_data(lu) -> tuple[np.ndarray, np.ndarray]:
    """LU factors (mechlib.linalg.factor.factor_saddle's) as the two flat arrays of the module
    docstring."""
    if isinstance(lu, Banded):
        return lu.ints, lu.floats
    if isinstance(lu, tuple):
        dense, piv, rows = lu
        n = len(rows)
        ints = np.concatenate([np.array([0, n], dtype=np.int64), np.asarray(piv, np.int64)])
        return ints, np.concatenate([np.asarray(dense).ravel(order="F"), rows])
    f = lu.lu
    lower, upper = f.L.tocsc(), f.U.tocsc()
    n = lower.shape[0]
    ints = np.concatenate(
        [
            np.array([1, n, lower.nnz, upper.nnz], dtype=np.int64),
            lower.indptr,
            lower.indices,
            upper.indptr,
            upper.indices,
            f.perm_r,
            f.perm_c,
        ]
    ).astype(np.int64)
    return ints, np.concatenate([lower.data, upper.data])


@njit(**KERNEL)
def lu_solve(ints, floats, b):
    """x with A x = b from `factor_data` (mechlib.linalg.factor.solve_factored's arithmetic)."""
    x = np.empty(ints[1])
    lu_solve_into(ints, floats, b, x)
    return x


@njit(**KERNEL)
def lu_solve_into(ints, floats, b, x):
    """`lu_solve` written into x (no allocation for dense factors); returns x."""
    if ints[0] == BAND:
        _band_solve(ints, floats, b, x)
    elif ints[0] == DENSE:
        _dense_solve(ints, floats, b, x)
    else:
        _superlu_solve(ints, floats, b, x)
    return x


@njit(**KERNEL)
def _band_solve(ints, floats, b, x):
    """R P A P^T = L U (LAPACK's band factors): x[perm] = (L U)^-1 R b[perm]."""
    n = ints[1]
    kl, ku = ints[2], ints[3]
    size = (2 * kl + ku + 1) * n
    perm = ints[4 : 4 + n]
    piv = np.empty(n, dtype=np.int32)
    y = np.empty(n)
    for i in range(n):
        piv[i] = ints[4 + n + i] + 1
        y[i] = floats[size + i] * b[perm[i]]
    lapack.gbtrs(floats[:size], n, kl, ku, piv, y)
    for i in range(n):
        x[perm[i]] = y[i]


@njit(**KERNEL)
def _dense_solve(ints, floats, b, x):
    """(R A) = P L U: x = U^-1 L^-1 P^T (R b)."""
    n = ints[1]
    piv = ints[2 : 2 + n]
    lu = floats[: n * n]
    for i in range(n):
        x[i] = floats[n * n + i] * b[i]
    for i in range(n):
        p = piv[i]
        if p != i:
            x[i], x[p] = x[p], x[i]
    for j in range(n):  # unit lower triangle, by columns
        xj = x[j]
        if xj != 0.0:
            for i in range(j + 1, n):
                x[i] -= lu[j * n + i] * xj
    for j in range(n - 1, -1, -1):
        x[j] /= lu[j * n + j]
        xj = x[j]
        if xj != 0.0:
            for i in range(j):
                x[i] -= lu[j * n + i] * xj


@njit(**KERNEL)
def _superlu_solve(ints, floats, b, x):
    """Pr A Pc = L U (SuperLU's, CSC): L U y = Pr b, x = Pc y."""
    n, nl, nu = ints[1], ints[2], ints[3]
    o = 4
    lp, li = ints[o : o + n + 1], ints[o + n + 1 : o + n + 1 + nl]
    o += n + 1 + nl
    up, ui = ints[o : o + n + 1], ints[o + n + 1 : o + n + 1 + nu]
    o += n + 1 + nu
    perm_r, perm_c = ints[o : o + n], ints[o + n : o + 2 * n]
    lx, ux = floats[:nl], floats[nl : nl + nu]
    y = np.empty(n)
    for i in range(n):
        y[perm_r[i]] = b[i]
    for j in range(n):  # unit lower triangle (CSC)
        yj = y[j]
        if yj != 0.0:
            for k in range(lp[j], lp[j + 1]):
                if li[k] > j:
                    y[li[k]] -= lx[k] * yj
    for j in range(n - 1, -1, -1):  # upper triangle (CSC): the diagonal is row j's entry
        for k in range(up[j], up[j + 1]):
            if ui[k] == j:
                y[j] /= ux[k]
        yj = y[j]
        if yj != 0.0:
            for k in range(up[j], up[j + 1]):
                if ui[k] < j:
                    y[ui[k]] -= ux[k] * yj
    for i in range(n):
        x[i] = y[perm_c[i]]


@njit(**KERNEL)
def refactor(values, place, row, col, ints, floats):
    """DENSE or BAND factors (ints, floats: a layout's, in place) of the matrix of the
    pattern values `values`: rows equilibrated (each scaled by 1/max|row|), then LAPACK's
    LU. False, the factors undefined, where the matrix is taken for singular: a zero or
    non-finite row, a zero pivot or non-finite factors; for DENSE a reciprocal condition
    number (LAPACK's 1-norm estimate) at or below SINGULAR_RATIO, as mechlib.linalg.factor.factor
    (the estimate skipped where `surely_regular` proves it above: the same decision);
    for BAND the smallest pivot at or below SINGULAR_RATIO of the largest, as
    mechlib.linalg.factor.sparse_saddle_factors (the condition estimate would cost as much as the
    factorisation)."""
    n = ints[1]
    if ints[0] == DENSE:
        kl, ku, size = 0, 0, n * n
    else:
        kl, ku = ints[2], ints[3]
        size = (2 * kl + ku + 1) * n
    store, scales = floats[:size], floats[size : size + n]
    store[:] = 0.0
    big = np.zeros(n)
    for e in range(values.shape[0]):
        v = values[e]
        if not math.isfinite(v):
            return False
        store[place[e]] = v
        big[row[e]] = max(big[row[e]], abs(v))
    if not _row_scales(big, scales):
        return False
    column_sums = np.zeros(n)
    for e in range(values.shape[0]):
        scaled = store[place[e]] * scales[row[e]]
        store[place[e]] = scaled
        column_sums[col[e]] += abs(scaled)
    return _lapack_lu(store, n, kl, ku, column_sums.max(), ints)


@njit(**KERNEL)
def refactor_dense(ints, floats):
    """`refactor` of a DENSE layout whose matrix (n x n, every entry, by columns) is
    already in floats[:n^2], in place: the same arithmetic without the scatter through a
    pattern (the same factors, bit for bit)."""
    n = ints[1]
    store, scales = floats[: n * n], floats[n * n : n * n + n]
    big = np.zeros(n)
    for c in range(n):
        for r in range(n):
            v = store[r + n * c]
            if not math.isfinite(v):
                return False
            big[r] = max(big[r], abs(v))
    if not _row_scales(big, scales):
        return False
    anorm = 0.0
    for c in range(n):
        total = 0.0
        for r in range(n):
            scaled = store[r + n * c] * scales[r]
            store[r + n * c] = scaled
            total += abs(scaled)
        anorm = max(anorm, total)
    return _lapack_lu(store, n, 0, 0, anorm, ints)


@njit(**KERNEL)
def _row_scales(big, scales):
    """scales = 1 / big (the rows' largest |entry|); False where a row is zero."""
    for i in range(big.shape[0]):
        if big[i] == 0.0:
            return False
        scales[i] = 1.0 / big[i]
    return True


@njit(**KERNEL)
def _lapack_lu(store, n, kl, ku, anorm, ints):
    """LAPACK's LU of the equilibrated matrix in `store` (DENSE when ints[0] says so, else
    BAND with kl, ku) of 1-norm `anorm`, its pivots into ints; False where `refactor`
    takes it for singular."""
    piv = np.empty(n, dtype=np.int32)
    if ints[0] == DENSE:
        info = lapack.getrf(store, n, piv)
    else:
        info = lapack.gbtrf(store, n, kl, ku, piv)
    if info != 0:
        return False
    for v in store:
        if not math.isfinite(v):
            return False
    if ints[0] == DENSE:
        if not (surely_regular(store, n, anorm) or lapack.gecon(store, n, anorm) > SINGULAR_RATIO):
            return False
    elif not _pivots_apart(store, n, 2 * kl + ku + 1, kl + ku):
        return False
    first = 2 if ints[0] == DENSE else 4 + n
    for i in range(n):
        ints[first + i] = piv[i] - 1
    return True


@njit(**KERNEL)
def surely_regular(store, n, anorm):
    """Whether LAPACK's condition estimate (`lapack.gecon`) of the matrix B of 1-norm
    `anorm` whose getrf factors (B = P L U) are store[:n^2] would be above SINGULAR_RATIO,
    proved without computing it: `inverse_norm_bound` bounds ||B^-1||_1 from above, gecon's
    estimate bounds it from below (its triangular solves' round-off moves it by about n
    eps relative; the factor 2 covers that). False says only "not proved": gecon then
    decides, so the decision is always gecon's."""
    return 2.0 * SINGULAR_RATIO * anorm * inverse_norm_bound(store, n) < 1.0  # NaN: False


@njit(**KERNEL)
def inverse_norm_bound(store, n):
    """An upper bound of ||B^-1||_1 from B's getrf factors P L U in store[:n^2] (by
    columns): |U^-1 L^-1| <= M(U)^-1 M(L)^-1 entry by entry (M the comparison matrix:
    |diagonal| less |off-diagonal|; Higham, Accuracy and Stability of Numerical
    Algorithms, 2002, section 8.2), so the largest entry of w^T = e^T M(U)^-1 M(L)^-1 is
    at least every column sum of |B^-1| = |U^-1 L^-1 P^T|. Two triangular solves of
    positive terms (n^2 multiply-adds; gecon's estimate takes about five pairs of solves)."""
    w = np.empty(n)
    for j in range(n):  # M(U)^T y = e (lower triangular): U's column j above its diagonal
        acc = 1.0
        for i in range(j):
            acc += abs(store[i + n * j]) * w[i]
        w[j] = acc / abs(store[j + n * j])
    for j in range(n - 1, -1, -1):  # M(L)^T z = y (unit upper triangular): L's column j
        acc = w[j]
        for i in range(j + 1, n):
            acc += abs(store[i + n * j]) * w[i]
        w[j] = acc
    largest = 0.0
    for j in range(n):
        largest = max(largest, w[j])
    return largest


@njit(**KERNEL)
def _pivots_apart(store, n, lead, diagonal):
    """Whether U's smallest |pivot| is above SINGULAR_RATIO of its largest (band storage
    of leading dimension `lead`, U's diagonal in row `diagonal`)."""
    low, high = math.inf, 0.0
    for j in range(n):
        u = abs(store[diagonal + j * lead])
        low, high = min(low, u), max(high, u)
    return low > SINGULAR_RATIO * high
