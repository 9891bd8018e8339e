"""Compiled (numba) kernels of the constraint primitives and the rigid-body mass terms.

Layout: `x` (nb+1, 7) rows [r, p] per body, ground last; `xd` their rates; Jacobian rows have
7 (nb+1) columns. Rotation of a body-fixed vector s: the homogeneous form
A(p) s = (e0^2 - e.e) s + 2 e (e.s) + 2 e0 (e x s); its polarisation b(p, w) s gives
B(p, s) w = d(A(p) s)/dp w = 2 b(p, w) s. Formulas: Haug (1989) ch. 9-11; G, E as in
Nikravesh (1988): omega' = 2 G pd (body axes), omega = 2 E pd (global axes).
numba replaces per-row Python loops that cost ~100x more in the interpreter.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.model.table_kernel import table_value

__all__ = [
    "angle_rate",
    "angle_state",
    "b_matrix",
    "body_forces",
    "dot1_gamma",
    "dot1_jac",
    "dot1_phi",
    "dot1_phi_jac",
    "dot1_rate",
    "dot2_gamma",
    "dot2_jac",
    "dot2_phi",
    "dot2_phi_jac",
    "dot2_rate",
    "inverse_mass_blocks",
    "mass_blocks",
    "mass_matrix",
    "mass_times",
    "norm_gamma",
    "norm_jac",
    "norm_phi",
    "pair_state",
    "point_force",
    "point_force3",
    "point_pair",
    "point_position",
    "point_velocity",
    "positive_cholesky",
    "rotation_matrix",
    "sph_gamma",
    "sph_jac",
    "sph_phi",
    "spring_state",
    "spring_wrench",
    "torsion_wrench",
]


@njit(**KERNEL)
def _dot3(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(**KERNEL)
def _rot(p, s, out):
    """out = A(p) s (`_rotated`)."""
    out[0], out[1], out[2] = _rotated(p, s)


@njit(**KERNEL)
def _rotated(p, s):
    """The components of A(p) s as three numbers: no array made (the hot loops' arms)."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    es = e1 * s[0] + e2 * s[1] + e3 * s[2]
    c = e0 * e0 - (e1 * e1 + e2 * e2 + e3 * e3)
    return (
        c * s[0] + 2.0 * e1 * es + 2.0 * e0 * (e2 * s[2] - e3 * s[1]),
        c * s[1] + 2.0 * e2 * es + 2.0 * e0 * (e3 * s[0] - e1 * s[2]),
        c * s[2] + 2.0 * e3 * es + 2.0 * e0 * (e1 * s[1] - e2 * s[0]),
    )


@njit(**KERNEL)
def _brot(p, w, s, out):
    """out = B(p, s) w = 2 b(p, w) s (the rate of A(p) s for pd = w)."""
    out[0], out[1], out[2] = _brotated(p, w, s)


@njit(**KERNEL)
def _brotated(p, w, s):
    """The components of B(p, s) w as three numbers (`_brot` without an array)."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    w0, f1, f2, f3 = w[0], w[1], w[2], w[3]
    c = e0 * w0 - (e1 * f1 + e2 * f2 + e3 * f3)
    fs = f1 * s[0] + f2 * s[1] + f3 * s[2]
    es = e1 * s[0] + e2 * s[1] + e3 * s[2]
    return (
        2.0
        * (
            c * s[0]
            + e1 * fs
            + f1 * es
            + e0 * (f2 * s[2] - f3 * s[1])
            + w0 * (e2 * s[2] - e3 * s[1])
        ),
        2.0
        * (
            c * s[1]
            + e2 * fs
            + f2 * es
            + e0 * (f3 * s[0] - f1 * s[2])
            + w0 * (e3 * s[0] - e1 * s[2])
        ),
        2.0
        * (
            c * s[2]
            + e3 * fs
            + f3 * es
            + e0 * (f1 * s[1] - f2 * s[0])
            + w0 * (e1 * s[1] - e2 * s[0])
        ),
    )


@njit(**KERNEL)
def _bmat(p, s, out):
    """out (3, 4) = B(p, s) = d(A(p) s)/dp (`_bmatrix`'s entries)."""
    m = _bmatrix(p, s)
    for a in range(3):
        for b in range(4):
            out[a, b] = m[4 * a + b]


@njit(**KERNEL)
def _bmatrix(p, s):
    """B(p, s) = d(A(p) s)/dp as 12 numbers, row by row: no array made (the constraint
    rows are evaluated at every Newton iteration; a small array costs about 30 ns there).
    Columns 1-3: 2 (e s^T - s e^T + (e.s) I - e0 [s]x)."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    s0, s1, s2 = s[0], s[1], s[2]
    es = e1 * s0 + e2 * s1 + e3 * s2
    return (
        2.0 * (e0 * s0 + e2 * s2 - e3 * s1),
        2.0 * (e1 * s0 - s0 * e1 + es),
        2.0 * (e1 * s1 - s0 * e2) + 2.0 * e0 * s2,
        2.0 * (e1 * s2 - s0 * e3) - 2.0 * e0 * s1,
        2.0 * (e0 * s1 + e3 * s0 - e1 * s2),
        2.0 * (e2 * s0 - s1 * e1) - 2.0 * e0 * s2,
        2.0 * (e2 * s1 - s1 * e2 + es),
        2.0 * (e2 * s2 - s1 * e3) + 2.0 * e0 * s0,
        2.0 * (e0 * s2 + e1 * s1 - e2 * s0),
        2.0 * (e3 * s0 - s2 * e1) + 2.0 * e0 * s1,
        2.0 * (e3 * s1 - s2 * e2) - 2.0 * e0 * s0,
        2.0 * (e3 * s2 - s2 * e3 + es),
    )


@njit(**KERNEL)
def b_matrix(p, s):
    """B(p, s) = d(A(p) s)/dp (3, 4) as a new array."""
    out = np.empty((3, 4))
    _bmat(p, s, out)
    return out


@njit(**KERNEL)
def sph_phi(x, bi, bj, si, sj, out):
    for k in range(bi.shape[0]):
        a = _rotated(x[bi[k], 3:], si[k])
        b = _rotated(x[bj[k], 3:], sj[k])
        for c in range(3):
            out[3 * k + c] = x[bi[k], c] + a[c] - x[bj[k], c] - b[c]


@njit(**KERNEL)
def sph_jac(x, bi, bj, si, sj, out):
    for k in range(bi.shape[0]):
        ci, cj = 7 * bi[k], 7 * bj[k]
        for c in range(3):
            out[3 * k + c, ci + c] += 1.0
            out[3 * k + c, cj + c] -= 1.0
        m = _bmatrix(x[bi[k], 3:], si[k])
        for c in range(3):
            for d in range(4):
                out[3 * k + c, ci + 3 + d] += m[4 * c + d]
        m = _bmatrix(x[bj[k], 3:], sj[k])
        for c in range(3):
            for d in range(4):
                out[3 * k + c, cj + 3 + d] -= m[4 * c + d]


@njit(**KERNEL)
def sph_gamma(x, xd, bi, bj, si, sj, out):
    for k in range(bi.shape[0]):
        a = _rotated(xd[bi[k], 3:], si[k])
        b = _rotated(xd[bj[k], 3:], sj[k])
        for c in range(3):
            out[3 * k + c] = -2.0 * (a[c] - b[c])


@njit(**KERNEL)
def dot1_phi(x, bi, bj, u, v, out):
    for k in range(bi.shape[0]):
        out[k] = _dot3(_rotated(x[bi[k], 3:], u[k]), _rotated(x[bj[k], 3:], v[k]))


@njit(**KERNEL)
def dot1_jac(x, bi, bj, u, v, out):
    for k in range(bi.shape[0]):
        a = _rotated(x[bi[k], 3:], u[k])
        b = _rotated(x[bj[k], 3:], v[k])
        _dot1_row(x, k, bi, bj, u, v, a, b, out)


@njit(**KERNEL)
def dot1_phi_jac(x, bi, bj, u, v, phi, out):
    """`dot1_phi` and `dot1_jac` in one loop: each row's arms A_i u, A_j v taken once
    (the same products, bit for bit)."""
    for k in range(bi.shape[0]):
        a = _rotated(x[bi[k], 3:], u[k])
        b = _rotated(x[bj[k], 3:], v[k])
        phi[k] = _dot3(a, b)
        _dot1_row(x, k, bi, bj, u, v, a, b, out)


@njit(**KERNEL)
def _dot1_row(x, k, bi, bj, u, v, a, b, out):
    """Dot-1 row k's Jacobian entries added into out[k] from its arms a = A_i u, b = A_j v."""
    m = _bmatrix(x[bi[k], 3:], u[k])
    for d in range(4):
        out[k, 7 * bi[k] + 3 + d] += b[0] * m[d] + b[1] * m[4 + d] + b[2] * m[8 + d]
    m = _bmatrix(x[bj[k], 3:], v[k])
    for d in range(4):
        out[k, 7 * bj[k] + 3 + d] += a[0] * m[d] + a[1] * m[4 + d] + a[2] * m[8 + d]


@njit(**KERNEL)
def dot1_rate(x, xd, bi, bj, u, v, out):
    a = np.empty(3)
    b = np.empty(3)
    ad = np.empty(3)
    bd = np.empty(3)
    for k in range(bi.shape[0]):
        _rot(x[bi[k], 3:], u[k], a)
        _rot(x[bj[k], 3:], v[k], b)
        _brot(x[bi[k], 3:], xd[bi[k], 3:], u[k], ad)
        _brot(x[bj[k], 3:], xd[bj[k], 3:], v[k], bd)
        out[k] = _dot3(ad, b) + _dot3(a, bd)


@njit(**KERNEL)
def dot1_gamma(x, xd, bi, bj, u, v, out):
    for k in range(bi.shape[0]):
        pi, pj, wi, wj = x[bi[k], 3:], x[bj[k], 3:], xd[bi[k], 3:], xd[bj[k], 3:]
        a, b = _rotated(pi, u[k]), _rotated(pj, v[k])
        ad, bd = _brotated(pi, wi, u[k]), _brotated(pj, wj, v[k])
        add, bdd = _rotated(wi, u[k]), _rotated(wj, v[k])
        out[k] = -(2.0 * _dot3(add, b) + 2.0 * _dot3(ad, bd) + 2.0 * _dot3(a, bdd))


@njit(**KERNEL)
def _dot2_arms(x, k, bi, bj, v, si, sj):
    """Dot-2 row k's b = A_j v and d = r_i + A_i s_i - r_j - A_j s_j as tuples (no array
    made: the rows are evaluated at every Newton iteration and every dense row)."""
    pi, pj = x[bi[k], 3:], x[bj[k], 3:]
    b = _rotated(pj, v[k])
    d0, d1, d2 = _rotated(pi, si[k])
    t0, t1, t2 = _rotated(pj, sj[k])
    xi, xj = x[bi[k]], x[bj[k]]
    d = (d0 + (xi[0] - xj[0] - t0), d1 + (xi[1] - xj[1] - t1), d2 + (xi[2] - xj[2] - t2))
    return b, d


@njit(**KERNEL)
def _dot2_rates(x, xd, k, bi, bj, v, si, sj):
    """The rates of `_dot2_arms`' b and d for xd, as tuples."""
    pi, pj = x[bi[k], 3:], x[bj[k], 3:]
    bd = _brotated(pj, xd[bj[k], 3:], v[k])
    d0, d1, d2 = _brotated(pi, xd[bi[k], 3:], si[k])
    t0, t1, t2 = _brotated(pj, xd[bj[k], 3:], sj[k])
    vi, vj = xd[bi[k]], xd[bj[k]]
    dd = (d0 + (vi[0] - vj[0] - t0), d1 + (vi[1] - vj[1] - t1), d2 + (vi[2] - vj[2] - t2))
    return bd, dd


@njit(**KERNEL)
def dot2_phi(x, bi, bj, v, si, sj, out):
    for k in range(bi.shape[0]):
        b, d = _dot2_arms(x, k, bi, bj, v, si, sj)
        out[k] = _dot3(b, d)


@njit(**KERNEL)
def dot2_jac(x, bi, bj, v, si, sj, out):
    for k in range(bi.shape[0]):
        b, d = _dot2_arms(x, k, bi, bj, v, si, sj)
        _dot2_row(x, k, bi, bj, v, si, sj, b, d, out)


@njit(**KERNEL)
def dot2_phi_jac(x, bi, bj, v, si, sj, phi, out):
    """`dot2_phi` and `dot2_jac` in one loop: each row's arms (`_dot2_arms`) taken once
    (the same products, bit for bit)."""
    for k in range(bi.shape[0]):
        b, d = _dot2_arms(x, k, bi, bj, v, si, sj)
        phi[k] = _dot3(b, d)
        _dot2_row(x, k, bi, bj, v, si, sj, b, d, out)


@njit(**KERNEL)
def _dot2_row(x, k, bi, bj, v, si, sj, b, d, out):
    """Dot-2 row k's Jacobian entries added into out[k] from its arms b, d (`_dot2_arms`)."""
    ci, cj = 7 * bi[k], 7 * bj[k]
    for c in range(3):
        out[k, ci + c] += b[c]
        out[k, cj + c] -= b[c]
    m = _bmatrix(x[bi[k], 3:], si[k])
    for e in range(4):
        out[k, ci + 3 + e] += b[0] * m[e] + b[1] * m[4 + e] + b[2] * m[8 + e]
    m = _bmatrix(x[bj[k], 3:], v[k])
    for e in range(4):
        out[k, cj + 3 + e] += d[0] * m[e] + d[1] * m[4 + e] + d[2] * m[8 + e]
    m = _bmatrix(x[bj[k], 3:], sj[k])
    for e in range(4):
        out[k, cj + 3 + e] -= b[0] * m[e] + b[1] * m[4 + e] + b[2] * m[8 + e]


@njit(**KERNEL)
def dot2_rate(x, xd, bi, bj, v, si, sj, out):
    for k in range(bi.shape[0]):
        b, d = _dot2_arms(x, k, bi, bj, v, si, sj)
        bd, dd = _dot2_rates(x, xd, k, bi, bj, v, si, sj)
        out[k] = _dot3(bd, d) + _dot3(b, dd)


@njit(**KERNEL)
def dot2_gamma(x, xd, bi, bj, v, si, sj, out):
    for k in range(bi.shape[0]):
        b, d = _dot2_arms(x, k, bi, bj, v, si, sj)
        bd, dd = _dot2_rates(x, xd, k, bi, bj, v, si, sj)
        bdd = _rotated(xd[bj[k], 3:], v[k])
        t1 = _rotated(xd[bi[k], 3:], si[k])
        t2 = _rotated(xd[bj[k], 3:], sj[k])
        ddd = 2.0 * (_dot3(b, t1) - _dot3(b, t2))
        out[k] = -(2.0 * _dot3(bdd, d) + 2.0 * _dot3(bd, dd) + ddd)


@njit(**KERNEL)
def norm_phi(x, nb, out):
    for k in range(nb):
        out[k] = x[k, 3] ** 2 + x[k, 4] ** 2 + x[k, 5] ** 2 + x[k, 6] ** 2 - 1.0


@njit(**KERNEL)
def norm_jac(x, nb, out):
    for k in range(nb):
        for d in range(4):
            out[k, 7 * k + 3 + d] += 2.0 * x[k, 3 + d]


@njit(**KERNEL)
def norm_gamma(xd, nb, out):
    for k in range(nb):
        out[k] = -2.0 * (xd[k, 3] ** 2 + xd[k, 4] ** 2 + xd[k, 5] ** 2 + xd[k, 6] ** 2)


@njit(**KERNEL)
def _g_times(p, w, out):
    """out (3) = G(p) w."""
    out[0], out[1], out[2] = _g_of(p, w)


@njit(**KERNEL)
def _g_of(p, w):
    """G(p) w as three numbers (no array made)."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    return (
        -w[0] * e1 + e0 * w[1] - (e2 * w[3] - e3 * w[2]),
        -w[0] * e2 + e0 * w[2] - (e3 * w[1] - e1 * w[3]),
        -w[0] * e3 + e0 * w[3] - (e1 * w[2] - e2 * w[1]),
    )


@njit(**KERNEL)
def _gt_times(p, y, sign, out):
    """out (4) = G(p)^T y (sign = +1) or E(p)^T y (sign = -1)."""
    out[0], out[1], out[2], out[3] = _gt_of(p, y, sign)


@njit(**KERNEL)
def _gt_of(p, y, sign):
    """`_gt_times` as four numbers (no array made)."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    return (
        -(e1 * y[0] + e2 * y[1] + e3 * y[2]),
        sign * (e2 * y[2] - e3 * y[1]) + e0 * y[0],
        sign * (e3 * y[0] - e1 * y[2]) + e0 * y[1],
        sign * (e1 * y[1] - e2 * y[0]) + e0 * y[2],
    )


@njit(**KERNEL)
def _inertia_times(inertia, w, out):
    """out (3) = inertia (3, 3) w, inline (numba's @ calls BLAS and allocates)."""
    out[0], out[1], out[2] = _inertia_of(inertia, w)


@njit(**KERNEL)
def _inertia_of(inertia, w):
    """inertia (3, 3) w as three numbers (no array made)."""
    return (
        inertia[0, 0] * w[0] + inertia[0, 1] * w[1] + inertia[0, 2] * w[2],
        inertia[1, 0] * w[0] + inertia[1, 1] * w[1] + inertia[1, 2] * w[2],
        inertia[2, 0] * w[0] + inertia[2, 1] * w[1] + inertia[2, 2] * w[2],
    )


@njit(**KERNEL)
def mass_times(x, masses, inertia, scale, vec, out):
    """out = M(q) vec; M_p = 4 G^T J' G + scale p p^T (the last term only fixes |p|)."""
    for b in range(masses.shape[0]):
        o = 7 * b
        for c in range(3):
            out[o + c] = masses[b] * vec[o + c]
        p = x[b, 3:]
        g4 = _gt_of(p, _inertia_of(inertia[b], _g_of(p, vec[o + 3 : o + 7])), 1.0)
        pv = p[0] * vec[o + 3] + p[1] * vec[o + 4] + p[2] * vec[o + 5] + p[3] * vec[o + 6]
        for d in range(4):
            out[o + 3 + d] = 4.0 * g4[d] + scale[b] * p[d] * pv


@njit(**KERNEL)
def _rotation_block(p, inertia, quarter, along, divisor, out):
    """out (4, 4) = (quarter G^T J G + along p p^T) / divisor for Euler parameters p and a
    (3, 3) `inertia` J: the one loop of `mass_blocks` and `inverse_mass_blocks`, column d
    from the unit vector e_d as numbers (no array made: a dense row takes M^-1's blocks)."""
    for d in range(4):
        unit = (
            1.0 if d == 0 else 0.0,
            1.0 if d == 1 else 0.0,
            1.0 if d == 2 else 0.0,
            1.0 if d == 3 else 0.0,
        )
        g4 = _gt_of(p, _inertia_of(inertia, _g_of(p, unit)), 1.0)
        for e in range(4):
            out[e, d] = (quarter * g4[e] + along * p[e] * p[d]) / divisor


@njit(**KERNEL)
def mass_blocks(x, masses, inertia, scale, out):
    """The diagonal blocks (nb, 7, 7) of M(q): m I for r, 4 G^T J' G + scale p p^T for p."""
    for b in range(masses.shape[0]):
        out[b] = 0.0
        for c in range(3):
            out[b, c, c] = masses[b]
        _rotation_block(x[b, 3:], inertia[b], 4.0, scale[b], 1.0, out[b, 3:, 3:])


@njit(**KERNEL)
def inverse_mass_blocks(x, masses, inverse_inertia, scale, out):
    """The inverses (nb, 7, 7) of `mass_blocks`: I / m for r and, as P = [G; p^T] has
    P P^T = P^T P = |p|^2 I, (G^T J'^-1 G / 4 + p p^T / scale) / |p|^4 for p;
    `inverse_inertia` (nb, 3, 3): each J'^-1."""
    for b in range(masses.shape[0]):
        out[b] = 0.0
        for c in range(3):
            out[b, c, c] = 1.0 / masses[b]
        p = x[b, 3:]
        norm4 = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3]) ** 2
        _rotation_block(p, inverse_inertia[b], 0.25, 1.0 / scale[b], norm4, out[b, 3:, 3:])


