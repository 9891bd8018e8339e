"""A read-only view of one mechanism state, as expressions and force elements see it."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from mechlib.kinematics import kernels
from mechlib.kinematics.kin import Kin

if TYPE_CHECKING:
    from mechlib.system.system import System

__all__ = ["StateView", "measure_bodies"]

# the measures of a view by the coordinate they read of a joint, or reading named points
_JOINT_MEASURES = {"angle": "angle", "omega": "angle", "travel": "travel", "speed": "travel"}
_POINT_MEASURES = frozenset({"x", "y", "z", "vx", "vy", "vz", "dist"})


def measure_bodies(system: System, measures) -> set[int] | None:
    """The body indices whose states the view measures `measures` read, given as (kind,
    names) pairs named as the StateView methods (('angle', ('hinge',)), ('dist', ('a',
    'b'))); None when one reads more (`effort`: the multipliers and the whole Jacobian),
    is of another kind, or names no joint coordinate or point of `system`."""
    out: set[int] = set()
    for kind, names in measures:
        try:
            if kind in _JOINT_MEASURES:
                measure = system.measure(names[0], _JOINT_MEASURES[kind])
                out |= {measure.bi, measure.bj}
            elif kind in _POINT_MEASURES:
                out |= {system.point(name)[0] for name in names}
            else:
                return None
        except KeyError:
            return None
    return out


class StateView:
    """State measures in SI: joint angle (rad) / travel (m) and rates, point positions (m)."""

    def __init__(
        self,
        system: System,
        kin: Kin,
        lam: np.ndarray | None = None,
        jac: np.ndarray | None = None,
        *,
        memo: bool = False,
    ):
        self.system = system
        self.kin = kin
        self.lam = lam
        self._jac = jac  # phi_q at kin, when the caller has it already
        # With `memo`, body rotations and named points' positions and velocities are
        # computed once (read-only arrays): for a view that lives while its state cannot
        # change (System.wrenches: every element at one state; a drag force reads a
        # point's vx and vy three times each, joint friction its axis twice).
        self._memo: dict | None = {} if memo else None

    def jacobian(self) -> np.ndarray:
        """phi_q (m, nq) of this state (computed once)."""
        if self._jac is None:
            self._jac = self.system.phi_q(self.kin)
        return self._jac

    def jacobian_rows(self, rows: np.ndarray) -> np.ndarray:
        """phi_q[rows] (len(rows), nq) of this state, for the active equations `rows`: from
        the whole phi_q when known, else from the equation groups that hold them only
        (System.phi_q_rows; a joint's reaction at a column of a differenced tangent)."""
        if self._jac is not None:
            return self._jac[rows]
        key = ("rows", rows.tobytes())  # kept writeable: the compiled friction reads it
        found = None if self._memo is None else self._memo.get(key)
        if found is None:
            found = self.system.phi_q_rows(self.kin, rows)
            if self._memo is not None:
                self._memo[key] = found
        return found

    @property
    def t(self) -> float:
        return self.kin.t

    @property
    def at_rest(self) -> bool:
        """An equilibrium's state (static, quasi-static): see Kin.at_rest."""
        return self.kin.at_rest

    def rotation(self, body: int) -> np.ndarray:
        """Rotation matrix of body index `body` (ground = nb)."""
        return self._kept(("rotation", body), lambda: kernels.rotation_matrix(self.kin.x[body, 3:]))

    def _kept(self, key: tuple, compute: Callable[[], np.ndarray]) -> np.ndarray:
        """compute(), once per view with `memo` (then read-only: its readers share it)."""
        if self._memo is None:
            return compute()
        found = self._memo.get(key)
        if found is None:
            found = self._memo[key] = compute()
            found.flags.writeable = False
        return found

    def point_position(self, body: int, s: np.ndarray) -> np.ndarray:
        """Global position (m) of the body-fixed vector s (m) of body index `body`."""
        return kernels.point_position(self.kin.x, body, np.asarray(s, dtype=float))

    def point_velocity(self, body: int, s: np.ndarray) -> np.ndarray:
        """Global velocity (m/s) of that point."""
        return kernels.point_velocity(self.kin.x, self.kin.xd, body, np.asarray(s, dtype=float))

    def states(self, element) -> np.ndarray:
        """The internal states of an element with states (see mechlib.elements.states)."""
        return self.system.states.of(element)

    def reaction(self, joint: str) -> tuple[np.ndarray, np.ndarray]:
        """Force (N) and torque about the joint point (N*m) on body 1 of `joint` from body 2,
        global axes, from the multipliers of this state (zero when none are known yet)."""
        if self.lam is None or len(self.lam) == 0:
            return np.zeros(3), np.zeros(3)
        from mechlib.kinematics.reactions import joint_wrench

        return joint_wrench(self.system, self.kin, self.jacobian(), self.lam, joint)

    def reaction_force(self, joint: str) -> np.ndarray:
        """Force (N, global) on body 1 of `joint` from body 2 (its own rows), from the
        multipliers of this state (zero when none are known yet): the part of `reaction`
        that joint friction reads, without the moment."""
        if self.lam is None or len(self.lam) == 0:
            return np.zeros(3)
        rows, body, sign = self.system.joint_force_rows(joint)
        block = self.jacobian_rows(rows)[:, 7 * body : 7 * body + 3]
        return -sign * (block.T @ self.lam[rows])

    def effort(self, motion: str) -> float:
        """Torque (N*m) or force (N) that `motion` applies along its joint coordinate, from
        the multipliers of this state (0 while none are known)."""
        if self.lam is None or len(self.lam) == 0:
            return 0.0
        from mechlib.kinematics.reactions import motion_effort

        return motion_effort(self.system, self.kin, self.jacobian(), self.lam, motion)

    def _measure(self, joint: str, kind: str):
        return self.system.measure(joint, kind)

    def angle(self, joint: str) -> float:
        return self._measure(joint, "angle").value(self.kin)

    def omega(self, joint: str) -> float:
        return self._measure(joint, "angle").rate(self.kin)

    def travel(self, joint: str) -> float:
        return self._measure(joint, "travel").value(self.kin)

    def speed(self, joint: str) -> float:
        return self._measure(joint, "travel").rate(self.kin)

    def position(self, point: str) -> np.ndarray:
        """Global position (m) of a named point."""
        where = self.system.point
        return self._kept(("position", point), lambda: self.point_position(*where(point)))

    def dist(self, p1: str, p2: str) -> float:
        return float(np.linalg.norm(self.position(p1) - self.position(p2)))

    def x(self, point: str) -> float:
        return float(self.position(point)[0])

    def y(self, point: str) -> float:
        return float(self.position(point)[1])

    def z(self, point: str) -> float:
        return float(self.position(point)[2])

    def velocity(self, point: str) -> np.ndarray:
        """Global velocity (m/s) of a named point."""
        where = self.system.point
        return self._kept(("velocity", point), lambda: self.point_velocity(*where(point)))

    def vx(self, point: str) -> float:
        return float(self.velocity(point)[0])

    def vy(self, point: str) -> float:
        return float(self.velocity(point)[1])

    def vz(self, point: str) -> float:
        return float(self.velocity(point)[2])
