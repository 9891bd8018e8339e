"""Coulomb friction in a joint, loaded by the joint's own reaction (seed 003 eq. 2.2).

Revolute, cylindrical, spherical: torque T = mu * pin_radius * F_r + preload (N*m), F_r the
reaction force normal to the joint axis (the whole force for a spherical joint, pin_radius
then the ball radius). Prismatic: force F = mu * F_n + preload (N), F_n the reaction force
normal to the axis. The friction opposes the relative motion of body 1 against body 2 through
the regularised law of `mechlib.elements.regularize`: the velocity in dynamic and kinematic
states, the displacement since the last accepted state in static and quasi-static ones.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechlib.core.rotation import cross, omega_global
from mechlib.elements import friction_kernel as kernel
from mechlib.elements.regularize import (
    StaticSlipAnchor,
    at_rest,
    coulomb_factor,
    coulomb_vector,
    rotation_increment,
)
from mechlib.kinematics.coordinates import AngleMeasure, TravelMeasure
from mechlib.kinematics.view import StateView

__all__ = ["FRICTION_JOINTS", "JointFriction", "friction_units"]

FRICTION_JOINTS = ("revolute", "cylindrical", "spherical", "prismatic")
_NO_JACOBIAN, _NO_VALUES, _NO_ROWS = np.zeros((0, 0)), np.zeros(0), np.zeros(0, dtype=np.int64)


def friction_units(joint_type: str) -> dict[str, str]:
    """Units of a joint friction's outputs on a joint of `joint_type`: the friction effort
    and its capacity in N on a prismatic joint, N*m on the others; the normal force in N."""
    unit = "N" if joint_type == "prismatic" else "N*m"
    return {"value": unit, "capacity": unit, "normal": "N"}


@dataclass
class JointFriction(StaticSlipAnchor):
    """Friction of joint `joint`: `mu` (-), `pin_radius` (m; not for prismatic joints),
    `preload` (N*m, or N on a prismatic joint), `v_threshold` (rad/s or m/s: full friction
    from this relative speed on), `slip_threshold` (rad or m: the same for the displacement
    between two static states)."""

    name: str
    joint: str
    mu: float
    pin_radius: float = 0.0
    preload: float = 0.0
    v_threshold: float = 1.0e-3
    slip_threshold: float = 1.0e-6
    effect: str = "friction"
    active: bool = True
    uses_reactions = True

    @property
    def output_units(self) -> dict[str, str]:
        """The units of the outputs (known once bound to its joint: `friction_units`)."""
        return friction_units(self._type)

    def bind(self, system) -> None:
        j = system.mechanism.joints[self.joint]
        if j.type not in FRICTION_JOINTS:
            raise ValueError(
                f"joint_friction '{self.name}': joint '{self.joint}' is {j.type}; "
                f"friction needs a {', '.join(FRICTION_JOINTS)} joint"
            )
        self._type = j.type
        self._system = system
        self._bi, self._si = system.body_point(j.body1, j.at)
        self._bj, _ = system.body_point(j.body2, j.at)
        self._m: AngleMeasure | TravelMeasure | None = None
        self._stick_row = None
        if j.type != "spherical":
            self._m = system.measure(self.joint, "travel" if j.type == "prismatic" else "angle")
            if not _prescribed(system.mechanism, self.joint):
                self._stick_row = system.held_coordinate(self.stick_owner, self._m)
        self._anchor = 0.0 if self._m is not None else np.eye(3)
        self._compiled: tuple[AngleMeasure, np.ndarray, np.ndarray] | None = None
        if isinstance(self._m, AngleMeasure):  # a revolute or cylindrical joint
            m = self._m
            self._compiled = (
                m,
                np.array([self._bi, self._bj, m.bi, m.bj, 0], dtype=np.int64),
                np.r_[m.f, m.g, m.axis_local, self.mu * self._arm, self.preload].astype(float),
            )
            assert self._compiled[2].size == kernel.FLOATS
        self._rate = self._rate_before = 0.0  # slip rates at the last two accepted states
        self._impending = 0.0  # direction of the slip that starts when a stuck joint lets go

    # ---- kinematics of the slip -------------------------------------------------------
    def _relative_rotation(self, view: StateView) -> np.ndarray:
        return view.rotation(self._bi) @ view.rotation(self._bj).T

    def _direction(self, view: StateView) -> np.ndarray:
        """Signed, regularised unit vector (global) of body 1's slip against body 2."""
        if self._m is not None:
            axis = self._axis(view)
            if at_rest(view):
                slip = self._m.value(view.kin) - self._anchor
                return coulomb_factor(slip, self.slip_threshold) * axis
            rate = self._m.rate(view.kin) / self.v_threshold + self._impending
            return coulomb_factor(rate, 1.0) * axis
        if at_rest(view):
            return coulomb_vector(
                rotation_increment(self._relative_rotation(view), self._anchor), self.slip_threshold
            )
        k = view.kin
        w = omega_global(k.p[self._bi], k.pd[self._bi]) - omega_global(
            k.p[self._bj], k.pd[self._bj]
        )
        return coulomb_vector(w, self.v_threshold)

    # ---- stick (dynamic analyses; see mechlib.solvers.stick) ----------------------------------
    @property
    def stick_owner(self) -> str:
        """Owner name of the equation that holds the joint while it sticks."""
        return f"{self.name}: stick"

    @property
    def can_stick(self) -> bool:
        """Joints with one slip coordinate stick exactly; a spherical joint's friction is
        the regularised law alone (it creeps below `v_threshold`), and a joint whose
        coordinate a motion or a coupling prescribes has nothing to stick."""
        return self._stick_row is not None

    @property
    def stuck(self) -> bool:
        return self._stick_row is not None and self._system.is_active(self._stick_row)

    @property
    def locked(self) -> bool:
        """A lock (an event's `lock`, a phase's `locks`) holds the joint's coordinate: it
        cannot slip, so the friction neither sticks nor acts (the lock's equation carries
        the load) until the lock is released."""
        return self._m is not None and self._system.locked(self._m)

    def slip_rate(self, view: StateView) -> float:
        """Rate (rad/s or m/s) of the joint coordinate."""
        return self._coordinate.rate(view.kin)

    def may_stick(self, view: StateView) -> bool:
        """Sliding, and the slip rate passed through zero over the last accepted step (or
        is within the regularised band): a candidate to stick."""
        rate = self.slip_rate(view)
        return not (self.stuck or self.locked) and (
            rate * self._rate_before <= 0.0 or abs(rate) < self.v_threshold
        )

    def stick_effort(self, view: StateView) -> float:
        """Torque (N*m) or force (N) the stick equation applies to body 1 along the axis."""
        return view.effort(self.stick_owner)

    @property
    def impending(self) -> float:
        """+1/-1: the direction a slip starting from rest takes (0: none known)."""
        return self._impending

    def stick(self, k) -> None:
        self._system.hold(self._stick_row, k)

    def unstick(self) -> None:
        """Take the stick equation away again (it was not needed)."""
        self._system.let_go(self._stick_row)

    def slip(self, effort: float) -> None:
        """Let go: the joint starts to slip the way the held load pushes it (against the
        stick effort `effort`)."""
        self.unstick()
        self._impending = -math.copysign(1.0, effort)

    @property
    def _coordinate(self) -> AngleMeasure | TravelMeasure:
        """The joint coordinate's measure (a spherical joint has none)."""
        if self._m is None:
            raise ValueError(f"joint_friction '{self.name}': a spherical joint has no coordinate")
        return self._m

    def _axis(self, view: StateView) -> np.ndarray:
        m = self._coordinate
        return view.rotation(m.bj) @ m.axis_local

    def _normal_force(self, view: StateView) -> np.ndarray:
        """Reaction force (N, global) normal to the axis (all of it for a spherical
        joint)."""
        force = view.reaction_force(self.joint)
        if self._m is None:
            return force
        axis = self._axis(view)
        return force - (force @ axis) * axis

    @property
    def _arm(self) -> float:
        return 1.0 if self._type == "prismatic" else self.pin_radius

    def static_anchor(self) -> tuple:
        return self._anchor, self._impending

    def restore_static_anchor(self, anchor: tuple) -> None:
        self._anchor, self._impending = anchor

    def capacity(self, view: StateView) -> float:
        """mu r F_r + preload (N*m, or N on a prismatic joint) at `view`."""
        return self._capacity(view)[0]

    def _capacity(self, view: StateView) -> tuple[float, float]:
        normal = float(np.linalg.norm(self._normal_force(view)))
        return self.mu * self._arm * normal + self.preload, normal

    # ---- element protocol -------------------------------------------------------------
    def _add_wrench(self, view: StateView, capacity: float, F: np.ndarray, N: np.ndarray) -> None:
        load = -capacity * self._direction(view)  # on body 1, opposing its slip
        if self._type != "prismatic":
            N[self._bi] += load
            N[self._bj] -= load
            return
        at = view.point_position(self._bi, self._si)
        F[self._bi] += load
        N[self._bi] += cross(at - view.kin.r[self._bi], load)
        F[self._bj] -= load
        N[self._bj] -= cross(at - view.kin.r[self._bj], load)

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        if self.stuck or self.locked:  # held by its stick equation, or by a lock, instead
            return
        arguments = self._kernel_arguments(view, whole=False)
        if arguments is None:
            self._add_wrench(view, self._capacity(view)[0], F, N)
            return
        kernel.rotation_friction_wrench(*arguments, N)  # type: ignore[call-arg]

    def _kernel_arguments(self, view: StateView, whole: bool = True) -> tuple | None:
        """The compiled kernels' state arguments (mechlib.elements.friction_kernel) for a
        revolute or cylindrical joint in a moving state, else None (the Python path). With
        `whole`, the constraint Jacobian and multipliers of all equations (the coupling
        writes the joint's columns among them); else the joint's own rows alone, which
        are all the wrench reads (a state whose phi_q is not known, such as a column of
        a differenced tangent, computes no other rows: StateView.jacobian_rows)."""
        if self._compiled is None or at_rest(view):
            return None
        m, ints, floats = self._compiled
        lam, sign = view.lam, 1.0
        # no reaction known yet, or none needed: with mu = 0 the capacity is the preload
        # alone, and the constraint Jacobian a reaction needs would be evaluated for nothing
        # (at every column of a differenced tangent)
        if lam is None or len(lam) == 0 or self.mu == 0.0:
            jac, lam, rows = _NO_JACOBIAN, _NO_VALUES, _NO_ROWS
        else:
            rows, ints[4], sign = self._system.joint_force_rows(self.joint)
            if whole:
                jac = view.jacobian()
            else:
                jac, lam, rows = view.jacobian_rows(rows), lam[rows], np.arange(rows.size)
        varying = np.array([sign, m.reference, self.v_threshold, self._impending])
        return view.kin.x, view.kin.xd, jac, lam, rows, ints, floats, varying

    def reaction_jacobian(self, view: StateView, out: np.ndarray) -> None:
        """Add dQ/dlam (nq, m) of this friction at `view` to `out`. Q is linear in the
        capacity mu r |F_n| + preload, and F_n = P (-sign B^T lam) with B the force block
        of the joint's rows: dQ/dlam = Q(capacity 1) (x) mu r (-sign B u), u = F_n/|F_n|
        (nothing where F_n = 0, whose derivative is undefined)."""
        if self.mu == 0.0 or self.stuck or self.locked:
            return
        arguments = self._kernel_arguments(view)
        if arguments is not None:  # compiled: the same product
            system = self._system
            kernel.rotation_friction_coupling(*arguments, system.masses, system.inertia, out)  # type: ignore[call-arg]
            return
        normal = self._normal_force(view)
        size = float(np.linalg.norm(normal))
        if size == 0.0:
            return
        F = np.zeros((view.system.nb + 1, 3))
        N = np.zeros_like(F)
        self._add_wrench(view, 1.0, F, N)
        unit = view.system.generalized(view.kin, F, N)
        rows, body, sign = view.system.joint_force_rows(self.joint)
        block = view.jacobian()[rows, 7 * body : 7 * body + 3]
        out[:, rows] += np.outer(unit, -sign * self.mu * self._arm * (block @ (normal / size)))

    def begin(self, view: StateView) -> None:
        """Start of an analysis: slips are measured from this state."""
        self._anchor = (
            self._m.value(view.kin) if self._m is not None else self._relative_rotation(view).copy()
        )
        rate = self.slip_rate(view) if self._m is not None else 0.0
        self._rate = self._rate_before = rate
        self._impending = 0.0

    def commit(self, view: StateView) -> None:
        """Accepted state. At rest (static, quasi-static): the anchor moves to it, so that
        the next equilibrium's friction opposes the travel between the two. Moving: the
        slip rate is kept (stick detection), and a slip that got going forgets the
        direction it started in."""
        if at_rest(view):
            self.begin(view)
        elif self._m is not None:
            self._rate_before, self._rate = self._rate, self.slip_rate(view)
            if abs(self._rate) >= self.v_threshold or self.locked:
                self._impending = 0.0

    def output(self, view: StateView) -> dict[str, float]:
        """value: friction resisting body 1's motion (signed along the axis; magnitude for
        a spherical joint); capacity: mu r F_r + preload; normal: F_r."""
        capacity, normal = self._capacity(view)
        if self.stuck:
            return {"value": -self.stick_effort(view), "capacity": capacity, "normal": normal}
        if self.locked:  # the lock carries the load
            return {"value": 0.0, "capacity": capacity, "normal": normal}
        direction = self._direction(view)
        if self._m is not None:
            value = capacity * float(direction @ self._axis(view))
        else:
            value = capacity * float(np.linalg.norm(direction))
        return {"value": value, "capacity": capacity, "normal": normal}


def _prescribed(mechanism, joint: str) -> bool:
    """True when a motion drives `joint`, or a coupler or gear ties its coordinate."""
    if any(m.joint == joint for m in mechanism.motions.values()):
        return True
    return any(j.joints and joint in j.joints for j in mechanism.joints.values())