@njit(**KERNEL)
def mass_matrix(x, masses, inertia, scale, out):
    """Dense M(q) (nq, nq), block diagonal (`mass_blocks` on the diagonal)."""
    blocks = np.empty((masses.shape[0], 7, 7))
    mass_blocks(x, masses, inertia, scale, blocks)
    for b in range(masses.shape[0]):
        o = 7 * b
        for c in range(7):
            for d in range(7):
                out[o + c, o + d] = blocks[b, c, d]


@njit(**KERNEL)
def body_forces(x, xd, masses, inertia, gravity, F, N, with_inertia, out):
    """Q (nq): forces F and torques N (global, through the cm, gravity added here) and, with
    `with_inertia`, the quadratic velocity term -8 G(pd)^T J' G(p) pd."""
    for b in range(masses.shape[0]):
        o = 7 * b
        for c in range(3):
            out[o + c] = F[b, c] + masses[b] * gravity[c]
        p, pd = x[b, 3:], xd[b, 3:]
        g4 = _gt_of(p, N[b], -1.0)
        for d in range(4):
            out[o + 3 + d] = 2.0 * g4[d]
        if with_inertia:
            w0, w1, w2 = _g_of(p, pd)
            g4 = _gt_of(pd, _inertia_of(inertia[b], (w0 * 2.0, w1 * 2.0, w2 * 2.0)), 1.0)
            for d in range(4):
                out[o + 3 + d] -= 4.0 * g4[d]


