"""A roller circle on body 1 against a planar profile curve of body 2 (a cam, a guide).

The profile is a table of points (global, design position, m) in the plane through them with
normal `plane_normal`; a cubic spline through them, parameterised by chord length, is the
curve. The roller is the circle (centre, radius) in that plane. The contact normal is the
curve's in-plane normal at the point nearest the roller centre, on the side where the roller
centre lies at the design position; penetration = radius - signed distance of the centre.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from mechlib.contact.curve_kernels import nearest_on_cubic
from mechlib.contact.geometry import Gap, relative_velocity, unit
from mechlib.rotation import cross

__all__ = ["CircleProfile"]

_SAMPLES_PER_SEGMENT = 40  # coarse search grid for the nearest point
_NEWTON_ITERATIONS = 6  # refinements of the curve parameter (quadratic convergence)


@dataclass
class CircleProfile:
    """Roller (centre, radius, m) on body 1; profile `points` (n, 3, m) of body 2."""

    center: Sequence[float]
    radius: float
    points: Sequence[Sequence[float]]
    plane_normal: Sequence[float]
    _bound: tuple = field(default=(), repr=False)
    _cubic: tuple = field(default=(), repr=False)  # the spline's breakpoints, coefficients

    def bind(self, system, body1: str, body2: str) -> tuple[int, int]:
        """The bodies' indices; the spline is built on the first gap (`_shape`): a model
        that is only built and checked (`loads validate`) imports no scipy.interpolate."""
        pts = np.asarray(self.points, float)
        if len(pts) < 2:
            raise ValueError("a profile needs at least 2 points")
        b1, s1 = system.body_point(body1, self.center)
        b2, s0 = system.body_point(body2, pts[0])  # body-2 axes = global axes at design
        self._bound = (b1, s1, b2, s0)
        return b1, b2

    def _shape(self) -> None:
        """The spline through the points in their plane, its sample grid and the side of
        the curve the roller centre lies on at the design position (appended to _bound)."""
        from scipy.interpolate import CubicSpline  # here, where the spline is built

        pts = np.asarray(self.points, float)
        m = unit(self.plane_normal)
        origin = pts[0]
        e1 = unit((pts[-1] - origin) - ((pts[-1] - origin) @ m) * m)
        e2 = np.cross(m, e1)
        uv = np.column_stack(((pts - origin) @ e1, (pts - origin) @ e2))
        chord = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(uv, axis=0), axis=1))))
        spline = CubicSpline(chord, uv, bc_type="natural" if len(pts) > 2 else "not-a-knot")
        self._cubic = (np.ascontiguousarray(spline.x), np.ascontiguousarray(spline.c))
        grid = np.linspace(0.0, chord[-1], _SAMPLES_PER_SEGMENT * (len(pts) - 1) + 1)
        shape = (np.column_stack((e1, e2)), m, spline, grid, spline(grid))
        self._bound = self._bound[:4] + shape + (1.0,)
        side = self._signed(np.asarray(self.center, float) - origin)[0]
        self._bound = self._bound[:-1] + (1.0 if side >= 0.0 else -1.0,)

    def _nearest(self, w: np.ndarray) -> tuple[float, np.ndarray]:
        """(curve parameter (m of chord) of the point nearest the in-plane point w (2,),
        (3, 2) the curve point, tangent and second derivative there)."""
        grid, samples = self._bound[7], self._bound[8]
        out = np.empty((3, 2))
        breaks, coefs = self._cubic
        u = nearest_on_cubic(w, grid, samples, breaks, coefs, _NEWTON_ITERATIONS, out)
        return u, out

    def _signed(self, local: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """Signed distance (m) of a point (relative to the profile origin, body-2 axes) from
        the curve, the in-plane unit normal and the nearest curve point (body-2 axes)."""
        basis, m = self._bound[4], self._bound[5]
        w = basis.T @ local
        _, curve = self._nearest(w)
        tangent = basis @ curve[1]
        normal = unit(cross(m, tangent)) * (self._bound[9] if len(self._bound) > 9 else 1.0)
        foot = basis @ curve[0]
        return float((local - foot) @ normal), normal, foot

    def gap(self, view) -> Gap:
        if len(self._bound) == 4:
            self._shape()
        b1, s1, b2, s0 = self._bound[:4]
        rot2 = view.rotation(b2)
        origin = view.point_position(b2, s0)
        c = view.point_position(b1, s1)
        d, n_local, foot = self._signed(rot2.T @ (c - origin))
        n = rot2 @ n_local
        point = origin + rot2 @ foot + 0.5 * (d - self.radius) * n
        return Gap(self.radius - d, n, point, relative_velocity(view, b1, b2, point))
