"""Compiled nearest point on a planar piecewise-cubic curve (a profile contact's spline).

The curve is scipy's PPoly form of a cubic spline through 2-D points: breakpoints `breaks`
(m + 1,) and coefficients `coefs` (4, m, 2), piece i being sum_k coefs[k, i] (u - u_i)^(3-k)
(u: chord length, m). One call does the coarse search over precomputed samples and the
Newton refinement that `CircleProfile` did with three scipy calls per iteration.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = ["nearest_on_cubic"]


@njit(**KERNEL)
def _piece(breaks, u):
    """Index of the piece holding u (the last one at and beyond the end)."""
    lo, hi = 0, breaks.shape[0] - 2
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if breaks[mid] <= u:
            lo = mid
        else:
            hi = mid - 1
    return lo


@njit(**KERNEL)
def _evaluate(breaks, coefs, u, out):
    """out (3, 2): the curve point, its first and second derivatives at u."""
    i = _piece(breaks, u)
    d = u - breaks[i]
    for j in range(2):
        a3, a2, a1, a0 = coefs[0, i, j], coefs[1, i, j], coefs[2, i, j], coefs[3, i, j]
        out[0, j] = ((a3 * d + a2) * d + a1) * d + a0
        out[1, j] = (3.0 * a3 * d + 2.0 * a2) * d + a1
        out[2, j] = 6.0 * a3 * d + 2.0 * a2


@njit(**KERNEL)
def nearest_on_cubic(w, grid, samples, breaks, coefs, iterations, out):
    """Curve parameter u (m of chord) of the point nearest the in-plane point w (2,): the
    nearest of the `samples` (n, 2) at `grid` (n,), then Newton on (c(u) - w) . c'(u) = 0
    within [grid[0], grid[-1]]; `out` (3, 2) receives the point, tangent and second
    derivative at u."""
    best, u = np.inf, grid[0]
    for k in range(grid.shape[0]):
        dx, dy = samples[k, 0] - w[0], samples[k, 1] - w[1]
        if dx * dx + dy * dy < best:
            best, u = dx * dx + dy * dy, grid[k]
    for _ in range(iterations):
        _evaluate(breaks, coefs, u, out)
        rx, ry = out[0, 0] - w[0], out[0, 1] - w[1]
        tx, ty = out[1, 0], out[1, 1]
        slope = tx * tx + ty * ty + rx * out[2, 0] + ry * out[2, 1]
        if slope <= 0.0:
            break
        step = (rx * tx + ry * ty) / slope
        u = min(max(u - step, grid[0]), grid[-1])
        if abs(step) < 1e-13:  # m of chord: converged to round-off
            break
    _evaluate(breaks, coefs, u, out)
    return u
