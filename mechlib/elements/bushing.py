"""Bushing: a 6-DOF linear spring-damper between two bodies (SPEC 1.2.1 `bushing`).

Frames: at point `at`, with the global axes at design, one fixed in body 1 (I) and one in
body 2 (J). In J axes: d = A2^T (p_I - p_J) the translation (m), theta the rotation vector
(rad: axis times angle) of A2^T A1, their rates d' (as seen from J) and omega = A2^T (w1 - w2).
Force on body 1, J axes: -(K d + C d'); torque on body 1: -(Kr theta + Cr omega); body 2 gets
the opposite at the same point. Linear in theta: meant for the small rotations of a
compliant mount (as a linear Adams bushing); the rotation vector keeps it well defined at
larger ones.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from mechlib.rotation import cross, omega_global
from mechlib.view import StateView

__all__ = ["Bushing", "rotation_vector"]


def rotation_vector(rot: np.ndarray) -> np.ndarray:
    """Axis times angle (rad, angle in [0, pi)) of the rotation matrix `rot`."""
    s = 0.5 * np.array([rot[2, 1] - rot[1, 2], rot[0, 2] - rot[2, 0], rot[1, 0] - rot[0, 1]])
    sin = float(np.linalg.norm(s))
    cos = 0.5 * (float(np.trace(rot)) - 1.0)
    if sin < 1e-12:
        return s  # no rotation (or a half turn, beyond any bushing)
    return math.atan2(sin, cos) / sin * s


@dataclass
class Bushing:
    """6-DOF bushing between `bodies` (1, 2) at point `at` (m): stiffness [kx, ky, kz] (N/m),
    torsional_stiffness (N*m/rad), damping (N*s/m), torsional_damping (N*m*s/rad), all about
    the global axes at design, which turn with body 2."""

    name: str
    bodies: tuple[str, str]
    at: Sequence[float]
    stiffness: Sequence[float] = (0.0, 0.0, 0.0)
    torsional_stiffness: Sequence[float] = (0.0, 0.0, 0.0)
    damping: Sequence[float] = (0.0, 0.0, 0.0)
    torsional_damping: Sequence[float] = (0.0, 0.0, 0.0)
    effect: str = "springs"
    active: bool = True
    output_units: ClassVar[dict[str, str]] = {
        "fx": "N",
        "fy": "N",
        "fz": "N",
        "tx": "N*m",
        "ty": "N*m",
        "tz": "N*m",
        "dx": "m",
        "dy": "m",
        "dz": "m",
        "rx": "rad",
        "ry": "rad",
        "rz": "rad",
    }
    _ends: tuple = field(default=(), repr=False)

    def bind(self, system) -> None:
        self._ends = (
            *system.body_point(self.bodies[0], self.at),
            *system.body_point(self.bodies[1], self.at),
        )

    def _state(self, view: StateView):
        """(force, torque on body 1 in global axes, d, theta in J axes, point of body 1)."""
        b1, s1, b2, s2 = self._ends
        kin = view.kin
        a1, a2 = view.rotation(b1), view.rotation(b2)
        p1, p2 = view.point_position(b1, s1), view.point_position(b2, s2)
        w1, w2 = (omega_global(kin.x[b, 3:], kin.xd[b, 3:]) for b in (b1, b2))
        d = a2.T @ (p1 - p2)
        d_rate = a2.T @ (
            view.point_velocity(b1, s1) - view.point_velocity(b2, s2) - cross(w2, p1 - p2)
        )
        theta = rotation_vector(a2.T @ a1)
        omega = a2.T @ (w1 - w2)
        force = -(np.multiply(self.stiffness, d) + np.multiply(self.damping, d_rate))
        torque = -(
            np.multiply(self.torsional_stiffness, theta)
            + np.multiply(self.torsional_damping, omega)
        )
        return a2 @ force, a2 @ torque, d, theta, p1

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        force, torque, _, _, p1 = self._state(view)
        for body, sign in ((self._ends[0], 1.0), (self._ends[2], -1.0)):
            F[body] += sign * force
            N[body] += sign * (torque + cross(p1 - view.kin.r[body], force))

    def output(self, view: StateView) -> dict[str, float]:
        """fx..tz: the force and torque on body 1 (global axes, N and N*m); dx..dz, rx..rz:
        the translation (m) and rotation vector (rad) of body 1's frame in body 2's."""
        force, torque, d, theta, _ = self._state(view)
        values = dict(zip(("fx", "fy", "fz", "tx", "ty", "tz"), (*force, *torque)))
        values.update(zip(("dx", "dy", "dz", "rx", "ry", "rz"), (*d, *theta)))
        return {k: float(v) for k, v in values.items()}
