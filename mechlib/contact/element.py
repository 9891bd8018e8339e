"""The contact force element: a geometry, a normal-force law and an optional friction law.

Force on body 1 at the contact point: F_N * normal + friction, with
friction = -mu(|v_t|) * F_N * v_t / |v_t| (v_t the tangential relative velocity); body 2
gets the opposite force at the same point. The element remembers (`commit`, on accepted
states) the approach speed at the start of each contact, which the hysteresis damping of
`hertz` and `restitution` divide by. The gap, the force and the wrench are compiled
(mechlib.contact.kernels); so is the tangent of the primitive geometries, while a profile
contact's is the integrator's difference of its compiled wrench.

Energy (the energy request, mechlib.energy): `potential` is the integral of the law's
elastic part k x^n over the penetration, `dissipation` the power of the rest of the normal
force, (F_N - k x^n) times the penetration rate, plus the friction's, mu F_N |v_t|: the
contact's power is exactly -dV/dt - D, since the penetration rate of every geometry is the
time derivative of its penetration. Not conservative: a sphere leaving a bounded plane
(`extent`) while pressed in drops its energy with the force.
"""

from __future__ import annotations

from bisect import bisect_left
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechlib.contact import kernels
from mechlib.contact.friction import NO_FRICTION
from mechlib.contact.geometry import Gap
from mechlib.elements.regularize import StaticSlipAnchor, at_rest, coulomb_vector
from mechlib.rotation import cross
from mechlib.view import StateView

__all__ = ["Contact", "ContactForces"]

_CONTACT_UNITS = {
    "normal": "N",
    "friction": "N",
    "fx": "N",
    "fy": "N",
    "fz": "N",
    "penetration": "m",
    "px": "m",
    "py": "m",
    "pz": "m",
    "sliding_speed": "m/s",
    "wear": "W",
}
_Laws = tuple[int, np.ndarray, int, np.ndarray]  # law, its parameters, friction, its parameters
_Kernel = tuple[int, int, int, np.ndarray, int, np.ndarray, int, np.ndarray]


@dataclass(frozen=True)
class ContactForces:
    """Normal force (N, >= 0), friction force magnitude (N), force on body 1 (N, global),
    tangential sliding speed (m/s) and the gap they come from."""

    normal: float
    friction: float
    force: np.ndarray
    sliding_speed: float
    gap: Gap


