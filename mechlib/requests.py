"""Outputs requested by name before solving, evaluated on the recorded trajectory.

Sign conventions: a joint reaction is the force and torque on the FIRST body of the joint
from the second, at the joint point (torque about that point), components in `frame` axes;
it includes the effort of motions acting on the joint. A motion effort is the torque (N*m)
or force (N) the motion applies to body 1 about/along the joint axis, positive in the
direction of increasing coordinate.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from mechlib.rotation import cross, d_rotate, e_matrix, rotate, rotation_matrix
from mechlib.system import System
from mechlib.view import StateView

__all__ = ["evaluate_requests", "JointReaction", "MotionEffort", "PointKinematics", "JointCoordinate",
           "ElementOutput", "ExpressionOutput", "Request"]

_FORCE = ("fx", "fy", "fz")
_TORQUE = ("tx", "ty", "tz")


@dataclass(frozen=True)
class JointReaction:
    """Reaction of joint `joint` on its body 1 (N, N*m): fx fy fz tx ty tz f t."""

    name: str
    joint: str
    frame: str = "ground"
    units = dict(zip(_FORCE + _TORQUE + ("f", "t"), ("N",) * 3 + ("N*m",) * 3 + ("N", "N*m")))


@dataclass(frozen=True)
class MotionEffort:
    """Torque (N*m) or force (N) a motion applies along its joint coordinate: value."""

    name: str
    motion: str
    units = {"value": "N*m or N"}


@dataclass(frozen=True)
class PointKinematics:
    """Position (m), velocity (m/s) or acceleration (m/s^2) of a point: x y z, components in
    `frame` axes; a position is measured from the frame's origin. Velocity and acceleration
    are those seen from ground, not relative to the frame."""

    name: str
    point: str
    quantity: str = "position"
    frame: str = "ground"
    units = {"x": "m", "y": "m", "z": "m"}


@dataclass(frozen=True)
class JointCoordinate:
    """angle|omega|alpha (rad, rad/s, rad/s^2) or travel|speed|accel (m...) of a joint."""

    name: str
    joint: str
    quantity: str = "angle"
    units = {"value": "rad"}


@dataclass(frozen=True)
class ElementOutput:
    """What a force element reports: `value` (tension or moment) or its force/torque
    components, given in `frame` axes (default ground)."""

    name: str
    element: str
    frame: str = "ground"


@dataclass(frozen=True)
class ExpressionOutput:
    """An expression of time and state: value."""

    name: str
    function: Callable[[float, StateView], float]
    unit: str = ""


Request = JointReaction | MotionEffort | PointKinematics | JointCoordinate | ElementOutput | ExpressionOutput


def _rows_of(system: System, owners: set[str]) -> np.ndarray:
    return np.array([i for i, o in enumerate(system.owners) if o in owners], dtype=int)


def _body_wrench(system: System, k, jac_rows: np.ndarray, lam: np.ndarray, body: int):
    """Force (global) and torque about the cm of body `body` from constraint rows."""
    if body == system.nb or len(lam) == 0:
        return np.zeros(3), np.zeros(3)
    gen = -(jac_rows[:, 7 * body:7 * body + 7].T @ lam)
    return gen[:3], 0.5 * e_matrix(k.p[body]) @ gen[3:]


def joint_wrench(system: System, k, lam_all: np.ndarray, jac: np.ndarray, joint: str,
                 extra_owners: set[str] = frozenset()):
    """(force, torque about the joint point) on body 1 of `joint`, global axes."""
    j = system.mechanism.joints[joint]
    b1, s1 = system.body_point(j.body1, j.at)
    rows = _rows_of(system, {joint} | set(extra_owners))
    sign = 1.0
    if b1 == system.nb:  # ground is body 1: minus what body 2 receives (action-reaction)
        (b1, s1), sign = system.body_point(j.body2, j.at), -1.0
    force, torque_cm = _body_wrench(system, k, jac[rows], lam_all[rows], b1)
    arm = rotate(k.p[b1], s1)
    return sign * force, sign * (torque_cm - cross(arm, force))


def _frame_matrix(system: System, k, frame: str) -> np.ndarray:
    return system.frame_axes(frame, k)


def _motions_on(system: System, joint: str) -> set[str]:
    return {m.name for m in system.mechanism.motions.values() if m.joint == joint}


def _reaction(system, k, lam, jac, req: JointReaction, view) -> dict[str, float]:
    force, torque = joint_wrench(system, k, lam, jac, req.joint, _motions_on(system, req.joint))
    axes = _frame_matrix(system, k, req.frame).T
    f, t = axes @ force, axes @ torque
    out = dict(zip(_FORCE, f)) | dict(zip(_TORQUE, t))
    out["f"], out["t"] = float(np.linalg.norm(f)), float(np.linalg.norm(t))
    return out


def _effort(system, k, lam, jac, req: MotionEffort, view) -> dict[str, float]:
    motion = system.mechanism.motions[req.motion]
    eq = next(c for c in system.coordinates if c.owner == req.motion)
    measure = eq.terms[0][1]
    rows = _rows_of(system, {req.motion})
    force, torque = _body_wrench(system, k, jac[rows], lam[rows], measure.bi)
    if measure.bi == system.nb:  # body 1 is ground: the effort on body 1 is minus body 2's
        force, torque = _body_wrench(system, k, jac[rows], lam[rows], measure.bj)
        force, torque = -force, -torque
    axis = rotation_matrix(k.p[measure.bj]) @ measure.axis_local
    del motion
    return {"value": float((torque if measure.kind == "angle" else force) @ axis)}


def _in_frame(system, k, values: dict[str, float], frame: str) -> dict[str, float]:
    """Vector components (fx fy fz, tx ty tz) of an element output turned into `frame`."""
    if frame == "ground":
        return values
    axes = _frame_matrix(system, k, frame).T
    out = dict(values)
    for names in (_FORCE, _TORQUE):
        if all(n in values for n in names):
            out.update(zip(names, axes @ np.array([values[n] for n in names])))
    return out


_ANGULAR = {"angle": "angle", "omega": "angle", "alpha": "angle",
            "travel": "travel", "speed": "travel", "accel": "travel"}


def _coordinate(system, k, req: JointCoordinate, qdd) -> float:
    m = system.measure(req.joint, _ANGULAR[req.quantity])
    if req.quantity in ("angle", "travel"):
        return m.value(k)
    if req.quantity in ("omega", "speed"):
        return m.rate(k)
    return float(m.gradient(k)[:system.nq] @ qdd + m.quad(k))


def _point_series(system: System, trajectory, req: PointKinematics) -> dict[str, np.ndarray]:
    """Point kinematics at all recorded times at once (ground axes), then into `frame`."""
    b, s = system.point(req.point)
    n = len(trajectory)
    if b == system.nb:
        v = np.tile(s, (n, 1)) if req.quantity == "position" else np.zeros((n, 3))
    else:
        sl = slice(7 * b, 7 * b + 7)
        x = np.array([q[sl] for q in trajectory.q])
        xd = np.array([q[sl] for q in trajectory.qd])
        if req.quantity == "position":
            v = x[:, :3] + rotate(x[:, 3:], s)
        elif req.quantity == "velocity":
            v = xd[:, :3] + np.einsum("nij,nj->ni", d_rotate(x[:, 3:], s), xd[:, 3:])
        else:
            xdd = np.array([q[sl] for q in trajectory.qdd])
            v = (xdd[:, :3] + np.einsum("nij,nj->ni", d_rotate(x[:, 3:], s), xdd[:, 3:])
                 + 2.0 * rotate(xd[:, 3:], s))
    if req.frame != "ground":
        kins = [system.kin(q, None, t) for q, t in zip(trajectory.q, trajectory.time)]
        if req.quantity == "position":  # measured from the frame's origin
            v = v - np.array([system.frame_origin(req.frame, k) for k in kins])
        axes = np.array([system.frame_axes(req.frame, k) for k in kins])
        v = np.einsum("nji,nj->ni", axes, v)
    return dict(zip("xyz", v.T))


def evaluate_requests(system: System, trajectory, requests) -> dict[str, np.ndarray]:
    """Columns `REQUEST.COMPONENT` (SI) at the recorded times, in request order."""
    per_request: dict[str, dict[str, list]] = {r.name: {} for r in requests}
    stepwise = [r for r in requests if not isinstance(r, PointKinematics)]
    need_jac = any(isinstance(r, (JointReaction, MotionEffort)) for r in stepwise)
    for i, t in enumerate(trajectory.time if stepwise else ()):
        system.restore(trajectory.references[i])  # angles as the solver unwrapped them
        k = system.kin(trajectory.q[i], trajectory.qd[i], t)
        qdd, lam = trajectory.qdd[i], trajectory.lam[i]
        jac = system.phi_q(k) if need_jac else None
        view = system.view(k)
        for req in stepwise:
            for comp, value in _evaluate(system, k, lam, jac, req, view, qdd).items():
                per_request[req.name].setdefault(comp, []).append(float(value))
    for req in requests:
        if isinstance(req, PointKinematics):
            per_request[req.name] = _point_series(system, trajectory, req)
    return {f"{name}.{comp}": np.asarray(values, dtype=float)
            for name, comps in per_request.items() for comp, values in comps.items()}


def _evaluate(system, k, lam, jac, req, view, qdd) -> dict[str, float]:
    if isinstance(req, JointReaction):
        return _reaction(system, k, lam, jac, req, view)
    if isinstance(req, MotionEffort):
        return _effort(system, k, lam, jac, req, view)
    if isinstance(req, JointCoordinate):
        return {"value": _coordinate(system, k, req, qdd)}
    if isinstance(req, ElementOutput):
        return _in_frame(system, k, system.mechanism.forces[req.element].output(view), req.frame)
    return {"value": req.function(k.t, view)}