@njit(**KERNEL)
def point_position(x, b, s):
    """Global position (m) of the body-fixed vector s of body b: r_b + A(p_b) s."""
    out = np.empty(3)
    _rot(x[b, 3:], s, out)
    for c in range(3):
        out[c] += x[b, c]
    return out


@njit(**KERNEL)
def point_velocity(x, xd, b, s):
    """Global velocity (m/s) of the body-fixed point s of body b: rd_b + B(p_b, s) pd_b."""
    out = np.empty(3)
    _brot(x[b, 3:], xd[b, 3:], s, out)
    for c in range(3):
        out[c] += xd[b, c]
    return out


@njit(**KERNEL)
def rotation_matrix(p):
    """A(p) (3, 3) of one set of Euler parameters (homogeneous form)."""
    out = np.empty((3, 3))
    unit = np.zeros(3)
    col = np.empty(3)
    for j in range(3):
        unit[:] = 0.0
        unit[j] = 1.0
        _rot(p, unit, col)
        out[:, j] = col
    return out


@njit(**KERNEL)
def point_force(x, b, s, force, F, N):
    """Add a force (N, global) at the body-fixed point s of body b to F[b] and its moment
    about the cm, A(p_b) s x force, to N[b]."""
    point_force3(x, b, s, force[0], force[1], force[2], F, N)


