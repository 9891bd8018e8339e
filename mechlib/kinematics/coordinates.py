"""Joint coordinates (angle of a revolute, travel of a prismatic) and equations on them.

The angle of body 1 relative to body 2 about the joint axis h (right-hand rule) is
theta = atan2(S, C) with S = f1.g2, C = f1.f2 (f, g the joint triad at design, so theta = 0
there); it is unwrapped against a reference committed at every accepted state, so it runs
continuously past +-pi. The travel is the distance of body 1's joint point from body 2's along
h. `CoordinateEquation` holds sum(c_k theta_k) - f(t) = 0: motions (drivers), couplers,
gears and the screw's travel/angle relation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechlib.kinematics.constraints import Dot1, Dot2
from mechlib.kinematics.kin import Kin
from mechlib.model.mechanism import TimeFunction

__all__ = [
    "AngleMeasure",
    "CoordinateEquation",
    "TravelMeasure",
    "angle_gradient",
    "angle_quad",
]

TWO_PI = 2.0 * math.pi


class AngleMeasure:
    """Relative rotation angle (rad) of body i about the axis h fixed in body j."""

    kind = "angle"

    def __init__(self, bi: int, bj: int, f: np.ndarray, g: np.ndarray, h: np.ndarray):
        self.sine_cosine = Dot1([bi, bi], [bj, bj], [f, f], [g, f])
        self.bi, self.bj, self.axis_local = bi, bj, np.asarray(h, float)
        self.f, self.g = np.asarray(f, float), np.asarray(g, float)  # kernels.angle_state
        self.reference = 0.0

    def value(self, k: Kin) -> float:
        s, c = self.sine_cosine.phi(k)
        raw = math.atan2(s, c)
        return raw + TWO_PI * round((self.reference - raw) / TWO_PI)

    def commit(self, k: Kin) -> None:
        """Accept the current state as the unwrapping reference."""
        self.reference = self.value(k)

    def gradient(self, k: Kin) -> np.ndarray:
        """d(theta)/dq, shape (7 (nb+1),)."""
        s, c = self.sine_cosine.phi(k)
        rows = np.zeros((2, k.ncol))
        self.sine_cosine.jacobian(k, rows)
        return angle_gradient(s, c, rows[0], rows[1])

    def rate(self, k: Kin) -> float:
        s, c = self.sine_cosine.phi(k)
        sd, cd = self.sine_cosine.rate(k)
        return (c * sd - s * cd) / (s * s + c * c)

    def quad(self, k: Kin) -> float:
        """Part of d2(theta)/dt2 not multiplying qdd."""
        s, c = self.sine_cosine.phi(k)
        sd, cd = self.sine_cosine.rate(k)
        sq, cq = -self.sine_cosine.gamma(k)
        return angle_quad(s, c, sd, cd, sq, cq)


def angle_gradient(s, c, s_rows, c_rows):
    """d(theta)/dq of theta = atan2(S, C) from S, C and their gradient rows (scalars and
    rows, or arrays of them broadcast: mechlib.kinematics.coordinate_block)."""
    return (c * s_rows - s * c_rows) / (s * s + c * c)


def angle_quad(s, c, sd, cd, sq, cq):
    """The part of d2(theta)/dt2 not multiplying qdd (rad/s^2) from S, C, their rates and
    the parts of their second derivatives not multiplying qdd (scalars or arrays)."""
    r2 = s * s + c * c
    rate = (c * sd - s * cd) / r2
    return (c * sq - s * cq) / r2 - 2.0 * rate * (s * sd + c * cd) / r2


class TravelMeasure:
    """Travel (m) of body i's joint point along the axis h fixed in body j."""

    kind = "travel"

    def __init__(self, bi: int, bj: int, h: np.ndarray, si: np.ndarray, sj: np.ndarray):
        self.distance = Dot2([bi], [bj], [h], [si], [sj])
        self.bi, self.bj, self.axis_local = bi, bj, np.asarray(h, float)

    def value(self, k: Kin) -> float:
        return float(self.distance.phi(k)[0])

    def commit(self, k: Kin) -> None:
        """Travel needs no unwrapping reference."""

    def gradient(self, k: Kin) -> np.ndarray:
        rows = np.zeros((1, k.ncol))
        self.distance.jacobian(k, rows)
        return rows[0]

    def rate(self, k: Kin) -> float:
        return float(self.distance.rate(k)[0])

    def quad(self, k: Kin) -> float:
        return float(-self.distance.gamma(k)[0])


@dataclass
class CoordinateEquation:
    """sum(coef_k * measure_k(q)) - function(t) = 0, one labelled row owned by `owner`."""

    terms: list[tuple[float, AngleMeasure | TravelMeasure]]
    label: str
    owner: str
    function: TimeFunction | None = None

    def phi(self, k: Kin) -> float:
        value = sum(c * m.value(k) for c, m in self.terms)
        return value - (self.function.value(k.t) if self.function else 0.0)

    def gradient(self, k: Kin) -> np.ndarray:
        return sum((c * m.gradient(k) for c, m in self.terms), np.zeros(k.ncol))

    def nu(self, t: float) -> float:
        """Right side of the velocity equation, -d(phi)/dt."""
        return self.function.rate(t) if self.function else 0.0

    def gamma(self, k: Kin) -> float:
        extra = self.function.accel(k.t) if self.function else 0.0
        return extra - sum(c * m.quad(k) for c, m in self.terms)
