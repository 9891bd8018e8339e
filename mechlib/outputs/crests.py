"""The rise of a column's crest between its output rows: the quartic through the crest's row
and the two rows either side, compiled (one pass over the crests, no LAPACK call each).

Used by the envelope's error estimate (loadcases.run.peak_error). The 5 x 5 system of each
crest is solved by Gaussian elimination with partial pivoting, as LAPACK's dgesv does, but
not in its order of operations: the coefficients agree with numpy's `linalg.solve` to the
last few bits (tests/mechlib/test_crests.py), not bit for bit.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = ["quartic_rises"]

_NEWTON = 4  # Newton steps from the parabola's vertex to the quartic's (order 6: 1e-12)


@njit(**KERNEL)
def _solve5(a, b):
    """x with a x = b of the 5 x 5 matrix `a` and (5,) `b`, both overwritten; nan where a
    pivot is exactly zero."""
    n = 5
    for c in range(n):
        p = c
        for r in range(c + 1, n):
            if abs(a[r, c]) > abs(a[p, c]):
                p = r
        if a[p, c] == 0.0:
            return np.full(n, np.nan)
        if p != c:
            for j in range(n):
                a[c, j], a[p, j] = a[p, j], a[c, j]
            b[c], b[p] = b[p], b[c]
        inverse = 1.0 / a[c, c]
        for r in range(c + 1, n):
            factor = a[r, c] * inverse
            for j in range(c + 1, n):
                a[r, j] -= factor * a[c, j]
            b[r] -= factor * b[c]
    x = np.empty(n)
    for r in range(n - 1, -1, -1):
        total = b[r]
        for j in range(r + 1, n):
            total -= a[r, j] * x[j]
        x[r] = total / a[r, r]
    return x


@njit(**KERNEL)
def _rise(coef, low, high):
    """The rise above s = 0 of the highest point of the quartic sum coef[k] s^k strictly
    between `low` and `high` (scaled times), by Newton on its slope from the parabola's
    vertex; nan where it has none there (no maximum, or a division by an exact zero)."""
    c1, c2, c3, c4 = coef[1], coef[2], coef[3], coef[4]
    if c2 == 0.0:
        return np.nan
    at = -c1 / (2.0 * c2)
    for _ in range(_NEWTON):
        slope = c1 + at * (2.0 * c2 + at * (3.0 * c3 + 4.0 * c4 * at))
        bend = 2.0 * c2 + at * (6.0 * c3 + 12.0 * c4 * at)
        if bend == 0.0:
            return np.nan
        at = at - slope / bend
    bend = 2.0 * c2 + at * (6.0 * c3 + 12.0 * c4 * at)
    up = at * (c1 + at * (c2 + at * (c3 + at * c4)))
    if np.isfinite(up) and bend < 0.0 and low < at and at < high and up >= 0.0:
        return up
    return np.nan


@njit(**KERNEL)
def quartic_rises(table, rows, columns, powers, scaled, which):
    """Per crest k (row rows[k] of column columns[k] of `table` (n, columns), two rows at
    least from either end): the rise above its row of the highest point of the quartic
    through it and the two rows either side, between its neighbours; nan where none. The
    five rows' scaled times are scaled[which[k]] (the crest's own 0) and their powers 0-4
    powers[which[k]] (5, 5): crests of one row in several columns share them."""
    out = np.empty(len(rows))
    a = np.empty((5, 5))
    b = np.empty(5)
    for k in range(len(rows)):
        row, column, shared = rows[k], columns[k], which[k]
        for i in range(5):
            b[i] = table[row + i - 2, column] - table[row, column]
            for j in range(5):
                a[i, j] = powers[shared, i, j]
        out[k] = _rise(_solve5(a, b), scaled[shared, 1], scaled[shared, 3])
    return out