@njit(**KERNEL)
def point_force3(x, b, s, f0, f1, f2, F, N):
    """`point_force` of the force (f0, f1, f2) (N, global): no array made."""
    a0, a1, a2 = _rotated(x[b, 3:], s)
    F[b, 0] += f0
    F[b, 1] += f1
    F[b, 2] += f2
    N[b, 0] += a1 * f2 - a2 * f1
    N[b, 1] += a2 * f0 - a0 * f2
    N[b, 2] += a0 * f1 - a1 * f0


@njit(**KERNEL)
def point_pair(x, xd, b1, s1, b2, s2, unit):
    """(length (m), rate (m/s)) of the line from the body-fixed point s2 of b2 to s1 of b1;
    its unit vector into `unit` (3,), zero at zero length (`pair_state`)."""
    length, rate, unit[0], unit[1], unit[2] = pair_state(x, xd, b1, s1, b2, s2)
    return length, rate


@njit(**KERNEL)
def pair_state(x, xd, b1, s1, b2, s2):
    """`point_pair` as five numbers (length (m), rate (m/s), the unit vector's three): no
    array made (the elements' loads are evaluated at every Newton iteration)."""
    a1, a2 = _rotated(x[b1, 3:], s1), _rotated(x[b2, 3:], s2)
    v1, v2 = _brotated(x[b1, 3:], xd[b1, 3:], s1), _brotated(x[b2, 3:], xd[b2, 3:], s2)
    # positions and velocities: r + A s and rd + B w s
    d0 = (a1[0] + x[b1, 0]) - (a2[0] + x[b2, 0])
    d1 = (a1[1] + x[b1, 1]) - (a2[1] + x[b2, 1])
    d2 = (a1[2] + x[b1, 2]) - (a2[2] + x[b2, 2])
    length = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    u0 = d0 / length if length > 0.0 else 0.0
    u1 = d1 / length if length > 0.0 else 0.0
    u2 = d2 / length if length > 0.0 else 0.0
    rate = 0.0
    rate += u0 * ((v1[0] + xd[b1, 0]) - (v2[0] + xd[b2, 0]))
    rate += u1 * ((v1[1] + xd[b1, 1]) - (v2[1] + xd[b2, 1]))
    rate += u2 * ((v1[2] + xd[b1, 2]) - (v2[2] + xd[b2, 2]))
    return length, rate, u0, u1, u2


