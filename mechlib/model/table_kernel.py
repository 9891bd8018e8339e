"""A table's value in compiled code (numba): the sums of mechlib.model.tables.Table, from its
`packed` arrays, for the compiled elements with a tabulated law."""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = ["table_value"]


@njit(**KERNEL)
def table_value(breaks, coefs, ends, flags, v):
    """(inside its rule, y(v)) of a packed table (Table.packed): within the data the piece's
    polynomial summed as Table._value sums it; outside, the end value held or continued by
    its slope (Table.__call__); (False, nan) outside a table that does not extrapolate
    (the caller asks the table itself, which raises the message)."""
    lo, hi = breaks[0], breaks[-1]
    mode, order, exact = flags[0], flags[1], flags[2]
    if lo <= v <= hi:
        if exact and v == hi:
            return True, ends[1, 0]
        i = min(max(np.searchsorted(breaks, v, "right") - 1, 0), coefs.shape[0] - 1)
        d, power, out = v - breaks[i], 1.0, 0.0
        for c in coefs[i]:
            out += c * power
            power *= d
        return True, out
    if mode == 0:
        return False, np.nan
    end = 0 if v < lo else 1
    value, slope = ends[end, 0], ends[end, 1]
    if mode == 1:
        return True, value if order == 0 else 0.0
    if order == 0:
        return True, value + slope * (v - breaks[0 if end == 0 else breaks.size - 1])
    return True, value if order == 1 else 0.0
