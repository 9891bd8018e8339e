"""Outputs requested by name before solving, evaluated on the recorded trajectory.

Sign conventions: a joint reaction is the force and torque on the FIRST body of the joint
from the second, at the joint point (torque about that point), components in `frame` axes;
it includes the effort of motions acting on the joint. A motion effort is the torque (N*m)
or force (N) the motion applies to body 1 about/along the joint axis, positive in the
direction of increasing coordinate.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from mechlib.core.outcome import SolverFailure
from mechlib.core.rotation import d_rotate, rotate
from mechlib.kinematics.coordinates import AngleMeasure, CoordinateEquation, TravelMeasure
from mechlib.kinematics.reactions import (
    FORCE,
    TORQUE,
    Gatherer,
    effort_series,
    gather_in_batches,
    reaction_series,
)
from mechlib.kinematics.view import StateView
from mechlib.outputs.coordinate_columns import coordinate_column
from mechlib.outputs.energy import EnergyBalance, energy_columns
from mechlib.outputs.request_failure import partial_columns
from mechlib.system.system import System

__all__ = [
    "CouplerEffort",
    "ElementOutput",
    "ExpressionOutput",
    "FlexibleOutput",
    "JointCoordinate",
    "JointReaction",
    "MotionEffort",
    "PointKinematics",
    "Request",
    "evaluate_requests",
]


@dataclass(frozen=True)
class JointReaction:
    """Reaction of joint `joint` on its body 1 (N, N*m): fx fy fz tx ty tz f t."""

    name: str
    joint: str
    frame: str = "ground"
    units: ClassVar[dict[str, str]] = dict(
        zip(FORCE + TORQUE + ("f", "t"), ("N",) * 3 + ("N*m",) * 3 + ("N", "N*m"))
    )


@dataclass(frozen=True)
class MotionEffort:
    """Torque (N*m) or force (N) a motion applies along its joint coordinate: value."""

    name: str
    motion: str
    units: ClassVar[dict[str, str]] = {"value": "N*m or N"}


@dataclass(frozen=True)
class CouplerEffort:
    """Torque (N*m) or force (N) a coupler or gear applies along the coordinates of its two
    joints, each on the joint's body 1: `input` (joints[0]) and `output` (joints[1]); an
    ideal coupler balances power: input = -ratio * output."""

    name: str
    joint: str
    units: ClassVar[dict[str, str]] = {"input": "N*m or N", "output": "N*m or N"}


@dataclass(frozen=True)
class PointKinematics:
    """Position (m), velocity (m/s) or acceleration (m/s^2) of a point: x y z, components in
    `frame` axes; a position is measured from the frame's origin. Velocity and acceleration
    are those seen from ground, not relative to the frame."""

    name: str
    point: str
    quantity: str = "position"
    frame: str = "ground"
    units: ClassVar[dict[str, str]] = {"x": "m", "y": "m", "z": "m"}


@dataclass(frozen=True)
class FlexibleOutput:
    """Of the flexible body `body`: its modal coordinates (`modes`: q1..qn, kg^0.5*m per
    mass-normalised mode) or the elastic `deformation` of its interface point `point`
    (x y z, m, in the body's floating-frame axes: Phi_p zeta)."""

    name: str
    body: str
    quantity: str = "modes"
    point: str | None = None


@dataclass(frozen=True)
class JointCoordinate:
    """angle|omega|alpha (rad, rad/s, rad/s^2) or travel|speed|accel (m...) of a joint."""

    name: str
    joint: str
    quantity: str = "angle"
    units: ClassVar[dict[str, str]] = {"value": "rad"}


@dataclass(frozen=True)
class ElementOutput:
    """What a force element reports: `value` (tension or moment) or its force/torque
    components, given in `frame` axes (default ground)."""

    name: str
    element: str
    frame: str = "ground"
    components: tuple[tuple[str, str], ...] | None = None  # (column, element key) to keep


@dataclass(frozen=True)
class ExpressionOutput:
    """An expression of time and state: value."""

    name: str
    function: Callable[[float, StateView], float]
    unit: str = ""


Request = (
    EnergyBalance
    | JointReaction
    | MotionEffort
    | CouplerEffort
    | PointKinematics
    | JointCoordinate
    | ElementOutput
    | ExpressionOutput
)


def _frame_matrix(system: System, k, frame: str) -> np.ndarray:
    return system.frame_axes(frame, k)


def _frame_series(system: System, trajectory, frame: str) -> np.ndarray | None:
    if frame == "ground":
        return None
    return np.array(
        [
            system.frame_axes(frame, system.kin(q, None, t))
            for q, t in zip(trajectory.q, trajectory.time)
        ]
    )


def _gatherer(system: System, req) -> tuple[Gatherer, float]:
    """Rows of a joint (with the motions driving it) or of a motion, on body 1 (or minus
    on body 2 when body 1 is ground: action and reaction)."""
    if isinstance(req, JointReaction):
        j = system.mechanism.joints[req.joint]
        owners = {req.joint} | {
            m.name for m in system.mechanism.motions.values() if m.joint == req.joint
        }
        # on a flexible body the joint's rows act on the node body at its point
        body, other = (system.body_point(name, j.at)[0] for name in (j.body1, j.body2))
    else:
        measure = _equation(system, req.motion).terms[0][1]
        owners, body, other = {req.motion}, measure.bi, measure.bj
    return _on_body1(system, owners, body, other)


def _on_body1(system: System, owners: set[str], body: int, other: int) -> tuple[Gatherer, float]:
    if body == system.nb:
        return Gatherer(system, owners, other), -1.0
    return Gatherer(system, owners, body), 1.0


def _reaction_columns(system, trajectory, req: JointReaction, gatherer, sign):
    j = system.mechanism.joints[req.joint]
    body = j.body2 if sign < 0 else j.body1
    _, local = system.body_point(body, j.at)
    return reaction_series(
        system, trajectory, gatherer, local, sign, _frame_series(system, trajectory, req.frame)
    )


def _effort_columns(system, trajectory, req: MotionEffort, gatherer, sign):
    measure = _equation(system, req.motion).terms[0][1]
    return effort_series(system, trajectory, gatherer, measure, sign)


def _equation(system: System, owner: str) -> CoordinateEquation:
    """The coordinate equation of a motion, coupler or gear named `owner`."""
    return next(
        c for c in system.coordinates if isinstance(c, CoordinateEquation) and c.owner == owner
    )


def _coupler_terms(system: System, joint: str) -> list[tuple[str, AngleMeasure | TravelMeasure]]:
    """(column, measure) of a coupler's input and output joint coordinates."""
    equation = _equation(system, joint)
    return [("input", equation.terms[0][1]), ("output", equation.terms[1][1])]


def _coupler_gatherers(system: System, req: CouplerEffort) -> list[tuple[Gatherer, float]]:
    return [
        _on_body1(system, {req.joint}, m.bi, m.bj) for _, m in _coupler_terms(system, req.joint)
    ]


def _coupler_columns(system, trajectory, req: CouplerEffort, gatherers) -> dict[str, np.ndarray]:
    return {
        column: effort_series(system, trajectory, g, m, sign)["value"]
        for (column, m), (g, sign) in zip(_coupler_terms(system, req.joint), gatherers)
    }


def _in_frame(system, k, values: dict[str, float], frame: str) -> dict[str, float]:
    """Vector outputs of an element turned into `frame` axes: forces and torques (fx fy fz,
    tx ty tz), eccentricities (ex ey ez) by their components; contact points (px py pz)
    measured from the frame's origin too."""
    if frame == "ground":
        return values
    axes = _frame_matrix(system, k, frame).T
    out = dict(values)
    for names in (FORCE, TORQUE, ("ex", "ey", "ez"), ("px", "py", "pz")):
        if all(n in values for n in names):
            v = np.array([values[n] for n in names])
            if names[0] == "px":
                v = v - system.frame_origin(frame, k)
            out.update(zip(names, axes @ v))
    return out


def _point_series(system: System, trajectory, req: PointKinematics) -> dict[str, np.ndarray]:
    """Point kinematics at all recorded times at once (ground axes), then into `frame`."""
    b, s = system.point(req.point)
    n = len(trajectory)
    if b == system.nb:
        v = np.tile(s, (n, 1)) if req.quantity == "position" else np.zeros((n, 3))
    else:
        sl = slice(7 * b, 7 * b + 7)
        x, xd = trajectory.stacked("q")[:, sl], trajectory.stacked("qd")[:, sl]
        if req.quantity == "position":
            v = x[:, :3] + rotate(x[:, 3:], s)
        elif req.quantity == "velocity":
            v = xd[:, :3] + np.einsum("nij,nj->ni", d_rotate(x[:, 3:], s), xd[:, 3:])
        else:
            xdd = trajectory.stacked("qdd")[:, sl]
            v = (
                xdd[:, :3]
                + np.einsum("nij,nj->ni", d_rotate(x[:, 3:], s), xdd[:, 3:])
                + 2.0 * rotate(xd[:, 3:], s)
            )
    if req.frame != "ground":
        kins = [system.kin(q, None, t) for q, t in zip(trajectory.q, trajectory.time)]
        if req.quantity == "position":  # measured from the frame's origin
            v = v - np.array([system.frame_origin(req.frame, k) for k in kins])
        axes = np.array([system.frame_axes(req.frame, k) for k in kins])
        v = np.einsum("nji,nj->ni", axes, v)
    return dict(zip("xyz", v.T))


def evaluate_requests(system: System, trajectory, requests) -> dict[str, np.ndarray]:
    """Columns `REQUEST.COMPONENT` (SI) at the recorded times, in request order."""
    loads = {
        r.name: [_gatherer(system, r)]
        for r in requests
        if isinstance(r, (JointReaction, MotionEffort))
    }
    loads |= {
        r.name: _coupler_gatherers(system, r) for r in requests if isinstance(r, CouplerEffort)
    }
    stepwise = [r for r in requests if isinstance(r, (ElementOutput, ExpressionOutput))]
    gathered = bool(loads) and not stepwise and len(trajectory) > 0
    if gathered and system.packed_constraints() is not None:
        gather_in_batches(system, trajectory, [g for gs in loads.values() for g, _ in gs])
    else:
        gathered = False
    per_request: dict[str, dict[str, list[float]]] = {r.name: {} for r in requests}
    failed: dict[str, SolverFailure] = {}
    if stepwise or (loads and not gathered):
        _row_by_row(system, trajectory, stepwise, {} if gathered else loads, per_request, failed)
    columns = per_request | _whole_columns(system, trajectory, requests, loads)
    channels = {
        f"{name}.{comp}": np.asarray(values, dtype=float)
        for name, comps in columns.items()  # every request, in request order
        for comp, values in comps.items()
    }
    if failed:
        raise partial_columns(channels, failed, columns, len(trajectory))
    return channels


def _row_by_row(system: System, trajectory, stepwise, loads, per_request, failed) -> None:
    """The stepwise requests' values row by row into `per_request` (a request failing at a
    row stops there: `failed`), and the multipliers of the rows into the `loads` gatherers."""
    for i, t in enumerate(trajectory.time):
        system.restore_snapshot(trajectory.references[i])  # as the solver had it then
        k = system.kin(trajectory.q[i], trajectory.qd[i], t)
        if loads:
            jac = system.phi_q(k)
            for gatherers in loads.values():
                for gatherer, _ in gatherers:
                    gatherer.gather(jac, trajectory.lam[i])
        view = system.view(k, trajectory.lam[i])  # elements reading reactions see them
        # equilibria: force elements report what the solver used, without velocities
        rest = (
            system.view(system.kin(trajectory.q[i], None, t), trajectory.lam[i])
            if trajectory.at_rest
            else view
        )
        for req in stepwise:
            seen = rest if isinstance(req, ElementOutput) else view
            if req.name in failed:
                continue
            try:
                values = _evaluate(system, k, req, seen)
            except SolverFailure as failure:  # this column stops here, the others go on
                failed[req.name] = failure
                continue
            for comp, value in values.items():
                per_request[req.name].setdefault(comp, []).append(float(value))


def _whole_columns(system: System, trajectory, requests, loads) -> dict[str, dict]:
    """The requests evaluated on whole columns at once, in request order, energy balances
    after the others."""
    series: dict[str, dict[str, np.ndarray]] = {}
    for req in requests:
        if isinstance(req, PointKinematics):
            series[req.name] = _point_series(system, trajectory, req)
        elif isinstance(req, JointReaction):
            series[req.name] = _reaction_columns(system, trajectory, req, *loads[req.name][0])
        elif isinstance(req, MotionEffort):
            series[req.name] = _effort_columns(system, trajectory, req, *loads[req.name][0])
        elif isinstance(req, CouplerEffort):
            series[req.name] = _coupler_columns(system, trajectory, req, loads[req.name])
        elif isinstance(req, FlexibleOutput):
            series[req.name] = _flexible_columns(system, trajectory, req)
        elif isinstance(req, JointCoordinate) and len(trajectory):
            value = coordinate_column(system, trajectory, req.joint, req.quantity)
            series[req.name] = {"value": value}
    for req in requests:
        if isinstance(req, EnergyBalance):
            series[req.name] = energy_columns(
                system, trajectory, functools.partial(_row_views, system, trajectory)
            )
    return series


def _row_views(system: System, trajectory, i: int):
    """(k, view) of row i as requests read it: the solver's snapshot restored; the force
    elements of equilibria evaluated without velocities."""
    system.restore_snapshot(trajectory.references[i])
    q, qd, lam = trajectory.q[i], trajectory.qd[i], trajectory.lam[i]
    k = system.kin(q, qd, trajectory.time[i])
    rest = system.kin(q, np.zeros_like(qd), trajectory.time[i]) if trajectory.at_rest else k
    return k, system.view(rest, lam)


def _evaluate(system, k, req, view) -> dict[str, float]:
    if isinstance(req, ElementOutput):
        element = system.mechanism.forces[req.element]
        values = _in_frame(system, k, element.output(view), req.frame)
        if req.components is not None:
            values = {column: values[key] for column, key in req.components}
        if not element.active:  # switched off (by an event): it carries nothing
            values = dict.fromkeys(values, 0.0)
        return values
    return {"value": req.function(k.t, view)}


def _flexible_columns(system: System, trajectory, req: FlexibleOutput) -> dict[str, np.ndarray]:
    """Modal coordinates or a node's deformation (body axes) at all recorded times; a body
    built rigid (flexibility switched off) has no modes and no deformation."""
    attached = next((a for a in system.flexible if a.name == req.body), None)
    if attached is None:
        zero = np.zeros(len(trajectory))
        return {} if req.quantity == "modes" else dict.fromkeys("xyz", zero)
    start = 7 * system.nb + attached.offset
    zeta = np.array([q[start : start + attached.body.n] for q in trajectory.q])
    zeta = zeta.reshape(len(trajectory), attached.body.n)
    if req.quantity == "modes":
        return {f"q{j + 1}": zeta[:, j] for j in range(attached.body.n)}
    if req.point is None:
        raise ValueError(f"request {req.name}: a deformation needs a point")
    row = attached.nodes.index(system.point(req.point)[0])
    return dict(zip("xyz", (zeta @ attached.body.component.phi[row].T).T))
