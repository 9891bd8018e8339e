"""Joint limit (stop) on a joint coordinate with the IMPACT law (Adams' IMPACT function).

The coordinate q of a revolute, prismatic or cylindrical joint (angle, rad, or travel, m:
body 1 relative to body 2, mechlib.kinematics.coordinates) is stopped at `lower` and/or
`upper`. Penetration x = lower - q below the lower limit, q - upper above the upper one,
its rate xd > 0 while penetrating further. The effort along the coordinate is
E = +F (lower stop) or -F (upper stop), F >= 0 from the law:

- IMPACT: F = k x^e + step(x, s, 0, s + depth, c_max) xd (s = 0, or the penetration at
  which an event switched the limit on: the damping ramps in from the actual state);
- restitution (Flores et al. 2011, as the `restitution` contact):
  F = k x^e (1 + 8 (1 - r) / (5 r) xd / xd(-)), xd(-) the rate when the contact began.

Body 1 of the joint gets E about (along) the joint axis, body 2 the opposite. A travel
limit applies the pair of forces at body 1's joint point, which is exactly the work of the
travel measure (cylindrical joints too). Effect `contact`.
"""

from __future__ import annotations

import math
from bisect import bisect_left
from dataclasses import dataclass, field

import numpy as np

from mechlib.elements.contact.laws import (
    MIN_APPROACH_SPEED,
    impact_force,
    restitution_force,
)
from mechlib.elements.forces import resist_rotation
from mechlib.kinematics.view import StateView

__all__ = ["LIMIT_JOINTS", "JointLimit"]

LIMIT_JOINTS = {
    "revolute": ("angle",),
    "prismatic": ("travel",),
    "cylindrical": ("angle", "travel"),
}
"""Joint types a limit may stop, with their coordinates."""