@njit(**KERNEL)
def spring_state(x, xd, b1, s1, b2, s2, stiffness, damping, free_length, preload, slack, out):
    """out (5,) = [tension (N), length (m), unit vector (3) from point 2 to point 1] of a
    linear spring-damper between the body-fixed points s1 of b1 and s2 of b2
    (`_spring_tension`)."""
    tension, length, u0, u1, u2 = _spring_tension(
        x, xd, b1, s1, b2, s2, stiffness, damping, free_length, preload, slack
    )
    out[0], out[1], out[2], out[3], out[4] = tension, length, u0, u1, u2


@njit(**KERNEL)
def _spring_tension(x, xd, b1, s1, b2, s2, stiffness, damping, free_length, preload, slack):
    """(tension (N), length (m), unit vector (3) from point 2 to point 1): stiffness (N/m) x
    (length - free_length) + damping (N*s/m) x rate + preload; with `slack` (a wire) none
    while shorter than its free length or pushing."""
    length, rate, u0, u1, u2 = pair_state(x, xd, b1, s1, b2, s2)
    stretch = length - free_length
    tension = stiffness * stretch + damping * rate + preload
    if slack and (stretch < 0.0 or tension < 0.0):
        tension = 0.0
    return tension, length, u0, u1, u2


@njit(**KERNEL)
def spring_wrench(x, xd, b1, s1, b2, s2, stiffness, damping, free_length, preload, slack, F, N):
    """Add a linear spring-damper's forces (spring_state): -tension along the unit vector
    at point 1, +tension at point 2, with their moments about the cms, to F and N."""
    tension, _, u0, u1, u2 = _spring_tension(
        x, xd, b1, s1, b2, s2, stiffness, damping, free_length, preload, slack
    )
    f0, f1, f2 = tension * u0, tension * u1, tension * u2
    point_force3(x, b1, s1, -f0, -f1, -f2, F, N)
    point_force3(x, b2, s2, f0, f1, f2, F, N)


