"""Point-on-curve joint: point s1 of body i stays on a curve fixed in body j (2 equations).

With u* the parameter of the curve point nearest the body-i point (body-j axes), n1, n2 the
curve's normals there: phi_k = (A_j n_k) . (P_i - r_j - A_j c(u*)) = 0, k = 1, 2. With u*
held, this is the `dot2` primitive (body-fixed n_k, s_i and c(u*)); its gradient is then
exact on the curve, since d(phi_k)/du* = n_k' . (rho - c) - n_k . c' vanishes there. The
acceleration equation adds the curvature: gamma_k = gamma_dot2 + (n_k . c'') u*'^2 with
u*' = c' . rho' / |c'|^2 (rho: the point in body-j axes) - the centripetal acceleration of
a point running along a bent path.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.rotation import cross, omega_global
from mechlib.kinematics import kernels as kr
from mechlib.kinematics.kin import Kin
from mechlib.model.curves import Curve

__all__ = ["CurveEquation", "CurvePoint"]


class CurvePoint:
    """The nearest curve point of body i's joint point, for both equations of one joint."""

    def __init__(self, bi: int, bj: int, si: np.ndarray, curve: Curve):
        self.bi, self.bj, self.si, self.curve = bi, bj, np.asarray(si, float), curve
        self.u: float | None = None  # warm start of the projection
        self._last: tuple | None = None

    def local(self, k: Kin) -> np.ndarray:
        """Body i's joint point in body-j axes relative to body j's origin (m)."""
        p = kr.point_position(k.x, self.bi, self.si)
        return kr.rotation_matrix(k.x[self.bj, 3:]).T @ (p - k.x[self.bj, :3])

    def project(self, k: Kin) -> tuple[float, np.ndarray, tuple, np.ndarray]:
        """(u*, body i's point in body-j axes, the normals n1 n2 and the curve point at u*);
        both equations and their gradients ask at the same poses: the last one is kept."""
        key = k.x[[self.bi, self.bj]].tobytes()
        if self._last is not None and self._last[0] == key:
            return self._last[1:]
        rho = self.local(k)
        self.u = u = self.curve.nearest(rho, self.u)
        self._last = (key, u, rho, self.curve.normals(u), self.curve.point(u))
        return self._last[1:]

    def parameter_rate(self, k: Kin, u: float) -> float:
        """du*/dt = c' . rho' / |c'|^2 (rho' seen from body j)."""
        p = kr.point_position(k.x, self.bi, self.si)
        rel = p - k.x[self.bj, :3]
        vel = kr.point_velocity(k.x, k.xd, self.bi, self.si) - k.xd[self.bj, :3]
        w = omega_global(k.x[self.bj, 3:], k.xd[self.bj, 3:])
        rho_rate = kr.rotation_matrix(k.x[self.bj, 3:]).T @ (vel - cross(w, rel))
        t = self.curve.tangent(u)
        return float(t @ rho_rate / (t @ t))


class CurveEquation:
    """One of the two equations (`which` 0 or 1) of a point-on-curve joint; labelled and
    owned like a coordinate equation (no time function: nu = 0)."""

    def __init__(self, point: CurvePoint, which: int, label: str, owner: str):
        self.point, self.which, self.label, self.owner = point, which, label, owner
        self.function = None

    def _frozen(
        self, k: Kin
    ) -> tuple[
        tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray], float, np.ndarray
    ]:
        """The dot2 data with u* held: (bi, bj, v, si, sj) arrays of one item, and u*."""
        pt = self.point
        u, _, normals, foot = pt.project(k)
        n = normals[self.which]
        args = (np.array([pt.bi]), np.array([pt.bj]), n[None, :], pt.si[None, :], foot[None, :])
        return args, u, n

    def phi(self, k: Kin) -> float:
        args, _, _ = self._frozen(k)
        out = np.empty(1)
        kr.dot2_phi(k.x, *args, out)
        return float(out[0])

    def gradient(self, k: Kin) -> np.ndarray:
        args, _, _ = self._frozen(k)
        row = np.zeros((1, k.ncol))
        kr.dot2_jac(k.x, *args, row)
        return row[0]

    def nu(self, t: float) -> float:
        return 0.0

    def gamma(self, k: Kin) -> float:
        args, u, n = self._frozen(k)
        out = np.empty(1)
        kr.dot2_gamma(k.x, k.xd, *args, out)
        rate = self.point.parameter_rate(k, u)
        return float(out[0] + (n @ self.point.curve.curvature_vector(u)) * rate * rate)
