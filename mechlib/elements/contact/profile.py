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

from mechlib.elements.contact import kernels
from mechlib.elements.contact.geometry import Gap, unit

__all__ = ["CircleProfile"]

_SAMPLES_PER_SEGMENT = 40  # coarse search grid for the nearest point


@dataclass
class CircleProfile:
    """Roller (centre, radius, m) on body 1; profile `points` (n, 3, m) of body 2. The gap
    is compiled (mechlib.elements.contact.kernels, CIRCLE_PROFILE); `compiled()` gives its
    parameters once the spline is built."""

    center: Sequence[float]
    radius: float
    points: Sequence[Sequence[float]]
    plane_normal: Sequence[float]
    _bound: tuple = field(default=(), repr=False)  # (b1, b2, s1, s0) once bound
    _compiled: tuple | None = field(default=None, repr=False)  # (b1, b2, kind, g)

    def bind(self, system, body1: str, body2: str) -> tuple[int, int]:
        """The bodies' indices; the spline is built on the first gap (`compiled`): a model
        that is only built and checked (`loads validate`) imports no scipy.interpolate."""
        pts = np.asarray(self.points, float)
        if len(pts) < 2:
            raise ValueError("a profile needs at least 2 points")
        b1, s1 = system.body_point(body1, self.center)
        b2, s0 = system.body_point(body2, pts[0])  # body-2 axes = global axes at design
        self._bound, self._compiled = (b1, b2, s1, s0), None
        return b1, b2

    def compiled(self) -> tuple[int, int, int, np.ndarray]:
        """(body 1, body 2, kernels.CIRCLE_PROFILE, parameters) for the compiled gap and
        wrench, the spline built on the first call."""
        if self._compiled is None:
            self._compiled = self._shape(*self._bound)
        return self._compiled

    def _shape(self, b1: int, b2: int, s1: np.ndarray, s0: np.ndarray) -> tuple:
        """The spline through the points in their plane (chord-length parameter), its
        sample grid, and the side of the curve the roller centre lies on at the design
        position, packed as the kernel's parameters (kernels._profile_gap)."""
        from scipy.interpolate import CubicSpline  # here, where the spline is built

        pts = np.asarray(self.points, float)
        m = unit(self.plane_normal)
        origin = pts[0]
        e1 = unit((pts[-1] - origin) - ((pts[-1] - origin) @ m) * m)
        e2 = np.cross(m, e1)
        uv = np.column_stack(((pts - origin) @ e1, (pts - origin) @ e2))
        chord = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(uv, axis=0), axis=1))))
        spline = CubicSpline(chord, uv, bc_type="natural" if len(pts) > 2 else "not-a-knot")
        grid = np.linspace(0.0, chord[-1], _SAMPLES_PER_SEGMENT * (len(pts) - 1) + 1)
        head = [*s1, *s0, *m, self.radius, 1.0, *np.column_stack((e1, e2)).ravel()]
        g = np.concatenate(
            [
                head,
                [grid.size, spline.x.size],
                grid,
                spline(grid).ravel(),
                spline.x,
                np.asarray(spline.c, float).ravel(),
            ]
        )
        assert len(head) + 2 == kernels.PROFILE_HEAD
        # the design position: body 2 unrotated, the roller centre where it was given
        x = np.zeros((1, 7))
        x[0, 3] = 1.0
        out, point = np.empty(kernels.GAP_SIZE), np.empty(3)
        e = np.asarray(self.center, float) - origin
        side = g.copy()
        side[9] = 0.0  # a roller of no radius: its "penetration" is -d exactly
        kernels._profile_gap(x, 0, side, e, np.zeros(3), point, out)
        g[10] = 1.0 if out[0] <= 0.0 else -1.0  # the centre's side at design: d >= 0
        return b1, b2, kernels.CIRCLE_PROFILE, g

    def gap(self, view) -> Gap:
        b1, b2, kind, g = self.compiled()
        out = np.empty(kernels.GAP_SIZE)
        kernels.gap(kind, view.kin.x, view.kin.xd, b1, b2, g, out)
        return Gap(float(out[0]), out[1:4], out[4:7], out[7:10])