@dataclass
class JointLimit:
    """Stops of `joint`'s `coordinate` ("angle" or "travel") at `lower` and/or `upper` (rad
    or m; None: no stop on that side). `stiffness` k (N*m/rad^e or N/m^e), `exponent` e,
    `damping` c_max (N*m*s/rad or N*s/m) reached at penetration `depth` (rad or m); or
    `restitution` r in (0, 1] instead of the damping (Flores' hysteresis)."""

    name: str
    joint: str
    coordinate: str
    lower: float | None = None
    upper: float | None = None
    stiffness: float = 0.0
    exponent: float = 1.0
    damping: float = 0.0
    depth: float = 1.0e-4
    restitution: float | None = None
    effect: str = "contact"
    active: bool = True
    # (time, ramp start, approach rate) of every accepted state: outputs are read after the
    # solve and must see what the integrator used for each recorded state
    _history: tuple[list, list, list] = field(default_factory=lambda: ([], [], []), repr=False)
    _start: float = 0.0  # penetration where the damping ramp begins (activation in contact)
    _approach: float = MIN_APPROACH_SPEED  # penetration rate when the current contact began
    _last: tuple[float, float] = (-1.0, 0.0)  # x, xd of the last accepted state

    @property
    def output_units(self) -> dict[str, str]:
        """`value` the effort along the coordinate (positive increases it), `penetration`."""
        angle = self.coordinate == "angle"
        return {"value": "N*m" if angle else "N", "penetration": "rad" if angle else "m"}

    def bind(self, system) -> None:
        self._m = system.measure(self.joint, self.coordinate)
        j = system.mechanism.joints[self.joint]
        self._bi, self._si = system.body_point(j.body1, j.at)

    def state_bodies(self) -> set[int]:
        """The joint's two bodies (mechlib.system.fd_columns)."""
        return {self._m.bi, self._m.bj}

    def penetration(self, view: StateView) -> tuple[float, float, float]:
        """(x, xd, side): the deeper penetration (rad or m, <= 0 apart), its rate, and the
        side's sign (+1 the lower stop pushes q up, -1 the upper pushes it down)."""
        q, qd = self._m.value(view.kin), self._m.rate(view.kin)
        below = self.lower - q if self.lower is not None else -math.inf
        above = q - self.upper if self.upper is not None else -math.inf
        if below >= above:
            return below, -qd, 1.0
        return above, qd, -1.0

    def _force(self, x: float, xd: float, start: float, approach: float) -> float:
        """F (N*m or N, >= 0) of the law."""
        if self.restitution is not None:
            return restitution_force(
                self.restitution, self.stiffness, self.exponent, x, xd, approach
            )
        k, e, c, d = self.stiffness, self.exponent, self.damping, self.depth
        return impact_force(k, e, c, d, x, xd, start)

    def effort(self, view: StateView, at_time: bool = False) -> tuple[float, float]:
        """(E, x): the effort along the coordinate (N*m or N, positive increases it) and the
        penetration (>= 0); `at_time`: with the memory of the accepted state at view.t."""
        x, xd, side = self.penetration(view)
        if x <= 0.0:
            return 0.0, 0.0
        start, approach = self._memory_at(view.t) if at_time else (self._start, self._approach)
        if view.at_rest:
            xd = 0.0
        return side * self._force(x, xd, start, approach), x

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        effort = self.effort(view)[0]
        if effort == 0.0:
            return
        m = self._m
        if self.coordinate == "angle":
            resist_rotation(view, m, -effort, N)
            return
        force = effort * (view.rotation(m.bj) @ m.axis_local)
        point = view.point_position(self._bi, self._si)
        for body, sign in ((m.bi, 1.0), (m.bj, -1.0)):
            F[body] += sign * force
            N[body] += sign * np.cross(point - view.kin.r[body], force)

    def start_from(self, view: StateView) -> None:
        """Switched on by an event at `view`: the damping ramps in from the penetration now,
        and the restitution law's approach rate is the rate now (no step in the damping)."""
        x, xd, _ = self.penetration(view)
        self._start = max(x, 0.0)
        self._approach = max(xd, MIN_APPROACH_SPEED)
        self._last = (x, xd)
        self._record(view.t)

    def commit(self, view: StateView) -> None:
        """Accepted state: the approach rate when a contact begins (interpolated to x = 0
        between the last state apart and the first in contact); the ramp start back to 0
        once apart."""
        x, xd, _ = self.penetration(view)
        x0, xd0 = self._last
        if x <= 0.0:
            self._start, self._approach = 0.0, max(xd, MIN_APPROACH_SPEED)
        elif x0 <= 0.0 and x > x0:
            self._approach = max(xd0 + (xd - xd0) * (-x0) / (x - x0), MIN_APPROACH_SPEED)
        self._last = (x, xd)
        self._record(view.t)

    def _record(self, t: float) -> None:
        times, starts, approaches = self._history
        i = bisect_left(times, t)
        for kept in self._history:
            del kept[i:]  # a restart from an earlier time
        times.append(t)
        starts.append(self._start)
        approaches.append(self._approach)

    def _memory_at(self, t: float) -> tuple[float, float]:
        """(ramp start, approach) the integrator used for a state at time t (s): those
        committed last before t."""
        times, starts, approaches = self._history
        if not times:
            return self._start, self._approach
        i = max(bisect_left(times, t) - 1, 0)
        return starts[i], approaches[i]

    def output(self, view: StateView) -> dict[str, float]:
        effort, x = self.effort(view, at_time=True)
        return {"value": effort, "penetration": x}

    def potential(self, view: StateView) -> float:
        """Elastic energy (J) k x^(e+1) / (e+1) at penetration x."""
        x = self.penetration(view)[0]
        if x <= 0.0:
            return 0.0
        return self.stiffness * x ** (self.exponent + 1.0) / (self.exponent + 1.0)

    def dissipation(self, view: StateView) -> float:
        """Power (W) of the damping part of the law, (F - k x^e) xd."""
        x, xd, _ = self.penetration(view)
        if x <= 0.0 or view.at_rest:
            return 0.0
        start, approach = self._memory_at(view.t)
        return (self._force(x, xd, start, approach) - self.stiffness * x**self.exponent) * xd
