"""The rise of a column's crest between its output rows, compiled: the crests of every column
found and their parabola's rise and bounds taken at the crest rows alone (`crest_table`,
`crest_bounds`, numpy's arithmetic bit for bit), the quartic through the crest's row and
the two rows either side (`scaled_groups`, `quartic_rises`, one pass over the crests, no
LAPACK call each), each column's highest crest and its candidates (`crest_tops`), and a
run's candidates against another run's (`crest_match`).

Used by the envelope's error estimate (loadcases.run.peak_error). The 5 x 5 system of each
crest is solved by Gaussian elimination with partial pivoting, as LAPACK's dgesv does, but
not in its order of operations: the coefficients agree with numpy's `linalg.solve` to the
last few bits (tests/mechlib/test_crests.py), not bit for bit.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = [
    "crest_bounds",
    "crest_match",
    "crest_table",
    "crest_tops",
    "quartic_rises",
    "scaled_groups",
]

_NEWTON = 4  # Newton steps from the parabola's vertex to the quartic's (order 6: 1e-12)
#: numpy's division (inf and nan, no ZeroDivisionError: repeated times divide by 0) and no
#: other change: the same IEEE operations as numpy's arrays under np.errstate(ignore)
_ARRAYS = {**KERNEL, "error_model": "numpy"}


@njit(**_ARRAYS)
def _maximum(a, b):
    """np.maximum of two floats: nan where either is, b where they are equal (numpy's
    choice between -0.0 and 0.0)."""
    if a != a or b != b:
        return np.nan
    return a if a > b else b


@njit(**_ARRAYS)
def _minimum(a, b):
    """np.minimum of two floats: nan where either is, b where they are equal."""
    if a != a or b != b:
        return np.nan
    return a if a < b else b


@njit(**_ARRAYS)
def _bend(time, values, row, column, k):
    """(slope at `row`, curvature coefficient c) of the parabola through rows row - k, row,
    row + k of column `column` of values (v = v_row + slope dt + c dt^2): numpy's
    arithmetic of loadcases.run.peak_error's `_curvature`, nan at a repeated time."""
    h1 = time[row] - time[row - k]
    h2 = time[row + k] - time[row]
    v1 = values[row, column]
    d1 = (v1 - values[row - k, column]) / h1
    d2 = (values[row + k, column] - v1) / h2
    c = (d2 - d1) / (h1 + h2)
    return d1 + c * h1, c


@njit(**_ARRAYS)
def crest_bounds(time, values, rows, columns):
    """Per crest k (row rows[k] of column columns[k] of values (n, columns), 1 <= row <=
    n - 2): the parabola's rise above the row through it and its neighbours, -slope^2 /
    (4 c), and its bound: -c (h / 2)^2 with h the longer neighbouring interval, the smaller
    with the parabola through the rows two apart (at least 0; rows 2 to n - 3) and the
    smaller downward curvature of the parabolas through the rows beside (at least 0; n >=
    4). The rise nan where the parabola does not curve down (c >= 0 or nan). numpy's
    arithmetic bit for bit (loadcases.run.peak_error's `_crest_rises` over every row)."""
    n = len(values)
    rise, bound = np.empty(len(rows)), np.empty(len(rows))
    for k in range(len(rows)):
        row, column = rows[k], columns[k]
        slope, bend = _bend(time, values, row, column, 1)
        if not bend < 0.0:
            rise[k], bound[k] = np.nan, np.nan
            continue
        h = _maximum(time[row] - time[row - 1], time[row + 1] - time[row])
        half = (0.5 * h) * (0.5 * h)
        rise[k] = -(slope * slope) / (4.0 * bend)
        bound[k] = -bend * half
        if n >= 5 and 2 <= row <= n - 3:
            wide = _bend(time, values, row, column, 2)[1]
            bound[k] = _minimum(bound[k], _maximum(-wide, 0.0) * half)
        if n >= 4:
            beside = np.inf
            if row >= 2:
                beside = _maximum(-_bend(time, values, row - 1, column, 1)[1], 0.0)
            if row <= n - 3:
                after = _maximum(-_bend(time, values, row + 1, column, 1)[1], 0.0)
                beside = _minimum(beside, after)
            bound[k] = _minimum(bound[k], beside * half)
    return rise, bound