@njit(**KERNEL)
def angle_state(x, xd, bi, bj, f, g, reference, out):
    """out (2,) = [angle (rad), rate (rad/s)] of body bi relative to body bj about a joint
    axis (`angle_rate`)."""
    out[0], out[1] = angle_rate(x, xd, bi, bj, f, g, reference)


@njit(**KERNEL)
def angle_rate(x, xd, bi, bj, f, g, reference):
    """(angle (rad), rate (rad/s)) of body bi relative to body bj about a joint axis with
    body-fixed triad vectors f, g (mechlib.kinematics.coordinates.AngleMeasure): atan2(
    f_i . g_j, f_i . f_j), unwrapped to the turn nearest `reference` (rad); no array made."""
    pi, pj, wi, wj = x[bi, 3:], x[bj, 3:], xd[bi, 3:], xd[bj, 3:]
    fi, gj, fj = _rotated(pi, f), _rotated(pj, g), _rotated(pj, f)
    fid, gjd, fjd = _brotated(pi, wi, f), _brotated(pj, wj, g), _brotated(pj, wj, f)
    s, c = _dot3(fi, gj), _dot3(fi, fj)
    sd, cd = _dot3(fid, gj) + _dot3(fi, gjd), _dot3(fid, fj) + _dot3(fi, fjd)
    raw = math.atan2(s, c)
    turns = (reference - raw) / (2.0 * math.pi)
    # half-way ties to even, as Python's
    return raw + 2.0 * math.pi * np.round(turns), (c * sd - s * cd) / (s * s + c * c)