@dataclass
class Contact(StaticSlipAnchor):
    """Contact between `bodies` (body 1 carries the sphere/ball/pin/roller) with `geometry`
    (mechlib.contact.geometry / profile), `law` (mechlib.contact.laws) and optional
    `friction` (mechlib.contact.friction)."""

    name: str
    bodies: tuple[str, str]
    geometry: Any
    law: Any
    friction: Any = None
    effect: str = "contact"
    active: bool = True
    output_units = _CONTACT_UNITS
    approach: float = 0.0  # m/s, penetration rate when the current contact began
    _memory: tuple = field(default=(False, 0.0, 0.0), repr=False)  # in contact, x, xd
    # (time, approach) at every accepted state: outputs are read after the solve, and a
    # recorded state must see the approach speed the integrator used for it
    _history: tuple[list, list] = field(default_factory=lambda: ([], []), repr=False)
    # poses (r, R) of bodies 1 and 2 at the last accepted state: the slip of a static
    # (quasi-static) evaluation is measured from there
    _anchor: tuple | None = field(default=None, repr=False)
    _packed: tuple | None = field(default=None, repr=False)  # (anchor, _packed_anchor())
    slip_threshold: float = 1.0e-6  # m: static slip of full friction

    def bind(self, system) -> None:
        self._b1, self._b2 = self.geometry.bind(system, *self.bodies)
        law = self.law.kernel()
        friction = (NO_FRICTION, np.zeros(5)) if self.friction is None else self.friction.kernel()
        self._laws: _Laws = (*law, *friction)
        self._nb = system.nb
        # the primitives: (kind, b1, b2, g, law, law parameters, friction, its parameters)
        self._kernel: _Kernel | None = None
        self._profile_kernel: _Kernel | None = None
        if hasattr(self.geometry, "kernel"):
            b1, b2, kind, g = self.geometry.kernel()
            self._kernel = (kind, b1, b2, g, *self._laws)

    @property
    def has_tangent(self) -> bool:
        """True when `tangent` gives the stiffness and damping (compiled primitives)."""
        return self._kernel is not None

    def forces(self, view: StateView, approach: float | None = None) -> ContactForces:
        """The contact's forces in state `view` (`approach`: m/s, default the current one)."""
        gap = self.geometry.gap(view)
        approach = self.approach if approach is None else approach
        out = np.empty(6)
        packed = np.concatenate([[gap.penetration], gap.normal, gap.point, gap.velocity])
        kernels.contact_force(
            *self._laws, float(self.geometry.radius), packed, float(approach), out
        )
        normal = float(out[0])
        if self.friction is not None and normal > 0.0 and at_rest(view):
            direction = coulomb_vector(self._static_slip(view, gap), self.slip_threshold)
            friction = self.friction.mu_dynamic * normal * direction
            return ContactForces(
                normal, float(np.linalg.norm(friction)), normal * gap.normal - friction, 0.0, gap
            )
        return ContactForces(normal, float(out[1]), out[2:5], float(out[5]), gap)

    def _wrench_kernel(self) -> _Kernel | None:
        """The compiled wrench's arguments: a primitive's (also its tangent's), or a
        profile's once its spline is built (its tangent is the integrator's difference)."""
        if self._kernel is not None:
            return self._kernel
        if self._profile_kernel is None and hasattr(self.geometry, "compiled"):
            b1, b2, kind, g = self.geometry.compiled()
            self._profile_kernel = (kind, b1, b2, g, *self._laws)
        return self._profile_kernel

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        kernel = self._wrench_kernel()
        if kernel is not None:
            x, xd = view.kin.x, view.kin.xd
            if self.friction is None or not at_rest(view):
                kernels.contact_wrench(*kernel, self.approach, x, xd, F, N)
                return
            kernels.static_contact_wrench(
                *kernel, self.approach, x, xd, float(self.friction.mu_dynamic),
                self._packed_anchor(), float(self.slip_threshold), F, N,
            )  # fmt: skip
            return
        f = self.forces(view)
        p = f.gap.point
        for body, sign in ((self._b1, 1.0), (self._b2, -1.0)):
            F[body] += sign * f.force
            N[body] += cross(p - view.kin.r[body], sign * f.force)

    def tangent(self, view: StateView, K: np.ndarray, C: np.ndarray) -> None:
        """Add the stiffness -dQ/dq and damping -dQ/dqd (nq, nq) of the contact's
        generalized forces (only when `has_tangent`)."""
        if self._kernel is None:
            raise ValueError(f"contact {self.name}: no compiled tangent (see has_tangent)")
        kernels.contact_tangent(
            *self._kernel, self.approach, view.kin.x, view.kin.xd, self._nb, K, C
        )

    def _packed_anchor(self) -> np.ndarray:
        """The anchor poses (`_anchor`) as kernels.static_contact_wrench takes them (2, 12):
        r, then the rotation matrix by rows, per body; NaN before the first accepted
        state. Packed again only when the anchor changes."""
        held = self._packed
        if held is None or held[0] is not self._anchor:
            packed = np.full((2, 12), np.nan)
            if self._anchor is not None:
                for k, (r0, rot0) in enumerate(self._anchor):
                    packed[k, :3], packed[k, 3:] = r0, np.asarray(rot0).ravel()
            held = self._packed = (self._anchor, packed)
        return held[1]

    def _static_slip(self, view: StateView, gap: Gap) -> np.ndarray:
        """Tangential slip (m, global) of body 1 on body 2 at the contact point since the last
        accepted state: static and quasi-static analyses have no velocities, so their
        friction opposes the travel between consecutive equilibria (as joint_friction and
        seal do). Zero before the first accepted state."""
        if self._anchor is None:
            return np.zeros(3)
        then = []
        for b, (r0, rot0) in zip((self._b1, self._b2), self._anchor):
            local = view.rotation(b).T @ (gap.point - view.kin.r[b])
            then.append(r0 + rot0 @ local)
        slip = then[1] - then[0]  # (p - then_1) - (p - then_2)
        return slip - (slip @ gap.normal) * gap.normal

    def commit(self, view: StateView) -> None:
        """Remember the poses of the two bodies (static slip) and the approach speed when a
        contact begins: while apart, the rate of the latest state; at the first state in
        contact, the rate interpolated to x = 0 between that state and the last one apart
        (the step across the impact is not resolved)."""
        if self.friction is not None:
            self._anchor = tuple(
                (view.kin.r[b].copy(), view.rotation(b).copy()) for b in (self._b1, self._b2)
            )
        if not self.law.remembers:
            return
        gap = self.geometry.gap(view)
        x, xd = gap.penetration, gap.rate
        was_in, x0, xd0 = self._memory
        if x <= 0.0:
            self.approach = xd
        elif not was_in and x0 < 0.0:
            self.approach = xd0 + (xd - xd0) * (-x0) / (x - x0)
        self._memory = (x > 0.0, x, xd)
        times, values = self._history
        del values[bisect_left(times, view.t) :]  # a restart from an earlier time
        del times[bisect_left(times, view.t) :]
        times.append(view.t)
        values.append(self.approach)

    def potential(self, view: StateView) -> float:
        """Elastic energy (J) stored in the penetration (0 apart)."""
        x = self.geometry.gap(view).penetration
        return self.law.potential(x, float(self.geometry.radius))

    def dissipation(self, view: StateView) -> float:
        """Power (W, >= 0) of the damping part of the normal force and of the friction, at
        the approach speed the integrator used for this state."""
        f = self.forces(view, self.approach_at(view.t) if self.law.remembers else None)
        x = min(f.gap.penetration, float(self.geometry.radius))
        damping = f.normal - self.law.elastic_force(x)  # -k x^n where F_N is held at 0
        return damping * f.gap.rate + f.friction * f.sliding_speed

    def rest_dissipation(self, view: StateView, moving) -> float:
        """Power (W) the friction of an equilibrium (`view`, no velocities: its force
        opposes the slip since the last accepted state) takes out while the bodies move at
        the rates of `moving` (a Kin of the same positions)."""
        f = self.forces(view)
        friction = f.force - f.normal * f.gap.normal
        return -float(friction @ self.geometry.gap(view.system.view(moving)).sliding)

    def body_pair(self) -> tuple[int, int]:
        """The two body indices whose states alone set this element's forces."""
        return self._b1, self._b2

    def state_bodies(self) -> tuple[int, int]:
        """The body pair (mechlib.fd_columns)."""
        return self.body_pair()

    def approach_at(self, t: float) -> float:
        """Approach speed (m/s) the integrator used for a state at time t (s): the one
        committed last before t."""
        times, values = self._history
        i = bisect_left(times, t)
        return values[i - 1] if i > 0 else (values[0] if values else self.approach)

    def output(self, view: StateView) -> dict[str, float]:
        f = self.forces(view, self.approach_at(view.t) if self.law.remembers else None)
        px, py, pz = f.gap.point
        fx, fy, fz = f.force
        return {
            "normal": f.normal,
            "friction": f.friction,
            "fx": fx,
            "fy": fy,
            "fz": fz,
            "penetration": max(f.gap.penetration, 0.0),
            "px": px,
            "py": py,
            "pz": pz,
            "sliding_speed": f.sliding_speed,
            "wear": f.normal * f.sliding_speed,
        }
