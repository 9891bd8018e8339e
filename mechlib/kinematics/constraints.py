"""Constraint primitives evaluated as arrays, one compiled call per primitive type.

Every primitive group computes, for k equations at once: the residual ``phi`` (k,), its
Jacobian rows ``phi_q`` (k, 7 (nb+1)), and ``gamma`` (k,), the part of the second time
derivative not multiplying ``qdd`` with its sign changed (``phi_q qdd = gamma``). Vectors
given to a group are body-fixed (body axes = global axes at the design position).
Source: Haug, Computer-Aided Kinematics and Dynamics of Mechanical Systems (1989), ch. 9-11;
the arithmetic is in `mechlib.kinematics.kernels`.
"""

from __future__ import annotations

import numpy as np

from mechlib.kinematics import kernels as kr
from mechlib.kinematics.kin import Kin

__all__ = ["Dot1", "Dot2", "Normalization", "Spherical"]


Entries = tuple[np.ndarray, np.ndarray, np.ndarray]  # rows, columns, values
_CHUNK = 128  # items a group's kernel takes at once for `entries` (a small dense block)


def _joined(parts: list[Entries]) -> Entries:
    if not parts:
        return np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0)
    return tuple(np.concatenate(column) for column in zip(*parts))  # type: ignore[return-value]


def _ints(a) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(a, dtype=np.int64).reshape(-1))


def _vecs(a) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(a, dtype=float).reshape(-1, 3))


class _Group:
    """k equations of one primitive type; subclasses name their kernels (in
    `mechlib.kinematics.kernels`, by the prefix of `_phi`, `_jac`, `_gamma`, `_rate`) and rows per
    item. The kernels are looked up in the module at each call: once compiled, that is the
    numba dispatcher itself, without the `mechlib.core.jit` mark's call in between."""

    rows_per_item = 1
    prefix = ""

    def __init__(self, args: tuple):
        self.args = args
        self.size = self.rows_per_item * len(args[0])
        self._names = tuple(self.prefix + part for part in ("_phi", "_jac", "_gamma", "_rate"))

    def phi(self, k: Kin) -> np.ndarray:
        out = np.empty(self.size)
        getattr(kr, self._names[0])(k.x, *self.args, out)
        return out

    def jacobian(self, k: Kin, out: np.ndarray) -> None:
        """Add the rows into `out` (k, 7 (nb+1))."""
        getattr(kr, self._names[1])(k.x, *self.args, out)

    def gamma(self, k: Kin) -> np.ndarray:
        out = np.empty(self.size)
        getattr(kr, self._names[2])(k.x, k.xd, *self.args, out)
        return out

    def entries(self, k: Kin) -> Entries:
        """The non-zeros of its Jacobian rows: (row in the group, column of the working
        Jacobian, value), by the same kernel run on `_CHUNK` items at a time with only
        their bodies' columns, never the dense (k, 7 (nb+1)) block (mechlib.linalg.rank)."""
        bi, bj, *vectors = self.args
        parts = []
        for first in range(0, len(bi), _CHUNK):
            items = slice(first, first + _CHUNK)
            bodies = np.unique(np.concatenate([bi[items], bj[items]]))
            local_i, local_j = (
                np.searchsorted(bodies, bi[items]),
                np.searchsorted(bodies, bj[items]),
            )
            out = np.zeros((self.rows_per_item * local_i.size, 7 * bodies.size))
            args = (local_i, local_j, *(v[items] for v in vectors))
            getattr(kr, self._names[1])(k.x[bodies], *args, out)
            rows, cols = np.nonzero(out)
            parts.append(
                (
                    rows + self.rows_per_item * first,
                    7 * bodies[cols // 7] + cols % 7,
                    out[rows, cols],
                )
            )
        return _joined(parts)

    def rate(self, k: Kin) -> np.ndarray:
        """d(phi)/dt (k,)."""
        out = np.empty(self.size)
        getattr(kr, self._names[3])(k.x, k.xd, *self.args, out)
        return out


class Spherical(_Group):
    """Point s_i of body i coincides with point s_j of body j: 3 equations per pair."""

    rows_per_item = 3
    prefix = "sph"

    def __init__(self, bi, bj, si, sj):
        super().__init__((_ints(bi), _ints(bj), _vecs(si), _vecs(sj)))


class Dot1(_Group):
    """Body-fixed vector u of body i stays perpendicular to vector v of body j: a_i . a_j."""

    prefix = "dot1"

    def __init__(self, bi, bj, u, v):
        super().__init__((_ints(bi), _ints(bj), _vecs(u), _vecs(v)))


class Dot2(_Group):
    """Vector v of body j stays perpendicular to d = P_i - P_j (points s_i on i, s_j on j)."""

    prefix = "dot2"

    def __init__(self, bi, bj, v, si, sj):
        super().__init__((_ints(bi), _ints(bj), _vecs(v), _vecs(si), _vecs(sj)))


class Normalization:
    """Euler-parameter normalisation p.p - 1 = 0 of every moving body."""

    def __init__(self, nb: int):
        self.nb = nb
        self.size = nb

    def phi(self, k: Kin) -> np.ndarray:
        out = np.empty(self.size)
        kr.norm_phi(k.x, self.nb, out)
        return out

    def jacobian(self, k: Kin, out: np.ndarray) -> None:
        kr.norm_jac(k.x, self.nb, out)

    def entries(self, k: Kin) -> Entries:
        """The non-zeros of its Jacobian rows, as `_Group.entries`."""
        parts = []
        for first in range(0, self.nb, _CHUNK):
            count = min(_CHUNK, self.nb - first)
            out = np.zeros((count, 7 * count))
            kr.norm_jac(k.x[first : first + count], count, out)
            rows, cols = np.nonzero(out)
            parts.append((rows + first, cols + 7 * first, out[rows, cols]))
        return _joined(parts)

    def gamma(self, k: Kin) -> np.ndarray:
        out = np.empty(self.size)
        kr.norm_gamma(k.xd, self.nb, out)
        return out
