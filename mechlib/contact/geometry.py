"""Contact geometry of primitive pairs: penetration, normal, contact point, relative velocity.

Every geometry is given in global coordinates at the design position and bound once to a
`System` (body indices, body-fixed vectors). `gap(view)` returns a `Gap` for the current
state: `penetration` (m, > 0 in contact, the negative gap otherwise), the unit `normal` (global,
from body 2 towards body 1: the normal force on body 1 is +F_N * normal), the contact `point`
(global, m, midway between the two surfaces) and `velocity`, the velocity of body 1's material
point there minus body 2's (m/s). Conventions follow SPEC 1.2.1: body 1 carries the sphere,
ball, pin or roller; body 2 the plane, socket, hole or profile.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

__all__ = ["Gap", "SpherePlane", "SphereInSphere", "CylinderInCylinder", "material_velocity",
           "unit", "radial"]

_TINY = 1.0e-15  # m, below this the eccentricity has no direction (the force is zero there)


@dataclass(frozen=True)
class Gap:
    """Penetration (m), normal (3,), contact point (3,) and relative velocity (3,), global."""

    penetration: float
    normal: np.ndarray
    point: np.ndarray
    velocity: np.ndarray
    eccentricity: np.ndarray | None = None  # clearance geometries: centre 1 - centre 2 (m)

    @property
    def rate(self) -> float:
        """Penetration rate (m/s), positive while the bodies approach."""
        return -float(self.velocity @ self.normal)

    @property
    def sliding(self) -> np.ndarray:
        """Tangential relative velocity (m/s, global) of body 1 on body 2."""
        return self.velocity + self.rate * self.normal


def unit(v: Sequence[float]) -> np.ndarray:
    """v / |v| (raises on a zero vector: a direction is required)."""
    v = np.asarray(v, float)
    n = float(np.linalg.norm(v))
    if n == 0.0:
        raise ValueError("a direction must not be the zero vector")
    return v / n


def radial(e: np.ndarray) -> tuple[float, np.ndarray]:
    """Length (m) and direction of an eccentricity; +x when it has none (no force then)."""
    length = float(np.linalg.norm(e))
    if length < _TINY:
        return length, np.array([1.0, 0.0, 0.0])
    return length, e / length


def material_velocity(view, body: int, point: np.ndarray) -> np.ndarray:
    """Velocity (m/s, global) of the material point of `body` now at `point` (global, m)."""
    s = view.rotation(body).T @ (point - view.kin.r[body])
    return view.point_velocity(body, s)


def relative_velocity(view, b1: int, b2: int, point: np.ndarray) -> np.ndarray:
    """Velocity of body 1's material point at `point` minus body 2's (m/s)."""
    return material_velocity(view, b1, point) - material_velocity(view, b2, point)


@dataclass
class SpherePlane:
    """Sphere (centre, radius, m) on body 1 against a plane (point, normal) of body 2.

    `extent` (m), when given, bounds the plane to a disc of that radius about
    `plane_point` (a stop pad): a sphere whose centre lies outside it touches nothing.
    """

    center: Sequence[float]
    radius: float
    plane_point: Sequence[float]
    normal: Sequence[float]
    extent: float | None = None
    _bound: tuple = field(default=(), repr=False)

    def bind(self, system, body1: str, body2: str) -> tuple[int, int]:
        b1, sc = system.body_point(body1, self.center)
        b2, sp = system.body_point(body2, self.plane_point)
        # body axes coincide with the global axes at design: the normal is body-fixed as given
        self._bound = (b1, sc, b2, sp, unit(self.normal))
        return b1, b2

    def gap(self, view) -> Gap:
        b1, sc, b2, sp, n_local = self._bound
        n = view.rotation(b2) @ n_local
        c = view.point_position(b1, sc)
        offset = c - view.point_position(b2, sp)
        d = float(offset @ n)   # centre height over the plane
        point = c - 0.5 * (self.radius + d) * n
        if self.extent is not None:
            across = offset - d * n
            if float(across @ across) > self.extent ** 2:
                d = max(d, self.radius)  # off the pad: no penetration
        return Gap(self.radius - d, n, point, relative_velocity(view, b1, b2, point))


@dataclass
class SphereInSphere:
    """Ball (radius, m) on body 1 in a socket of radius + clearance on body 2; the centres
    coincide at the design position. Penetration = |eccentricity| - clearance."""

    center: Sequence[float]
    radius: float
    clearance: float
    _bound: tuple = field(default=(), repr=False)

    def bind(self, system, body1: str, body2: str) -> tuple[int, int]:
        self._bound = (*system.body_point(body1, self.center),
                       *system.body_point(body2, self.center))
        return self._bound[0], self._bound[2]

    def centres(self, view) -> tuple[np.ndarray, np.ndarray]:
        b1, s1, b2, s2 = self._bound
        return view.point_position(b1, s1), view.point_position(b2, s2)

    def gap(self, view) -> Gap:
        b1, _, b2, _ = self._bound
        c1, c2 = self.centres(view)
        e = c1 - c2
        length, u = radial(e)
        # ball surface c1 + R u, socket wall c2 + (R + clearance) u: the midpoint
        point = 0.5 * (c1 + c2) + (self.radius + 0.5 * self.clearance) * u
        return Gap(length - self.clearance, -u, point, relative_velocity(view, b1, b2, point),
                   e)


@dataclass
class CylinderInCylinder:
    """Pin (radius, m) on body 1 in a hole of radius + clearance on body 2, common axis at
    design. The eccentricity is measured normal to the hole's axis (body 2) at the pin's
    centre; a tilt of the pin within the hole is not modelled (its joints carry it)."""

    center: Sequence[float]
    axis: Sequence[float]
    radius: float
    clearance: float
    _bound: tuple = field(default=(), repr=False)

    def bind(self, system, body1: str, body2: str) -> tuple[int, int]:
        b1, s1 = system.body_point(body1, self.center)
        b2, s2 = system.body_point(body2, self.center)
        self._bound = (b1, s1, b2, s2, unit(self.axis))   # body 2 axes = global at design
        return b1, b2

    def axis_now(self, view) -> np.ndarray:
        """Hole axis (unit, global) in the current state."""
        return view.rotation(self._bound[2]) @ self._bound[4]

    def gap(self, view) -> Gap:
        b1, s1, b2, s2, _ = self._bound
        a = self.axis_now(view)
        c1 = view.point_position(b1, s1)
        e = c1 - view.point_position(b2, s2)
        e = e - (e @ a) * a
        length, u = radial(e)
        point = c1 - 0.5 * e + (self.radius + 0.5 * self.clearance) * u
        return Gap(length - self.clearance, -u, point, relative_velocity(view, b1, b2, point),
                   e)

