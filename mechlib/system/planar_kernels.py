"""Compiled map of planar coordinates to the 3-D state and its transpose (mechlib.system.planar).

Per body: q_b = (x, y, phi) -> r = c_b + x e1 + y e2, p = (cos(phi/2), sin(phi/2) n);
T_b = d(r, p)/d(x, y, phi) = [[e1, e2, 0], [0, 0, dp/dphi]], dp/dphi = (-sin, cos n) / 2.
Layout as mechlib.kinematics.kernels: `x`, `xd` (nb+1, 7) rows [r, p], ground last (left as it is).
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = ["planar_reduce", "planar_state"]


@njit(**KERNEL)
def planar_state(q, qd, offset, e_in, normal, x, xd):
    """x, xd (rows of the moving bodies) of planar q, qd (3 nb,): positions and rates."""
    for b in range(offset.shape[0]):
        half = 0.5 * q[3 * b + 2]
        c, s = np.cos(half), np.sin(half)
        rate = qd[3 * b + 2]
        for i in range(3):
            x[b, i] = offset[b, i] + e_in[i, 0] * q[3 * b] + e_in[i, 1] * q[3 * b + 1]
            xd[b, i] = e_in[i, 0] * qd[3 * b] + e_in[i, 1] * qd[3 * b + 1]
            x[b, 4 + i] = s * normal[i]
            xd[b, 4 + i] = 0.5 * c * normal[i] * rate
        x[b, 3] = c
        xd[b, 3] = -0.5 * s * rate


@njit(**KERNEL)
def planar_reduce(rows, x, e_in, normal, out):
    """out (m, 3 nb) = rows (m, 7 nb) T: 3-D Jacobian rows or generalised forces (as rows)."""
    nb = out.shape[1] // 3
    for b in range(nb):
        # dp/dphi from p itself: (-p.n, p0 n) / 2
        along = x[b, 4] * normal[0] + x[b, 5] * normal[1] + x[b, 6] * normal[2]
        d0 = -0.5 * along
        d1 = 0.5 * x[b, 3] * normal[0]
        d2 = 0.5 * x[b, 3] * normal[1]
        d3 = 0.5 * x[b, 3] * normal[2]
        for m in range(rows.shape[0]):
            o = 7 * b
            r0, r1, r2 = rows[m, o], rows[m, o + 1], rows[m, o + 2]
            out[m, 3 * b] = r0 * e_in[0, 0] + r1 * e_in[1, 0] + r2 * e_in[2, 0]
            out[m, 3 * b + 1] = r0 * e_in[0, 1] + r1 * e_in[1, 1] + r2 * e_in[2, 1]
            out[m, 3 * b + 2] = (
                rows[m, o + 3] * d0
                + rows[m, o + 4] * d1
                + rows[m, o + 5] * d2
                + rows[m, o + 6] * d3
            )
