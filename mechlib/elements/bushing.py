"""Bushing: a 6-DOF linear spring-damper between two bodies (SPEC 1.2.1 `bushing`).

Frames: at point `at`, with the global axes at design, one fixed in body 1 (I) and one in
body 2 (J). In J axes: d = A2^T (p_I - p_J) the translation (m), theta the rotation vector
(rad: axis times angle) of A2^T A1, their rates d' (as seen from J) and omega = A2^T (w1 - w2).
Force on body 1, J axes: -(K d + C d'); torque on body 1: -(Kr theta + Cr omega); body 2 gets
the opposite at the same point. Linear in theta: meant for the small rotations of a
compliant mount (as a linear Adams bushing); the rotation vector keeps it well defined at
larger ones.

Energy (the energy request, mechlib.outputs.energy): `potential` V = 1/2 d.K d + 1/2 theta.Kr theta,
`dissipation` d'.C d' + omega.Cr omega (W). The force's power is exactly -d/dt(1/2 d.K d)
- d'.C d'. The torque's is -theta.Kr J(theta) theta' (J the rotation vector's Jacobian,
omega = J theta'), and J^T theta = theta: exact for an isotropic Kr or a rotation about one
axis of Kr, otherwise exact to second order in rotation (the torque of an anisotropic Kr is
not conservative at finite 3-D rotations; its energy error is third order in theta).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from mechlib.core.rotation import cross
from mechlib.elements.bushing_kernel import STATE_SIZE, bushing_state
from mechlib.kinematics.view import StateView

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
    _gains: tuple = field(default=(), repr=False)

    def bind(self, system) -> None:
        b1, s1 = system.body_point(self.bodies[0], self.at)
        b2, s2 = system.body_point(self.bodies[1], self.at)
        self._ends = (b1, np.asarray(s1, float), b2, np.asarray(s2, float))
        self._gains = tuple(
            np.asarray(v, float)
            for v in (
                self.stiffness,
                self.damping,
                self.torsional_stiffness,
                self.torsional_damping,
            )
        )

    def state_bodies(self) -> set[int]:
        """The two bodies, whose relative pose and rates set the loads
        (mechlib.system.fd_columns)."""
        return {self._ends[0], self._ends[2]}

    def _state(self, view: StateView):
        """(force, torque on body 1 in global axes, d, theta in J axes, point of body 1,
        d', omega in J axes), from the compiled kernel (mechlib.elements.bushing_kernel)."""
        b1, s1, b2, s2 = self._ends
        k, c, kr, cr = self._gains
        out = np.empty(STATE_SIZE)
        bushing_state(view.kin.x, view.kin.xd, b1, s1, b2, s2, k, c, kr, cr, out)
        return out[0:3], out[3:6], out[6:9], out[9:12], out[12:15], out[15:18], out[18:21]

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        force, torque, _, _, p1, _, _ = self._state(view)
        for body, sign in ((self._ends[0], 1.0), (self._ends[2], -1.0)):
            F[body] += sign * force
            N[body] += sign * (torque + cross(p1 - view.kin.r[body], force))

    def output(self, view: StateView) -> dict[str, float]:
        """fx..tz: the force and torque on body 1 (global axes, N and N*m); dx..dz, rx..rz:
        the translation (m) and rotation vector (rad) of body 1's frame in body 2's."""
        force, torque, d, theta, *_ = self._state(view)
        values = dict(zip(("fx", "fy", "fz", "tx", "ty", "tz"), (*force, *torque)))
        values.update(zip(("dx", "dy", "dz", "rx", "ry", "rz"), (*d, *theta)))
        return {k: float(v) for k, v in values.items()}

    def potential(self, view: StateView) -> float:
        """Elastic energy (J): 1/2 d.K d + 1/2 theta.Kr theta."""
        _, _, d, theta, *_ = self._state(view)
        k, _, kr, _ = self._gains
        return 0.5 * float(d @ (k * d) + theta @ (kr * theta))

    def dissipation(self, view: StateView) -> float:
        """Power (W) of the dampers: d'.C d' + omega.Cr omega."""
        *_, d_rate, omega = self._state(view)
        _, c, _, cr = self._gains
        return float(d_rate @ (c * d_rate) + omega @ (cr * omega))
