"""Compiled weld equations of the kept nodes of one modal body (mechlib.flexible.attached,
whose docstring states them): residual, Jacobian rows, gamma and rate.

Arguments shared by the kernels: `x`, `xd` (nb + 1, 7) rows [r, p] of all bodies and their
rates (m, m/s); `frame` the modal body's row, `nodes` (k,) the node bodies' rows;
`positions` (k, 3) m, `phi` (k, 3, n) and `phi_star` (k, 3, n) of the kept nodes;
`zeta`, `zeta_d` (n,) its modal coordinates and rates. Six rows per node: the position
r_n - x - A (s + Phi zeta), then (A_n f).(A (g + theta x g)) for (f, g) = (y, z), (z, x),
(x, y).
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics.kernels import b_matrix, rotation_matrix

__all__ = ["weld_gamma", "weld_jacobian", "weld_phi", "weld_rate"]

_PAIRS = np.array([[1, 2], [2, 0], [0, 1]])  # (f, g) axes of the orientation rows


@njit(**KERNEL)
def _turned(theta, g):
    """g + theta x g (3,) for the unit axis g (index)."""
    out = _cross_axis(theta, g)
    out[g] += 1.0
    return out


@njit(**KERNEL)
def _cross_axis(s, g):
    """s x e_g (3,) for the unit axis g (index)."""
    e = _unit(g)
    return np.array(
        [s[1] * e[2] - s[2] * e[1], s[2] * e[0] - s[0] * e[2], s[0] * e[1] - s[1] * e[0]]
    )


@njit(**KERNEL)
def _unit(f):
    out = np.zeros(3)
    out[f] = 1.0
    return out


@njit(**KERNEL)
def weld_phi(x, frame, nodes, positions, phi, phi_star, zeta, out):
    """Residuals (6 k,) into `out`."""
    p = x[frame, 3:]
    A = rotation_matrix(p)
    for i in range(nodes.shape[0]):
        node = nodes[i]
        u = positions[i] + phi[i] @ zeta
        theta = phi_star[i] @ zeta
        An = rotation_matrix(x[node, 3:])
        out[6 * i : 6 * i + 3] = x[node, :3] - x[frame, :3] - A @ u
        for c in range(3):
            f, g = _PAIRS[c, 0], _PAIRS[c, 1]
            out[6 * i + 3 + c] = An[:, f].copy() @ (A @ _turned(theta, g))


@njit(**KERNEL)
def weld_jacobian(x, frame, nodes, positions, phi, phi_star, zeta, z_col, out):
    """Add the rows (6 k, ncol) into `out`; the modal columns start at `z_col`."""
    p = x[frame, 3:]
    A = rotation_matrix(p)
    fb, n = 7 * frame, zeta.shape[0]
    for i in range(nodes.shape[0]):
        node = nodes[i]
        pn = x[node, 3:]
        An = rotation_matrix(pn)
        u = positions[i] + phi[i] @ zeta
        theta = phi_star[i] @ zeta
        nb_ = 7 * node
        r0 = 6 * i
        turned = A @ phi[i]
        bu = b_matrix(p, u)
        for a in range(3):
            out[r0 + a, nb_ + a] += 1.0
            out[r0 + a, fb + a] -= 1.0
            out[r0 + a, fb + 3 : fb + 7] -= bu[a]
            out[r0 + a, z_col : z_col + n] -= turned[a]
        for c in range(3):
            f, g = _PAIRS[c, 0], _PAIRS[c, 1]
            v = _turned(theta, g)
            an, b = An[:, f].copy(), A @ v
            r = r0 + 3 + c
            out[r, nb_ + 3 : nb_ + 7] += b @ b_matrix(pn, _unit(f))
            out[r, fb + 3 : fb + 7] += an @ b_matrix(p, v)
            at = an @ A  # (3,): d(an . A w)/dw
            for j in range(n):  # d(theta x g)/dzeta_j = phi*_j x g
                out[r, z_col + j] += at @ _cross_axis(phi_star[i, :, j], g)


@njit(**KERNEL)
def weld_gamma(x, xd, frame, nodes, positions, phi, phi_star, zeta, zeta_d, out):
    """phi_q qdd = gamma (6 k,) into `out`: minus the second derivative's terms without
    qdd."""
    p, pd = x[frame, 3:], xd[frame, 3:]
    A = rotation_matrix(p)
    for i in range(nodes.shape[0]):
        pn, pnd = x[nodes[i], 3:], xd[nodes[i], 3:]
        u = positions[i] + phi[i] @ zeta
        u_d = phi[i] @ zeta_d
        theta, theta_d = phi_star[i] @ zeta, phi_star[i] @ zeta_d
        out[6 * i : 6 * i + 3] = b_matrix(pd, u) @ pd + 2.0 * (b_matrix(p, u_d) @ pd)
        An = rotation_matrix(pn)
        for c in range(3):
            f, g = _PAIRS[c, 0], _PAIRS[c, 1]
            v = _turned(theta, g)
            v_d = _turned(theta_d, g)
            v_d[g] -= 1.0  # theta_d x g
            ef = _unit(f)
            an, b = An[:, f].copy(), A @ v
            an_d = b_matrix(pn, ef) @ pnd
            b_d = b_matrix(p, v) @ pd + A @ v_d
            quad = (b_matrix(pnd, ef) @ pnd) @ b + 2.0 * (an_d @ b_d)
            quad += an @ (b_matrix(pd, v) @ pd + 2.0 * (b_matrix(p, v_d) @ pd))
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
            out[6 * i + 3 + c] = (b_matrix(pn, _unit(f)) @ pnd) @ b + An[:, f].copy() @ b_d
