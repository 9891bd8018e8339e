"""Contact geometry of primitive pairs: penetration, normal, contact point, relative velocity.

Every geometry is given in global coordinates at the design position and bound once to a
`System` (body indices, body-fixed vectors). `gap(view)` returns a `Gap` for the current
state: `penetration` (m, > 0 in contact, the negative gap otherwise), the unit `normal` (global,
from body 2 towards body 1: the normal force on body 1 is +F_N * normal), the contact `point`
(global, m, midway between the two surfaces) and `velocity`, the velocity of body 1's material
point there minus body 2's (m/s). Conventions follow SPEC 1.2.1: body 1 carries the sphere,
ball, pin or roller; body 2 the plane, socket, hole or profile. The primitives compute
their gap in compiled code (mechlib.elements.contact.kernels.gap); `kernel()` gives the geometry's
code and parameters for it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from mechlib.elements.contact import kernels

__all__ = [
    "CylinderInCylinder",
    "Gap",
    "SphereInSphere",
    "SpherePlane",
    "material_velocity",
    "relative_velocity",
    "unit",
]


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


def unit(v: ArrayLike) -> np.ndarray:
    """v / |v| (raises on a zero vector: a direction is required)."""
    vector = np.asarray(v, float)
    n = float(np.linalg.norm(vector))
    if n == 0.0:
        raise ValueError("a direction must not be the zero vector")
    return vector / n


def material_velocity(view, body: int, point: np.ndarray) -> np.ndarray:
    """Velocity (m/s, global) of the material point of `body` now at `point` (global, m)."""
    s = view.rotation(body).T @ (point - view.kin.r[body])
    return view.point_velocity(body, s)


def relative_velocity(view, b1: int, b2: int, point: np.ndarray) -> np.ndarray:
    """Velocity of body 1's material point at `point` minus body 2's (m/s)."""
    return material_velocity(view, b1, point) - material_velocity(view, b2, point)


class _Compiled:
    """A primitive whose gap the compiled kernel computes: `_bound` = (b1, b2, kind, g)."""

    _bound: tuple
    eccentric = True

    def kernel(self) -> tuple[int, int, int, np.ndarray]:
        """(body 1, body 2, geometry code, parameters) for mechlib.elements.contact.kernels."""
        return self._bound

    compiled = kernel  # as CircleProfile.compiled: the gap and wrench kernels' arguments

    def gap(self, view) -> Gap:
        b1, b2, kind, g = self._bound
        out = np.empty(kernels.GAP_SIZE)
        kernels.gap(kind, view.kin.x, view.kin.xd, b1, b2, g, out)
        return Gap(
            float(out[0]), out[1:4], out[4:7], out[7:10], out[10:13] if self.eccentric else None
        )


def _parameters(s1, s2, direction, radius: float, extra: float) -> np.ndarray:
    return np.concatenate([s1, s2, direction, [radius, extra]]).astype(float)


def _bind_clearance(
    joint, system, body1: str, body2: str, kind: int, axis: np.ndarray
) -> tuple[int, int]:
    """A clearance joint's compiled data: body 1's point at its centre (the design centre
    plus the joint's `offset`, if any), body 2's at the design centre, the axis (zeros for a
    ball), radius and clearance; returns the two body indices."""
    offset = np.asarray(getattr(joint, "offset", (0.0, 0.0, 0.0)), float)
    b1, s1 = system.body_point(body1, np.asarray(joint.center, float) + offset)
    b2, s2 = system.body_point(body2, joint.center)
    joint._bound = (b1, b2, kind, _parameters(s1, s2, axis, joint.radius, joint.clearance))
    return b1, b2


@dataclass
class SpherePlane(_Compiled):
    """Sphere (centre, radius, m) on body 1 against a plane (point, normal) of body 2.

    `extent` (m), when given, bounds the plane to a disc of that radius about
    `plane_point` (a stop pad): a sphere whose centre lies outside it touches nothing.
    Penetration = radius - height of the centre over the plane; contact point midway in
    the overlap along the normal.
    """

    center: Sequence[float]
    radius: float
    plane_point: Sequence[float]
    normal: Sequence[float]
    extent: float | None = None
    _bound: tuple = field(default=(), repr=False)
    eccentric = False

    def bind(self, system, body1: str, body2: str) -> tuple[int, int]:
        b1, sc = system.body_point(body1, self.center)
        b2, sp = system.body_point(body2, self.plane_point)
        # body axes coincide with the global axes at design: the normal is body-fixed as given
        extent = -1.0 if self.extent is None else float(self.extent)
        self._bound = (
            b1,
            b2,
            kernels.SPHERE_PLANE,
            _parameters(sc, sp, unit(self.normal), self.radius, extent),
        )
        return b1, b2


@dataclass
class SphereInSphere(_Compiled):
    """Ball (radius, m) on body 1 in a socket of radius + clearance on body 2, the socket
    centred on `center` at the design position and the ball on `center` + `offset` (m,
    global: an assembly error, the eccentricity at design; zero by default). Penetration =
    |eccentricity| - clearance; the contact point midway between the ball surface and the
    socket wall along the eccentricity."""

    center: Sequence[float]
    radius: float
    clearance: float
    offset: Sequence[float] = (0.0, 0.0, 0.0)
    _bound: tuple = field(default=(), repr=False)

    def bind(self, system, body1: str, body2: str) -> tuple[int, int]:
        return _bind_clearance(self, system, body1, body2, kernels.SPHERE_IN_SPHERE, np.zeros(3))


@dataclass
class CylinderInCylinder(_Compiled):
    """Pin (radius, m) on body 1 in a hole of radius + clearance on body 2, common axis at
    design. The eccentricity is measured normal to the hole's axis (body 2) at the pin's
    centre; a tilt of the pin within the hole is not modelled (its joints carry it)."""

    center: Sequence[float]
    axis: Sequence[float]
    radius: float
    clearance: float
    _bound: tuple = field(default=(), repr=False)

    def bind(self, system, body1: str, body2: str) -> tuple[int, int]:
        # body 2 axes = global at design
        return _bind_clearance(
            self, system, body1, body2, kernels.CYLINDER_IN_CYLINDER, unit(self.axis)
        )

    def axis_now(self, view) -> np.ndarray:
        """Hole axis (unit, global) in the current state."""
        b2, g = self._bound[1], self._bound[3]
        return view.rotation(b2) @ g[6:9]