@njit(**KERNEL)
def _eliminations(powers):
    """Gaussian elimination with partial pivoting of each 5 x 5 matrix powers[d], recorded
    to be replayed on right-hand sides (`_solved`): (upper triangles (d, 5, 5), the pivot
    row of each step (d, 5), each step's row factors (d, 5, 5): [step, row], whether a
    pivot was exactly zero (d,))."""
    count, n = powers.shape[0], 5
    upper = powers.copy()
    pivots = np.zeros((count, n), dtype=np.int64)
    factors = np.zeros((count, n, n))
    singular = np.zeros(count, dtype=np.bool_)
    for d in range(count):
        a = upper[d]
        for c in range(n):
            p = c
            for r in range(c + 1, n):
                if abs(a[r, c]) > abs(a[p, c]):
                    p = r
            pivots[d, c] = p
            if a[p, c] == 0.0:
                singular[d] = True
                break
            if p != c:
                for j in range(n):
                    a[c, j], a[p, j] = a[p, j], a[c, j]
            inverse = 1.0 / a[c, c]
            for r in range(c + 1, n):
                factor = a[r, c] * inverse
                factors[d, c, r] = factor
                for j in range(c + 1, n):
                    a[r, j] -= factor * a[c, j]
    return upper, pivots, factors, singular


