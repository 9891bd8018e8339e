"""Compiled weld equations of the kept nodes of one modal body (mechlib.flexible.attached,
whose docstring states them): residual, Jacobian rows, gamma and rate.

Arguments shared by the kernels: `x`, `xd` (nb + 1, 7) rows [r, p] of all bodies and their
rates (m, m/s); `frame` the modal body's row, `nodes` (k,) the node bodies' rows;
`positions` (k, 3) m, `phi` (k, 3, n) and `phi_star` (k, 3, n) of the kept nodes;
`zeta`, `zeta_d` (n,) its modal coordinates and rates. Six rows per node: the position
r_n - x - A (s + Phi zeta), then (A_n f).(A (g + theta x g)) for (f, g) = (y, z), (z, x),
(x, y).
The residual, Jacobian and gamma take their 3-vectors in loops into arrays made once per
call (they run at every Newton iteration): numpy products of 3-vectors in a kernel are each
an allocation and a BLAS call, 4-6 times the cost; the sums are the same to round-off (BLAS
may fuse a product and an add).
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics.kernels import _bmat, b_matrix, rotation_matrix

__all__ = ["weld_gamma", "weld_jacobian", "weld_phi", "weld_rate"]

_PAIRS = np.array([[1, 2], [2, 0], [0, 1]])  # (f, g) axes of the orientation rows
_EYE = np.eye(3)  # the unit axes, rows


@njit(**KERNEL)
def _turned(theta, g):
    """g + theta x g (3,) for the unit axis g (index)."""
    out = _cross_axis(theta, g)
    out[g] += 1.0
    return out


@njit(**KERNEL)
def _cross_axis(s, g):
    """s x e_g (3,) for the unit axis g (index)."""
    e = _EYE[g]
    return np.array(
        [s[1] * e[2] - s[2] * e[1], s[2] * e[0] - s[0] * e[2], s[0] * e[1] - s[1] * e[0]]
    )


@njit(**KERNEL)
def _turned_into(theta, g, out):
    """out = g + theta x g (3,) for the unit axis g (index), as `_turned`."""
    e = _EYE[g]
    out[0] = theta[1] * e[2] - theta[2] * e[1]
    out[1] = theta[2] * e[0] - theta[0] * e[2]
    out[2] = theta[0] * e[1] - theta[1] * e[0]
    out[g] += 1.0


@njit(**KERNEL)
def _times(m, v, out):
    """out = m @ v (rows,) for m (rows, cols): a node's displacement or rotation from the
    modal coordinates, shapes (3, n) @ zeta."""
    for a in range(m.shape[0]):
        total = 0.0
        for d in range(m.shape[1]):
            total += m[a, d] * v[d]
        out[a] = total


@njit(**KERNEL)
def _column_dot(m, f, v):
    """m[:, f] . v of m (3, 3), v (3,)."""
    return m[0, f] * v[0] + m[1, f] * v[1] + m[2, f] * v[2]


@njit(**KERNEL)
def weld_phi(x, frame, nodes, positions, phi, phi_star, zeta, out):
    """Residuals (6 k,) into `out`."""
    A = rotation_matrix(x[frame, 3:])
    u, theta, au, v, b = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    for i in range(nodes.shape[0]):
        node = nodes[i]
        _times(phi[i], zeta, u)
        for a in range(3):
            u[a] += positions[i, a]
        _times(phi_star[i], zeta, theta)
        An = rotation_matrix(x[node, 3:])
        _times(A, u, au)
        for a in range(3):
            out[6 * i + a] = x[node, a] - x[frame, a] - au[a]
        for c in range(3):
            f, g = _PAIRS[c, 0], _PAIRS[c, 1]
            _turned_into(theta, g, v)
            _times(A, v, b)
            out[6 * i + 3 + c] = _column_dot(An, f, b)


@njit(**KERNEL)
def weld_jacobian(x, frame, nodes, positions, phi, phi_star, zeta, z_col, out):
    """Add the rows (6 k, ncol) into `out`; the modal columns start at `z_col`."""
    p = x[frame, 3:]
    A = rotation_matrix(p)
    fb, n = 7 * frame, zeta.shape[0]
    u, theta, v, b, at = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    bu, bn = np.empty((3, 4)), np.empty((3, 4))
    for i in range(nodes.shape[0]):
        node = nodes[i]
        pn = x[node, 3:]
        An = rotation_matrix(pn)
        _times(phi[i], zeta, u)
        for a in range(3):
            u[a] += positions[i, a]
        _times(phi_star[i], zeta, theta)
        nb_ = 7 * node
        r0 = 6 * i
        _bmat(p, u, bu)
        for a in range(3):
            out[r0 + a, nb_ + a] += 1.0
            out[r0 + a, fb + a] -= 1.0
            for d in range(4):
                out[r0 + a, fb + 3 + d] -= bu[a, d]
            for j in range(n):  # -(A Phi)[a, j]
                out[r0 + a, z_col + j] -= (
                    A[a, 0] * phi[i, 0, j] + A[a, 1] * phi[i, 1, j] + A[a, 2] * phi[i, 2, j]
                )
        for c in range(3):
            f, g = _PAIRS[c, 0], _PAIRS[c, 1]
            _turned_into(theta, g, v)
            _times(A, v, b)
            r = r0 + 3 + c
            _bmat(pn, _EYE[f], bn)
            for d in range(4):
                out[r, nb_ + 3 + d] += b[0] * bn[0, d] + b[1] * bn[1, d] + b[2] * bn[2, d]
            _bmat(p, v, bu)
            for d in range(4):
                out[r, fb + 3 + d] += _column_dot(An, f, bu[:, d])
            for a in range(3):  # d(an . A w)/dw
                at[a] = _column_dot(A, a, An[:, f])
            e = _EYE[g]
            for j in range(n):  # d(theta x g)/dzeta_j = phi*_j x g
                s0, s1, s2 = phi_star[i, 0, j], phi_star[i, 1, j], phi_star[i, 2, j]
                out[r, z_col + j] += (
                    at[0] * (s1 * e[2] - s2 * e[1])
                    + at[1] * (s2 * e[0] - s0 * e[2])
                    + at[2] * (s0 * e[1] - s1 * e[0])
                )


@njit(**KERNEL)
def _dot(a, b):
    """a . b of two (3,) vectors."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(**KERNEL)