@njit(**KERNEL)
def torsion_wrench(x, xd, bi, bj, f, g, axis, reference, stiffness, damping, angle0, preload, N):
    """Add a linear torsion spring-damper's moments to N: moment = stiffness (N*m/rad) x
    (angle - angle0) + damping (N*m*s/rad) x rate + preload (N*m) about the joint axis
    (body-fixed `axis` of bj), -moment on bi, +moment on bj (angle_rate)."""
    angle, rate = angle_rate(x, xd, bi, bj, f, g, reference)
    moment = stiffness * (angle - angle0) + damping * rate + preload
    _resist_rotation(x, bi, bj, axis, moment, N)


@njit(**KERNEL)
def torsion_table_wrench(x, xd, ints, floats, reference, breaks, coefs, ends, flags, N):
    """Add a tabulated torsion spring-damper's moments to N: moment = law(angle - angle0)
    (N*m, the packed table: mechlib.model.table_kernel) + damping (N*m*s/rad) x rate + preload
    (N*m), as torsion_wrench. ints: the angle's bodies (bi, bj); floats: its triad f, g,
    the axis (body-fixed in bj), damping, angle0 (rad), preload. False, and nothing added,
    where the table refuses the turn."""
    state = np.empty(2)
    angle_state(x, xd, ints[0], ints[1], floats[0:3], floats[3:6], reference, state)
    ok, elastic = table_value(breaks, coefs, ends, flags, state[0] - floats[10])
    if not ok:
        return False
    moment = elastic + floats[9] * state[1] + floats[11]
    _resist_rotation(x, ints[0], ints[1], floats[6:9], moment, N)
    return True


@njit(**KERNEL)
def _resist_rotation(x, bi, bj, axis, moment, N):
    """A moment (N*m) resisting bi's rotation about the body-fixed `axis` of bj: -moment
    on bi, +moment on bj (mechlib.elements.forces.resist_rotation)."""
    a = _rotated(x[bj, 3:], axis)
    for c in range(3):
        N[bi, c] -= moment * a[c]
        N[bj, c] += moment * a[c]


@njit(**KERNEL)
def positive_cholesky(a):
    """(ok, L): the Cholesky factor of the symmetric `a`; ok False where `a` is not finite
    or not positive definite (L is then `a`)."""
    for v in a.ravel():
        if not np.isfinite(v):
            return False, a
    try:
        low = np.linalg.cholesky(a)
    except Exception:  # noqa: BLE001 -- numba catches no narrower class; not positive definite
        return False, a
    return True, low