@njit(**KERNEL)
def _solved(upper, pivots, factors, b, x):
    """x with a x = b of the matrix whose elimination is (upper, pivots, factors) (5 x 5,
    `_eliminations`): its row swaps and factors replayed on b (overwritten), then back
    substitution."""
    n = 5
    for c in range(n):
        p = pivots[c]
        if p != c:
            b[c], b[p] = b[p], b[c]
        for r in range(c + 1, n):
            b[r] -= factors[c, r] * b[c]
    for r in range(n - 1, -1, -1):
        total = b[r]
        for j in range(r + 1, n):
            total -= upper[r, j] * x[j]
        x[r] = total / upper[r, r]


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
    powers[which[k]] (5, 5): crests of one row in several columns share them, and the rows
    of the same scaled times their elimination (made once a matrix, replayed on each
    crest's values: the same operations as eliminating the crest's system whole)."""
    out = np.empty(len(rows))
    upper, pivots, factors, singular = _eliminations(powers)
    b, coef = np.empty(5), np.empty(5)
    for k in range(len(rows)):
        row, column, shared = rows[k], columns[k], which[k]
        if singular[shared]:
            out[k] = np.nan
            continue
        for i in range(5):
            b[i] = table[row + i - 2, column] - table[row, column]
        _solved(upper[shared], pivots[shared], factors[shared], b, coef)
        out[k] = _rise(coef, scaled[shared, 1], scaled[shared, 3])
    return out


@njit(**_ARRAYS)
def crest_table(time, values):
    """The crests of every column of values (n, columns), n >= 3, at once: (each column's
    largest finite row, -inf where none (columns,); the crest rows' indices into values
    (rows 1 to n - 2) and their columns, column by column and each's rows in order; each
    crest's parabola rise and bound, `crest_bounds`). A crest: a row higher than both its
    neighbours, the three times increasing (loadcases.run.peak_error's `_highest`). One
    pass a column, without branches on the values (a noisy column's crests come at random:
    each branch a misprediction)."""
    n, count = values.shape
    row_max = np.full(count, -np.inf)
    rising = np.zeros(n, np.bool_)
    for i in range(1, n - 1):
        rising[i] = (time[i] - time[i - 1] > 0.0) & (time[i + 1] - time[i] > 0.0)
    rows, columns = np.empty(count * (n - 2), np.int64), np.empty(count * (n - 2), np.int64)
    column = np.empty(n)
    total = 0
    for j in range(count):
        top = -np.inf
        for i in range(n):
            v = values[i, j]
            column[i] = v
            if np.isfinite(v):
                top = _maximum(top, v)
        row_max[j] = top
        for i in range(1, n - 1):
            v = column[i]
            rows[total], columns[total] = i, j
            total += (v > column[i - 1]) & (v > column[i + 1]) & rising[i]
    rows, columns = rows[:total].copy(), columns[:total].copy()
    rise, bound = crest_bounds(time, values, rows, columns)
    return row_max, rows, columns, rise, bound


@njit(**_ARRAYS)
def scaled_groups(time, rows):
    """The quartic's five scaled times of each crest row in `rows` (indices into the rows):
    (which of them the quartic fits: two rows at least from either end, the five times
    increasing; the distinct scaled rows (g, 5), told apart by their bits; each fitted
    crest's among them). The scaled times of row i: (t_{i+k} - t_i) / ((t_{i+1} - t_{i-1})
    / 2), k = -2..2 (numpy's arithmetic: the same bits)."""
    fitted = np.zeros(len(rows), np.bool_)
    which = np.empty(len(rows), np.int64)
    group = np.full(len(time), -1, np.int64)  # per row of the table, its distinct row
    seen = {}
    distinct = np.empty((len(rows), 5))
    row = np.empty(5)
    bits = row.view(np.int64)
    found = 0
    for k in range(len(rows)):
        i = rows[k]
        if not (
            2 <= i <= len(time) - 3
            and time[i - 1] - time[i - 2] > 0.0
            and time[i] - time[i - 1] > 0.0
            and time[i + 1] - time[i] > 0.0
            and time[i + 2] - time[i + 1] > 0.0
        ):
            continue
        fitted[k] = True
        if group[i] < 0:
            half = 0.5 * (time[i + 1] - time[i - 1])
            for c in range(5):
                row[c] = (time[i + c - 2] - time[i]) / half
            key = (bits[0], bits[1], bits[2], bits[3], bits[4])
            if key not in seen:
                seen[key] = found
                distinct[found] = row
                found += 1
            group[i] = seen[key]
        which[k] = group[i]
    return fitted, distinct[:found].copy(), which[fitted]


@njit(**_ARRAYS)
def crest_tops(time, values, rows, columns, rise, bound, row_max):
    """Each column's highest crest or row and its crests as candidates, from the crests of
    `crest_table` (rows, columns) with their rises (the quartic's where it has one, else
    the parabola's; nan: none) and bounds: a crest with a finite rise and bound is `local`
    and reads its row plus the smaller of the two, others their row (+ 0.0). Returns (the
    top of each column: np.maximum of its highest local crest and row_max; the candidates
    (time, value, 0) of every crest (k, 3), column by column)."""
    count = row_max.shape[0]
    highest = np.full(count, -np.inf)
    found = np.empty((len(rows), 3))
    for k in range(len(rows)):
        i, j = rows[k], columns[k]
        local = np.isfinite(rise[k]) and np.isfinite(bound[k])
        value = values[i, j] + (_minimum(rise[k], bound[k]) if local else 0.0)
        if local:
            highest[j] = _maximum(highest[j], value)
        found[k, 0], found[k, 1], found[k, 2] = time[i], value, 0.0
    top = np.empty(count)
    for j in range(count):
        top[j] = _maximum(highest[j], row_max[j])
    return top, found


@njit(**_ARRAYS)
def _highest_within(times, values, kinds, t, kind, window):
    """The highest of `values` of kind `kind` whose time lies within `window` s of t (times
    increasing: bisection to the first, then those within), -inf where none."""
    best = -np.inf
    for j in range(np.searchsorted(times, t - window, side="left"), len(times)):
        if times[j] > t + window:
            break
        if kinds[j] == kind:
            best = _maximum(best, values[j])
    return best


@njit(**_ARRAYS)
def crest_match(run, top, companion, window, scale, extreme):
    """A column's candidates in a run (rows (time s, value, kind), higher more extreme; its
    peak `top`) against those of another run of the same motion (`companion`), each paired
    with the other's highest of the same kind within `window` s (loadcases.run.peak_error,
    where the rule is): (the largest excess over `top` of a run candidate's value
    extrapolated by Richardson, P + scale (P - C), C its partner, 0 where none exceeds it;
    the partner of the run's highest candidate, `extreme` where it has none or `top` is
    above every candidate). The candidates finite, as the envelope's are."""
    order = np.argsort(companion[:, 0])
    times, values, kinds = companion[order, 0], companion[order, 1], companion[order, 2]
    excess, best = 0.0, -1
    for i in range(run.shape[0]):
        if best < 0 or run[i, 1] > run[best, 1]:
            best = i
        value = run[i, 1]
        near = _highest_within(times, values, kinds, run[i, 0], run[i, 2], window)
        if np.isfinite(near):
            excess = max(excess, (value + scale * (value - near)) - top)
    if best < 0 or run[best, 1] < top:
        return excess, extreme
    near = _highest_within(times, values, kinds, run[best, 0], run[best, 2], window)
    return excess, (near if np.isfinite(near) else extreme)