def _b_times(p, s, v, work, out):
    """out = B(p, s) @ v (3,) for v (4,); `work` (3, 4) holds B."""
    _bmat(p, s, work)
    _times(work, v, out)


@njit(**KERNEL)
def weld_gamma(x, xd, frame, nodes, positions, phi, phi_star, zeta, zeta_d, out):
    """phi_q qdd = gamma (6 k,) into `out`: minus the second derivative's terms without
    qdd."""
    p, pd = x[frame, 3:], xd[frame, 3:]
    A = rotation_matrix(p)
    u, u_d, theta, theta_d = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    v, v_d, b, b_d, an_d = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    w1, w2, work = np.empty(3), np.empty(3), np.empty((3, 4))
    for i in range(nodes.shape[0]):
        pn, pnd = x[nodes[i], 3:], xd[nodes[i], 3:]
        _times(phi[i], zeta, u)
        for a in range(3):
            u[a] += positions[i, a]
        _times(phi[i], zeta_d, u_d)
        _times(phi_star[i], zeta, theta)
        _times(phi_star[i], zeta_d, theta_d)
        _b_times(pd, u, pd, work, w1)
        _b_times(p, u_d, pd, work, w2)
        for a in range(3):
            out[6 * i + a] = w1[a] + 2.0 * w2[a]
        An = rotation_matrix(pn)
        for c in range(3):
            f, g = _PAIRS[c, 0], _PAIRS[c, 1]
            _turned_into(theta, g, v)
            _turned_into(theta_d, g, v_d)
            v_d[g] -= 1.0  # theta_d x g
            ef = _EYE[f]
            _times(A, v, b)
            _b_times(pn, ef, pnd, work, an_d)
            _b_times(p, v, pd, work, w1)
            _times(A, v_d, w2)
            for a in range(3):
                b_d[a] = w1[a] + w2[a]
            _b_times(pnd, ef, pnd, work, w1)
            quad = _dot(w1, b) + 2.0 * _dot(an_d, b_d)
            _b_times(pd, v, pd, work, w1)
            _b_times(p, v_d, pd, work, w2)
            for a in range(3):
                w1[a] = w1[a] + 2.0 * w2[a]
            quad += _column_dot(An, f, w1)
            out[6 * i + 3 + c] = -quad


@njit(**KERNEL)
def weld_rate(x, xd, frame, nodes, positions, phi, phi_star, zeta, zeta_d, out):
    """d(phi)/dt (6 k,) into `out`."""
    p, pd = x[frame, 3:], xd[frame, 3:]
    A = rotation_matrix(p)
    for i in range(nodes.shape[0]):
        node = nodes[i]
        pn, pnd = x[node, 3:], xd[node, 3:]
        u = positions[i] + phi[i] @ zeta
        u_d = phi[i] @ zeta_d
        theta, theta_d = phi_star[i] @ zeta, phi_star[i] @ zeta_d
        out[6 * i : 6 * i + 3] = xd[node, :3] - xd[frame, :3] - b_matrix(p, u) @ pd - A @ u_d
        An = rotation_matrix(pn)
        for c in range(3):
            f, g = _PAIRS[c, 0], _PAIRS[c, 1]
            v = _turned(theta, g)
            v_d = _turned(theta_d, g)
            v_d[g] -= 1.0
            b = A @ v
            b_d = b_matrix(p, v) @ pd + A @ v_d
            out[6 * i + 3 + c] = (b_matrix(pn, _EYE[f]) @ pnd) @ b + An[:, f].copy() @ b_d
