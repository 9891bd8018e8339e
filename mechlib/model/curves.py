"""Space curves through a table of points: a spline c(u) parameterised by chord length u (m),
its derivatives, the point nearest a given point, and a normal frame that turns smoothly
along the curve."""

from __future__ import annotations

import numpy as np

from mechlib.core.rotation import cross

__all__ = ["Curve"]

_SAMPLES_PER_SEGMENT = 40  # coarse search grid for the nearest point
_NEWTON_ITERATIONS = 8  # refinements of the parameter (quadratic convergence)


class Curve:
    """c(u) through `points` (n >= 2, 3; m) by `interpolation` akima | cubic | linear, u the
    chord length from the first point (m); beyond the ends the end polynomial continues."""

    def __init__(self, points, interpolation: str = "cubic"):
        # imported here, where a spline is built: a module that only names Curve (the model
        # checks of `loads validate`) loads no scipy.interpolate
        from scipy.interpolate import Akima1DInterpolator, CubicSpline, make_interp_spline

        pts = np.asarray(points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) < 2:
            raise ValueError("a curve needs at least 2 points [x, y, z]")
        steps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        if np.any(steps <= 0.0):
            raise ValueError("curve points must be distinct in sequence")
        self.u = np.concatenate(([0.0], np.cumsum(steps)))
        if interpolation == "linear" or len(pts) == 2:
            spline = make_interp_spline(self.u, pts, k=1)
        elif interpolation == "akima" and len(pts) >= 3:
            spline = Akima1DInterpolator(self.u, pts, axis=0, extrapolate=True)
        else:
            spline = CubicSpline(
                self.u, pts, axis=0, bc_type="not-a-knot" if len(pts) > 3 else "natural"
            )
        self._c, self._d1 = spline, spline.derivative(1)
        self._d2 = spline.derivative(2)
        self._grid = np.linspace(0.0, self.u[-1], _SAMPLES_PER_SEGMENT * (len(pts) - 1) + 1)
        self._samples = spline(self._grid)
        # the best-fit plane's normal: a reference that the tangent of a (nearly) planar
        # curve never meets, so the normal frame built on it turns without jumps
        _, _, vt = np.linalg.svd(pts - pts.mean(axis=0))
        self.binormal = vt[-1] if len(pts) > 2 else _perpendicular(pts[-1] - pts[0])

    def point(self, u: float) -> np.ndarray:
        return np.asarray(self._c(u), dtype=float)

    def tangent(self, u: float) -> np.ndarray:
        """dc/du (unit length for a chord-length parameter, nearly)."""
        return np.asarray(self._d1(u), dtype=float)

    def curvature_vector(self, u: float) -> np.ndarray:
        """d2c/du2 (1/m)."""
        return np.asarray(self._d2(u), dtype=float)

    def nearest(self, w: np.ndarray, guess: float | None = None) -> float:
        """Parameter u of the curve point nearest w (m): Newton on c'(u).(c(u) - w) = 0 from
        `guess`, or from the nearest sample when there is none."""
        if guess is None:
            guess = float(self._grid[int(np.argmin(np.sum((self._samples - w) ** 2, axis=1)))])
        u = guess
        for _ in range(_NEWTON_ITERATIONS):
            r, t, c = self.point(u) - w, self.tangent(u), self.curvature_vector(u)
            slope = t @ t + r @ c
            if slope <= 0.0:
                return self.nearest(w) if guess is not None and u == guess else u
            step = (r @ t) / slope
            u -= step
            if abs(step) < 1e-14 * max(1.0, self.u[-1]):
                break
        return float(u)

    def normals(self, u: float) -> tuple[np.ndarray, np.ndarray]:
        """Two unit normals (n1 in the curve's best-fit plane, n2 across it) at u."""
        t = self.tangent(u)
        n1 = cross(self.binormal, t)
        n1 /= np.linalg.norm(n1)
        n2 = cross(t, n1)
        return n1, n2 / np.linalg.norm(n2)


def _perpendicular(v: np.ndarray) -> np.ndarray:
    """A unit vector normal to v."""
    trial = np.eye(3)[int(np.argmin(np.abs(v)))]
    n = np.cross(v, trial)
    return n / np.linalg.norm(n)
