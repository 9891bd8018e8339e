"""Force elements: applied forces and torques, springs, torsion springs (SI units).

Each element is bound to a compiled `System` once (names -> body indices, body-fixed
vectors) and then adds its wrench to per-body accumulators: `F` (nb+1, 3) forces through
the centres of mass and `N` (nb+1, 3) torques, both global axes. `output` gives the values
a request reports. `effect` names the effect the element belongs to, so that a case that
switches the effect off gets a model without it.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from mechlib.core.rotation import cross
from mechlib.kinematics import kernels
from mechlib.kinematics.view import StateView, measure_bodies
from mechlib.model.mechanism import GROUND

__all__ = ["PointForce", "PointTorque", "Spring", "TorsionSpring", "resist_rotation"]

# Every element has `active` (an event may switch it; an inactive element applies and
# reports nothing) and `effect` (the case switch that removes it from the model).

VectorFunction = Callable[[float, StateView], Sequence[float]]
Measures = Collection[tuple[str, tuple[str, ...]]]  # view measures: ('angle', ('hinge',))


def resist_rotation(view: StateView, measure, moment: float, N: np.ndarray) -> None:
    """A moment (N*m) resisting positive rotation of a joint: -moment about the joint axis
    on body 1, +moment on body 2 (`measure`: the joint's AngleMeasure)."""
    axis = view.rotation(measure.bj) @ measure.axis_local
    N[measure.bi] -= moment * axis
    N[measure.bj] += moment * axis


def has_potential(law) -> bool:
    """True when a spring with `law` (None: linear) has an exact potential: linear, or a
    law with an exact `integral` (a table, mechlib.elements.laws.TableLaw)."""
    return law is None or hasattr(law, "integral")


def stored(law, stiffness: float, deflection: float) -> float:
    """Energy (J) of the elastic part at `deflection` (m or rad): k d^2 / 2, or the
    integral of `law` from 0 to d."""
    if law is None:
        return 0.5 * stiffness * deflection**2
    return float(law.integral(0.0, deflection))


def _global(view: StateView, frame: str, value: VectorFunction) -> np.ndarray:
    """`value(t, view)`, components in `frame` axes, in global components."""
    vector = np.asarray(value(view.t, view), float)
    if frame == GROUND:
        return vector
    return view.system.frame_axes(frame, view.kin) @ vector


def _read_bodies(system, own: int, frame: str, reads: Measures | None) -> set[int] | None:
    """The bodies a load's value depends on: its own, its frame's and those `reads` (the
    view measures the value reads) read; None when unknown."""
    read = None if reads is None else measure_bodies(system, reads)
    if read is None:
        return None
    axes = system.frame_index(frame)
    return read | {own} | (set() if axes is None else {axes})


@dataclass
class PointForce:
    """Force `value(t, view)` (N, 3 components in `frame` axes) at point `at` of `body`.
    `reads`: the view measures `value` reads ((kind, names) pairs, mechlib.kinematics.view.
    measure_bodies; empty: t only), None when unknown."""

    name: str
    body: str
    at: Sequence[float]
    value: VectorFunction
    frame: str = "ground"
    effect: str = "loads"
    active: bool = True
    reads: Measures | None = None
    output_units: ClassVar[dict[str, str]] = {"fx": "N", "fy": "N", "fz": "N"}

    def bind(self, system) -> None:
        self._b, self._s = system.body_point(self.body, self.at)
        self._bodies = _read_bodies(system, self._b, self.frame, self.reads)

    def state_bodies(self) -> set[int] | None:
        """The body indices whose states the force depends on (mechlib.system.fd_columns)."""
        return self._bodies

    def _force(self, view: StateView) -> np.ndarray:
        return _global(view, self.frame, self.value)

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        kernels.point_force(view.kin.x, self._b, self._s, self._force(view), F, N)

    def output(self, view: StateView) -> dict[str, float]:
        fx, fy, fz = self._force(view)
        return {"fx": fx, "fy": fy, "fz": fz}


@dataclass
class PointTorque:
    """Torque `value(t, view)` (N*m, components in `frame` axes) on `body`; `reads` as
    PointForce's."""

    name: str
    body: str
    value: VectorFunction
    frame: str = "ground"
    effect: str = "loads"
    active: bool = True
    reads: Measures | None = None
    output_units: ClassVar[dict[str, str]] = {"tx": "N*m", "ty": "N*m", "tz": "N*m"}

    def bind(self, system) -> None:
        self._b = system.body_index(self.body)
        self._bodies = _read_bodies(system, self._b, self.frame, self.reads)

    def state_bodies(self) -> set[int] | None:
        """The body indices whose states the torque depends on (mechlib.system.fd_columns)."""
        return self._bodies

    def _torque(self, view: StateView) -> np.ndarray:
        return _global(view, self.frame, self.value)

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        N[self._b] += self._torque(view)

    def output(self, view: StateView) -> dict[str, float]:
        tx, ty, tz = self._torque(view)
        return {"tx": tx, "ty": ty, "tz": tz}


@dataclass
class Spring:
    """Translational spring-damper between two points (tension positive, N).

    tension = stiffness (N/m) * (L - free_length) + damping (N*s/m) * dL/dt + preload (N);
    without `free_length` the design length is the free length. `tension_only`: a wire or
    rope, no force while slack (L < free length). `law`: a tabulated force (N) vs deflection
    L - free_length (m) replacing the linear term stiffness * (L - free_length).
    """

    name: str
    points: tuple[tuple[str, Sequence[float]], tuple[str, Sequence[float]]]
    stiffness: float = 0.0
    damping: float = 0.0
    free_length: float | None = None
    preload: float = 0.0
    tension_only: bool = False
    law: Callable[[float], float] | None = None
    effect: str = "springs"
    active: bool = True
    output_units: ClassVar[dict[str, str]] = {"value": "N", "length": "m"}
    _geometry: tuple = field(default=(), repr=False)
    _free_length: float = field(default=np.nan, init=False, repr=False)  # m, set by bind
    # kernels.spring_state's arguments, taken at bind (a bound spring's parameters are fixed)
    _compiled: tuple = field(default=(), init=False, repr=False)

    def bind(self, system) -> None:
        (b1, at1), (b2, at2) = self.points
        self._geometry = (*system.body_point(b1, at1), *system.body_point(b2, at2))
        if self.free_length is None:
            self.free_length = float(np.linalg.norm(np.subtract(at1, at2)))
        self._free_length = self.free_length
        b1, s1, b2, s2 = self._geometry
        self._compiled = (
            *(b1, np.asarray(s1, float), b2, np.asarray(s2, float)),
            *map(float, (self.stiffness, self.damping, self._free_length, self.preload)),
            bool(self.tension_only),
        )

    def state_bodies(self) -> set[int]:
        """The two points' bodies: the tension is a function of their stretch and its rate
        (`law`: of the stretch alone) (mechlib.system.fd_columns)."""
        return {self._geometry[0], self._geometry[2]}

    def _state(self, view: StateView):
        if self.law is None:  # linear: compiled
            out = np.empty(5)
            kernels.spring_state(view.kin.x, view.kin.xd, *self._compiled, out)  # type: ignore[call-arg]
            return float(out[0]), float(out[1]), out[2:5]
        b1, s1, b2, s2 = self._geometry
        d = view.point_position(b1, s1) - view.point_position(b2, s2)
        length = float(np.linalg.norm(d))
        u = d / length if length > 0.0 else np.zeros(3)
        rate = float(u @ (view.point_velocity(b1, s1) - view.point_velocity(b2, s2)))
        stretch = length - self._free_length
        tension = self.law(stretch) + self.damping * rate + self.preload
        if self.tension_only and (stretch < 0.0 or tension < 0.0):
            tension = 0.0  # a slack wire pushes nowhere, nor does its damping when taut
        return tension, length, u

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        if self.law is None:
            kernels.spring_wrench(view.kin.x, view.kin.xd, *self._compiled, F, N)  # type: ignore[call-arg]
            return
        b1, s1, b2, s2 = self._geometry
        tension, _, u = self._state(view)
        for body, s, sign in ((b1, s1, -1.0), (b2, s2, 1.0)):
            force = sign * tension * u
            F[body] += force
            N[body] += cross(view.point_position(body, s) - view.kin.r[body], force)

    def output(self, view: StateView) -> dict[str, float]:
        tension, length, _ = self._state(view)
        return {"value": tension, "length": length}

    def _taut(self, view: StateView) -> tuple[float, float] | None:
        """(stretch (m), rate (m/s)), None while a tension-only spring carries nothing."""
        tension, length, u = self._state(view)
        if self.tension_only and tension == 0.0:
            return None
        b1, s1, b2, s2 = self._geometry
        rate = float(u @ (view.point_velocity(b1, s1) - view.point_velocity(b2, s2)))
        return length - self._free_length, rate

    @property
    def potential(self):
        """Elastic energy (J) at a view, k s^2 / 2 + preload s, or with a tabulated law its
        exact integral over the stretch; None with a law without one (its work is then
        load work)."""
        return self._potential if has_potential(self.law) else None

    def _potential(self, view: StateView) -> float:
        taut = self._taut(view)
        if taut is None:
            return 0.0
        return stored(self.law, self.stiffness, taut[0]) + self.preload * taut[0]

    def dissipation(self, view: StateView) -> float:
        """Power (W) taken out by the damper: damping * rate^2."""
        taut = self._taut(view)
        return 0.0 if taut is None else self.damping * taut[1] ** 2


@dataclass
class TorsionSpring:
    """Rotational spring-damper on a revolute joint; moment (N*m) resisting positive angle.

    moment = stiffness (N*m/rad) * (angle - angle0) + damping (N*m*s/rad) * omega + preload;
    body 1 of the joint receives -moment about the joint axis, body 2 +moment. `law`: a
    tabulated moment (N*m) vs angle - angle0 (rad) replacing stiffness * (angle - angle0).
    """

    name: str
    joint: str
    stiffness: float = 0.0
    damping: float = 0.0
    angle0: float = 0.0
    preload: float = 0.0
    law: Callable[[float], float] | None = None
    effect: str = "springs"
    active: bool = True
    output_units: ClassVar[dict[str, str]] = {"value": "N*m", "angle": "rad"}
    # kernels.torsion_wrench's constants, taken at bind (as Spring's)
    linear_constants: tuple = field(default=(), init=False, repr=False)

    def bind(self, system) -> None:
        self._m = system.measure(self.joint, "angle")
        self.linear_constants = tuple(
            map(float, (self.stiffness, self.damping, self.angle0, self.preload))
        )
        self._table = None  # kernels.torsion_table_wrench's arguments, for a table law
        if getattr(self.law, "compiled", False):  # a TableLaw (its module imports this one)
            m = self._m
            self._table = (
                np.array([m.bi, m.bj], dtype=np.int64),
                np.r_[m.f, m.g, m.axis_local, self.damping, self.angle0, self.preload],
                self.law.table.packed,  # type: ignore[union-attr]
            )

    def state_bodies(self) -> set[int]:
        """The joint's two bodies: the moment is a function of its angle and rate (`law`:
        of the turn alone) (mechlib.system.fd_columns)."""
        return {self._m.bi, self._m.bj}

    def _moment(self, view: StateView) -> tuple[float, float]:
        m, state = self._m, np.empty(2)
        kernels.angle_state(view.kin.x, view.kin.xd, m.bi, m.bj, m.f, m.g, m.reference, state)
        angle, rate = float(state[0]), float(state[1])
        turn = angle - self.angle0
        elastic = self.law(turn) if self.law is not None else self.stiffness * turn
        return elastic + self.damping * rate + self.preload, angle

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        m, x, xd = self._m, view.kin.x, view.kin.xd
        if self.law is None:  # linear: compiled
            kernels.torsion_wrench(  # type: ignore[call-arg]
                x, xd, m.bi, m.bj, m.f, m.g, m.axis_local, m.reference, *self.linear_constants, N
            )
            return
        if self._table is not None:  # a table: compiled while the table takes the turn
            ints, floats, table = self._table
            if kernels.torsion_table_wrench(x, xd, ints, floats, m.reference, *table, N):  # type: ignore[call-arg]
                return
        resist_rotation(view, self._m, self._moment(view)[0], N)  # (raises off the table)

    def output(self, view: StateView) -> dict[str, float]:
        moment, angle = self._moment(view)
        return {"value": moment, "angle": angle}

    @property
    def potential(self):
        """Elastic energy (J) at a view, k turn^2 / 2 + preload turn, or with a tabulated
        law its exact integral over the turn; None with a law without one (its work is then
        load work)."""
        return self._potential if has_potential(self.law) else None

    def _potential(self, view: StateView) -> float:
        turn = self._m.value(view.kin) - self.angle0
        return stored(self.law, self.stiffness, turn) + self.preload * turn

    def dissipation(self, view: StateView) -> float:
        """Power (W) taken out by the damper: damping * omega^2."""
        return self.damping * self._m.rate(view.kin) ** 2
