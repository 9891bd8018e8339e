"""The contact force element: a geometry, a normal-force law and an optional friction law.

Force on body 1 at the contact point: F_N * normal + friction, with
friction = -mu(|v_t|) * F_N * v_t / |v_t| (v_t the tangential relative velocity); body 2
gets the opposite force at the same point. The element remembers (`commit`, on accepted
states) the approach speed at the start of each contact, which the hysteresis damping of
`hertz` and `restitution` divide by. The gap, the force and the wrench are compiled
(mechlib.elements.contact.kernels); so is the tangent of the primitive geometries, while a profile
contact's is the integrator's difference of its compiled wrench.

Energy (the energy request, mechlib.outputs.energy): `potential` is the integral of the law's
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

from mechlib.elements.contact import kernels
from mechlib.elements.contact.friction import NO_FRICTION
from mechlib.elements.contact.geometry import Gap
from mechlib.elements.contact.laws import IMPACT, MIN_APPROACH_SPEED
from mechlib.elements.contact.memory import MEMORY, commit_memory
from mechlib.elements.regularize import StaticSlipAnchor, at_rest
from mechlib.kinematics.view import StateView

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
    "elastic": "N",
    "damping": "N",
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
    (mechlib.elements.contact.geometry / profile), `law` (mechlib.elements.contact.laws) and
    optional `friction` (mechlib.elements.contact.friction)."""

    name: str
    bodies: tuple[str, str]
    geometry: Any
    law: Any
    friction: Any = None
    effect: str = "contact"
    active: bool = True
    output_units = _CONTACT_UNITS
    approach: float = 0.0  # m/s, penetration rate when the current contact began
    # in contact (1.0 or 0.0), x (m), xd (m/s) at the last accepted state (memory.MEMORY)
    _memory: np.ndarray = field(default_factory=lambda: np.zeros(MEMORY), repr=False)
    # (time, approach) at every accepted state: outputs are read after the solve, and a
    # recorded state must see the approach speed the integrator used for it
    _history: tuple[list, list] = field(default_factory=lambda: ([], []), repr=False)
    # poses of bodies 1 and 2 at the last accepted state, per body r then its rotation matrix
    # by rows (NaN: none yet): the slip of a static (quasi-static) evaluation is measured
    # from there (kernels.static_contact_wrench)
    _anchor: np.ndarray = field(default_factory=lambda: np.full((2, 12), np.nan), repr=False)
    slip_threshold: float = 1.0e-6  # m: static slip of full friction
    own_tangent: bool = True  # False: the solvers difference its forces (planar systems)
    # (time, start) of the impact law's damping ramp start (m), changed by `start_from`
    _starts: tuple[list, list] = field(default_factory=lambda: ([], []), repr=False)

    def bind(self, system) -> None:
        self._b1, self._b2 = self.geometry.bind(system, *self.bodies)
        law = self.law.kernel()
        friction = (NO_FRICTION, np.zeros(5)) if self.friction is None else self.friction.kernel()
        self._laws: _Laws = (*law, *friction)
        self._nb = system.nb
        # the primitives: (kind, b1, b2, g, law, law parameters, friction, its parameters)
        self._kernel: _Kernel | None = None
        self._wrench: _Kernel | None = None  # the gap and wrench's (`_wrench_kernel`)
        if hasattr(self.geometry, "kernel"):
            b1, b2, kind, g = self.geometry.kernel()
            self._kernel = (kind, b1, b2, g, *self._laws)

    @property
    def has_tangent(self) -> bool:
        """True when `tangent` gives the stiffness and damping (compiled primitives, in the
        3-D coordinates: not in a planar system, which sets `own_tangent` False)."""
        return self._kernel is not None and self.own_tangent

    def forces(self, view: StateView, approach: float | None = None) -> ContactForces:
        """The contact's forces in state `view` (`approach`: m/s, default the current one)."""
        gap = self.geometry.gap(view)
        approach = self.approach if approach is None else approach
        out = np.empty(6)
        packed = np.concatenate([[gap.penetration], gap.normal, gap.point, gap.velocity])
        kernels.contact_force(
            *self._laws, float(self.geometry.radius), packed, float(approach), out
        )
        return self._with_friction(view, gap, float(approach), out)

    def recorded_forces(self, view: StateView) -> ContactForces:
        """The forces of a recorded state, with the memory the integrator used at its time
        (approach speed, impact ramp start)."""
        if not self._starts[0]:
            return self.forces(view, self.approach_at(view.t) if self.law.remembers else None)
        params = self._laws[1]
        now, params[4] = params[4], self._start_at(view.t)
        try:
            return self.forces(view)
        finally:
            params[4] = now

    def _with_friction(
        self, view: StateView, gap: Gap, approach: float, out: np.ndarray
    ) -> ContactForces:
        """`out` of contact_force with the static friction of a state at rest."""
        if self.friction is not None and out[0] > 0.0 and at_rest(view):
            kernels.static_contact_force(
                *self._wrench_kernel(), float(approach), view.kin.x, view.kin.xd,
                *self._static_friction(), out,
            )  # fmt: skip
        return ContactForces(float(out[0]), float(out[1]), out[2:5], float(out[5]), gap)

    def _wrench_kernel(self) -> _Kernel:
        """The compiled gap and wrench's arguments (a profile's once its spline is built)."""
        if self._wrench is None:
            b1, b2, kind, g = self.geometry.compiled()
            self._wrench = (kind, b1, b2, g, *self._laws)
        return self._wrench

    def _static_friction(self) -> tuple[float, np.ndarray, float]:
        """(mu, anchor poses, slip threshold (m)) for the static friction kernels."""
        assert self.friction is not None
        return float(self.friction.mu_dynamic), self._anchor, float(self.slip_threshold)

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        kernel, x, xd = self._wrench_kernel(), view.kin.x, view.kin.xd
        if self.friction is None or not at_rest(view):
            kernels.contact_wrench(*kernel, self.approach, x, xd, F, N)
        else:
            kernels.static_contact_wrench(
                *kernel, self.approach, x, xd, *self._static_friction(), F, N
            )

    def tangent(self, view: StateView, K: np.ndarray, C: np.ndarray) -> None:
        """Add the stiffness -dQ/dq and damping -dQ/dqd (nq, nq) of the contact's
        generalized forces (only when `has_tangent`)."""
        if self._kernel is None:
            raise ValueError(f"contact {self.name}: no compiled tangent (see has_tangent)")
        kernels.contact_tangent(
            *self._kernel, self.approach, view.kin.x, view.kin.xd, self._nb, K, C
        )

    def start_from(self, view: StateView) -> None:
        """Switched on by an event at `view`: a contact already penetrating starts from its
        state: the approach rate (hertz, restitution) is the rate now, and the damping of
        the impact law ramps in from the penetration now (no step in the damping)."""
        gap = self.geometry.gap(view)
        x, xd = gap.penetration, gap.rate
        self._memory = np.array([1.0 if x > 0.0 else 0.0, x, xd])
        self._law_start(max(x, 0.0), view.t)
        if self.law.remembers and x > 0.0:
            self.approach = max(xd, MIN_APPROACH_SPEED)
            self._record(view.t)

    def _law_start(self, start: float, t: float) -> None:
        """Set the impact law's ramp start (m; its kernel parameter 4), remembered by time."""
        params = self._laws[1]
        if self._laws[0] != IMPACT or params[4] == start:
            return
        params[4] = start  # the kernels' tuples share this array
        times, values = self._starts
        del values[bisect_left(times, t) :]
        del times[bisect_left(times, t) :]
        times.append(t)
        values.append(start)

    def _start_at(self, t: float) -> float:
        """The impact ramp start (m) the integrator used at time t (s)."""
        times, values = self._starts
        i = bisect_left(times, t)
        return values[i - 1] if i > 0 else 0.0

    def commit(self, view: StateView) -> None:
        """Remember the poses of the two bodies (static slip) and the approach speed when a
        contact begins (mechlib.elements.contact.memory, the rule the compiled whole run
        commits by too)."""
        kind, b1, b2, g = self._wrench_kernel()[:4]
        posed = self.friction is not None
        # new arrays: recorded snapshots keep the old anchor, copies the old memory
        anchor = np.empty((2, 12)) if posed else self._anchor
        memory = self._memory.copy()
        approach, x = commit_memory(
            kind, b1, b2, g, self.law.remembers, posed, view.kin.x, view.kin.xd, memory,
            float(self.approach), anchor,
        )  # fmt: skip
        self._anchor = anchor
        if x <= 0.0:
            self._law_start(0.0, view.t)
        if not self.law.remembers:
            return
        self.approach, self._memory = approach, memory
        self._record(view.t)

    def _record(self, t: float) -> None:
        """Remember the approach speed from time t (s) on."""
        times, values = self._cut(t)
        times.append(t)
        values.append(self.approach)

    def extend_history(self, times: np.ndarray, approaches: np.ndarray) -> None:
        """The approach speeds (m/s) a compiled run committed at its accepted states at
        `times` (s, rising), as `_record` remembers them one by one."""
        if not self.law.remembers or not len(times):
            return
        kept, values = self._cut(float(times[0]))
        kept.extend(times.tolist())
        values.extend(approaches.tolist())

    def _cut(self, t: float) -> tuple[list, list]:
        """The history, what it held from time t (s) on dropped (a restart from an earlier
        time)."""
        times, values = self._history
        del values[bisect_left(times, t) :]
        del times[bisect_left(times, t) :]
        return times, values

    def potential(self, view: StateView) -> float:
        """Elastic energy (J) stored in the penetration (0 apart)."""
        x = self.geometry.gap(view).penetration
        return self.law.potential(x, float(self.geometry.radius))

    def normal_split(self, f: ContactForces) -> tuple[float, float]:
        """(elastic part k x^n, damping part F_N - k x^n) of the normal force (N) of `f`
        (seed 004 fig. 5.13); the penetration held at the radius as the kernels hold it. The
        damping part is negative where the law clips F_N at 0 (separating fast)."""
        x = min(f.gap.penetration, float(self.geometry.radius))
        elastic = self.law.elastic_force(x)
        return elastic, f.normal - elastic

    def dissipation(self, view: StateView) -> float:
        """Power (W, >= 0) of the damping part of the normal force and of the friction, at
        the approach speed the integrator used for this state."""
        f = self.recorded_forces(view)
        damping = self.normal_split(f)[1]
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
        """The body pair (mechlib.system.fd_columns)."""
        return self.body_pair()

    def approach_at(self, t: float) -> float:
        """Approach speed (m/s) the integrator used for a state at time t (s): the one
        committed last before t."""
        times, values = self._history
        i = bisect_left(times, t)
        return values[i - 1] if i > 0 else (values[0] if values else self.approach)

    def output(self, view: StateView) -> dict[str, float]:
        f = self.recorded_forces(view)
        px, py, pz = f.gap.point
        fx, fy, fz = f.force
        elastic, damping = self.normal_split(f)
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
            "elastic": elastic,
            "damping": damping,
        }
