"""Constraint primitives evaluated as arrays, one call per primitive type.

Every primitive group computes, for k equations at once: the residual ``phi`` (k,), its
Jacobian rows ``phi_q`` (k, 7 (nb+1)), and ``gamma`` (k,), the part of the second time
derivative not multiplying ``qdd`` with its sign changed (``phi_q qdd = gamma``). Vectors
given to a group are body-fixed (body axes = global axes at the design position).
Source: Haug, Computer-Aided Kinematics and Dynamics of Mechanical Systems (1989), ch. 9-11.
"""
from __future__ import annotations

import numpy as np

from mechlib.kin import Kin
from mechlib.rotation import d_rotate, rotate

__all__ = ["Spherical", "Dot1", "Dot2", "Normalization", "scatter_body_blocks"]


def scatter_body_blocks(out: np.ndarray, body: np.ndarray, rows: np.ndarray,
                        block: np.ndarray, first_col: int = 0) -> None:
    """Add blocks (k, m, w) into rows (k, m) of `out`, columns 7*body + first_col ... + w."""
    width = block.shape[-1]
    cols = 7 * body[:, None] + first_col + np.arange(width)[None, :]
    out[rows[:, :, None], cols[:, None, :]] += block


class Spherical:
    """Point s_i of body i coincides with point s_j of body j: 3 equations per pair."""

    def __init__(self, bi, bj, si, sj):
        self.bi, self.bj = np.asarray(bi, int), np.asarray(bj, int)
        self.si, self.sj = np.asarray(si, float).reshape(-1, 3), np.asarray(sj, float).reshape(-1, 3)
        self.size = 3 * len(self.bi)

    def phi(self, k: Kin) -> np.ndarray:
        d = (k.r[self.bi] + rotate(k.p[self.bi], self.si)
             - k.r[self.bj] - rotate(k.p[self.bj], self.sj))
        return d.ravel()

    def jacobian(self, k: Kin, out: np.ndarray) -> None:
        n = len(self.bi)
        rows = np.arange(3 * n).reshape(n, 3)
        eye = np.broadcast_to(np.eye(3), (n, 3, 3))
        scatter_body_blocks(out, self.bi, rows, eye)
        scatter_body_blocks(out, self.bj, rows, -eye)
        scatter_body_blocks(out, self.bi, rows, d_rotate(k.p[self.bi], self.si), 3)
        scatter_body_blocks(out, self.bj, rows, -d_rotate(k.p[self.bj], self.sj), 3)

    def gamma(self, k: Kin) -> np.ndarray:
        g = -2.0 * (rotate(k.pd[self.bi], self.si) - rotate(k.pd[self.bj], self.sj))
        return g.ravel()


class Dot1:
    """Body-fixed vector u of body i stays perpendicular to vector v of body j: a_i . a_j."""

    def __init__(self, bi, bj, u, v):
        self.bi, self.bj = np.asarray(bi, int), np.asarray(bj, int)
        self.u, self.v = np.asarray(u, float).reshape(-1, 3), np.asarray(v, float).reshape(-1, 3)
        self.size = len(self.bi)

    def phi(self, k: Kin) -> np.ndarray:
        a, b = rotate(k.p[self.bi], self.u), rotate(k.p[self.bj], self.v)
        return np.einsum("ki,ki->k", a, b)

    def jacobian(self, k: Kin, out: np.ndarray) -> None:
        a, b = rotate(k.p[self.bi], self.u), rotate(k.p[self.bj], self.v)
        rows = np.arange(self.size)[:, None]
        ja = np.einsum("ki,kij->kj", b, d_rotate(k.p[self.bi], self.u))[:, None, :]
        jb = np.einsum("ki,kij->kj", a, d_rotate(k.p[self.bj], self.v))[:, None, :]
        scatter_body_blocks(out, self.bi, rows, ja, 3)
        scatter_body_blocks(out, self.bj, rows, jb, 3)

    def rate(self, k: Kin) -> np.ndarray:
        """d(phi)/dt (k,)."""
        a, b = rotate(k.p[self.bi], self.u), rotate(k.p[self.bj], self.v)
        ad = np.einsum("kij,kj->ki", d_rotate(k.p[self.bi], self.u), k.pd[self.bi])
        bd = np.einsum("kij,kj->ki", d_rotate(k.p[self.bj], self.v), k.pd[self.bj])
        return np.einsum("ki,ki->k", ad, b) + np.einsum("ki,ki->k", a, bd)

    def gamma(self, k: Kin) -> np.ndarray:
        pi, pj = k.p[self.bi], k.p[self.bj]
        a, b = rotate(pi, self.u), rotate(pj, self.v)
        ad = np.einsum("kij,kj->ki", d_rotate(pi, self.u), k.pd[self.bi])
        bd = np.einsum("kij,kj->ki", d_rotate(pj, self.v), k.pd[self.bj])
        add, bdd = 2.0 * rotate(k.pd[self.bi], self.u), 2.0 * rotate(k.pd[self.bj], self.v)
        return -(np.einsum("ki,ki->k", add, b) + 2.0 * np.einsum("ki,ki->k", ad, bd)
                 + np.einsum("ki,ki->k", a, bdd))


class Dot2:
    """Vector v of body j stays perpendicular to d = P_i - P_j (points s_i on i, s_j on j)."""

    def __init__(self, bi, bj, v, si, sj):
        self.bi, self.bj = np.asarray(bi, int), np.asarray(bj, int)
        self.v = np.asarray(v, float).reshape(-1, 3)
        self.si, self.sj = np.asarray(si, float).reshape(-1, 3), np.asarray(sj, float).reshape(-1, 3)
        self.size = len(self.bi)

    def _parts(self, k: Kin):
        pi, pj = k.p[self.bi], k.p[self.bj]
        b = rotate(pj, self.v)
        d = k.r[self.bi] + rotate(pi, self.si) - k.r[self.bj] - rotate(pj, self.sj)
        return pi, pj, b, d

    def phi(self, k: Kin) -> np.ndarray:
        _, _, b, d = self._parts(k)
        return np.einsum("ki,ki->k", b, d)

    def jacobian(self, k: Kin, out: np.ndarray) -> None:
        pi, pj, b, d = self._parts(k)
        rows = np.arange(self.size)[:, None]
        scatter_body_blocks(out, self.bi, rows, b[:, None, :])
        scatter_body_blocks(out, self.bj, rows, -b[:, None, :])
        jpi = np.einsum("ki,kij->kj", b, d_rotate(pi, self.si))
        jpj = (np.einsum("ki,kij->kj", d, d_rotate(pj, self.v))
               - np.einsum("ki,kij->kj", b, d_rotate(pj, self.sj)))
        scatter_body_blocks(out, self.bi, rows, jpi[:, None, :], 3)
        scatter_body_blocks(out, self.bj, rows, jpj[:, None, :], 3)

    def _rates(self, k: Kin):
        pi, pj, b, d = self._parts(k)
        bd = np.einsum("kij,kj->ki", d_rotate(pj, self.v), k.pd[self.bj])
        dd = (k.rd[self.bi] + np.einsum("kij,kj->ki", d_rotate(pi, self.si), k.pd[self.bi])
              - k.rd[self.bj] - np.einsum("kij,kj->ki", d_rotate(pj, self.sj), k.pd[self.bj]))
        return b, d, bd, dd

    def rate(self, k: Kin) -> np.ndarray:
        b, d, bd, dd = self._rates(k)
        return np.einsum("ki,ki->k", bd, d) + np.einsum("ki,ki->k", b, dd)

    def gamma(self, k: Kin) -> np.ndarray:
        b, d, bd, dd = self._rates(k)
        bdd = 2.0 * rotate(k.pd[self.bj], self.v)
        ddd = 2.0 * (rotate(k.pd[self.bi], self.si) - rotate(k.pd[self.bj], self.sj))
        return -(np.einsum("ki,ki->k", bdd, d) + 2.0 * np.einsum("ki,ki->k", bd, dd)
                 + np.einsum("ki,ki->k", b, ddd))


class Normalization:
    """Euler-parameter normalisation p.p - 1 = 0 of every moving body."""

    def __init__(self, nb: int):
        self.bodies = np.arange(nb)
        self.size = nb

    def phi(self, k: Kin) -> np.ndarray:
        p = k.p[self.bodies]
        return np.einsum("ki,ki->k", p, p) - 1.0

    def jacobian(self, k: Kin, out: np.ndarray) -> None:
        rows = np.arange(self.size)[:, None]
        scatter_body_blocks(out, self.bodies, rows, 2.0 * k.p[self.bodies][:, None, :], 3)

    def gamma(self, k: Kin) -> np.ndarray:
        pd = k.pd[self.bodies]
        return -2.0 * np.einsum("ki,ki->k", pd, pd)
