"""Mechanism definitions: bodies, points, joints, motions and force elements (all SI).

Everything is given in the global frame at the design (assembly) position, as CAD gives it;
body axes coincide with global axes there. ``ground`` is the fixed body and is implicit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

import numpy as np

__all__ = [
    "GROUND",
    "JOINT_TYPES",
    "Body",
    "FlexibleBody",
    "Joint",
    "Mechanism",
    "Motion",
    "Point",
    "TimeFunction",
]

GROUND = "ground"
JOINT_TYPES = (
    "fixed",
    "revolute",
    "spherical",
    "cylindrical",
    "prismatic",
    "universal",
    "planar",
    "screw",
    "inline",
    "inplane",
    "parallel",
    "perpendicular",
    "orientation",
    "coupler",
    "gear",
    "point_on_curve",
)
_T = TypeVar("_T")


class TimeFunction(Protocol):
    """A prescribed coordinate f(t) with its exact rates (SI units of the coordinate)."""

    def value(self, t: float) -> float: ...
    def rate(self, t: float) -> float: ...
    def accel(self, t: float) -> float: ...


@dataclass(frozen=True)
class Body:
    """A rigid body: mass (kg), centre of mass (m) and inertia about it (kg*m^2, global axes)."""

    name: str
    mass: float
    cm: tuple[float, float, float]
    inertia: np.ndarray  # (3, 3)


@dataclass(frozen=True)
class FlexibleBody:
    """A modal body (mechlib.flexible): its `component` placed with the FE model's origin
    at `at` (m, global, FE axes = global axes at design). `node_bodies` names the massless
    body standing for each kept node (by node number): points of the flexible body must be
    at one of these nodes. `linear_limit`: the share of its size its nodes may deform by
    before a warning (mechlib.flexible.guards)."""

    name: str
    component: Any  # mechlib.flexible.ModalComponent
    at: tuple[float, float, float]
    node_bodies: dict[int, str]
    linear_limit: float = 0.1

    def node_position(self, node_id: int) -> np.ndarray:
        """Undeformed global position (m) of a kept node."""
        comp = self.component
        return np.asarray(self.at) + comp.origin + comp.positions[comp.node(node_id)]


@dataclass(frozen=True)
class Point:
    """A named point fixed on a body, at `at` (m, global, design position)."""

    name: str
    body: str
    at: tuple[float, float, float]


@dataclass(frozen=True)
class Joint:
    """A joint between `body1` and `body2` (reactions are on body1 from body2).

    `axis`: revolute/cylindrical/prismatic/screw/inline/parallel; `axes`: universal
    (a1 on body1, a2 on body2) and perpendicular; `normal`: planar/inplane; `pitch` (m per
    revolution): screw; `joints` + `ratio`: coupler/gear (coordinate of joints[1] = ratio *
    coordinate of joints[0]);
    `curve` (points, global at design, m) + `interpolation`: point_on_curve.
    """

    name: str
    type: str
    body1: str = GROUND
    body2: str = GROUND
    at: tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: tuple[float, float, float] | None = None
    axes: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None
    normal: tuple[float, float, float] | None = None
    pitch: float | None = None
    joints: tuple[str, str] | None = None
    ratio: float = 1.0
    curve: tuple[tuple[float, float, float], ...] | None = None
    interpolation: str = "cubic"

    def required(self, value: _T | None, key: str) -> _T:
        """`value`, the field `key` of this joint, which its type cannot do without."""
        if value is None:
            raise ValueError(f"joint {self.name}: a {self.type} joint needs `{key}`")
        return value


@dataclass(frozen=True)
class Motion:
    """A joint coordinate prescribed in time: `coordinate` is `angle` (rad) or `travel` (m)."""

    name: str
    joint: str
    function: TimeFunction
    coordinate: str | None = None


@dataclass
class Mechanism:
    """A mechanism under construction; `mechlib.solve` compiles and solves it."""

    name: str = "mechanism"
    gravity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    bodies: dict[str, Body] = field(default_factory=dict)
    points: dict[str, Point] = field(default_factory=dict)
    joints: dict[str, Joint] = field(default_factory=dict)
    motions: dict[str, Motion] = field(default_factory=dict)
    forces: dict[str, Any] = field(default_factory=dict)
    frames: dict[str, tuple[str, np.ndarray, tuple]] = field(default_factory=dict)
    flexible: dict[str, FlexibleBody] = field(default_factory=dict)
    plane: str | None = None  # xy, yz or xz: a planar mechanism (mechlib.system.planar)
    aliases: dict[str, str] = field(default_factory=dict)  # another name of a body

    def add_alias(self, alias: str, body: str) -> None:
        """`alias` names `body` wherever a body is named: a point given on it at any place is
        carried by `body` rigidly. On a flexible body's node body (`NAME.node<id>`) this is
        a rigid arm from that node (an offset attachment, seed 003 3.4.2.1)."""
        if body not in self.bodies:
            raise ValueError(f"alias {alias}: no body {body}")
        if alias in self.bodies:
            raise ValueError(f"alias {alias}: already a body's name")
        self.aliases[alias] = body

    def owner(self, body: str) -> str:
        """The body `body` stands for: an alias's body, and a node body's flexible body."""
        body = self.aliases.get(body, body)
        for name, flexible in self.flexible.items():
            if body in flexible.node_bodies.values():
                return name
        return body

    def add_body(self, name: str, *, mass: float, cm, inertia) -> Body:
        """Add a body; `inertia` is [Ixx, Iyy, Izz], 6 entries (+ Ixy, Ixz, Iyz) or 3x3."""
        body = Body(name, float(mass), _vec(cm), inertia_matrix(inertia))
        self.bodies[name] = body
        return body

    def add_flexible_body(
        self, name: str, component: Any, *, at=(0.0, 0.0, 0.0), linear_limit: float = 0.1
    ) -> FlexibleBody:
        """Add a modal body (a `ModalComponent`, FE origin placed `at`, m): its frame as a body
        with its rigid mass properties, and a massless body `NAME.node<id>` per kept node;
        `linear_limit`: the share of its size its nodes may deform by without a warning."""
        origin = np.asarray(_vec(at)) + component.origin
        self.bodies[name] = Body(
            name, float(component.mass), _vec(origin), component.invariants.I7.copy()
        )
        nodes = {}
        for node_id, position in zip(component.node_ids, component.positions):
            nodes[int(node_id)] = f"{name}.node{int(node_id)}"
            self.bodies[nodes[int(node_id)]] = Body(
                nodes[int(node_id)], 0.0, _vec(origin + position), np.zeros((3, 3))
            )
        flexible = FlexibleBody(name, component, _vec(at), nodes, float(linear_limit))
        self.flexible[name] = flexible
        return flexible

    def add_point(self, name: str, *, body: str, at) -> Point:
        point = Point(name, body, _vec(at))
        self.points[name] = point
        return point

    def add_joint(self, name: str, type: str, *, bodies: tuple[str, str], **keys) -> Joint:
        """Add a joint of one of JOINT_TYPES; vectors are normalised here."""
        if type not in JOINT_TYPES:
            raise ValueError(f"unknown joint type '{type}'")
        for key in ("axis", "normal"):
            if keys.get(key) is not None:
                keys[key] = _unit(keys[key])
        if keys.get("axes") is not None:
            keys["axes"] = tuple(_unit(a) for a in keys["axes"])
        if keys.get("at") is not None:
            keys["at"] = _vec(keys["at"])
        if keys.get("joints") is not None:
            keys["joints"] = tuple(keys["joints"])
        if keys.get("curve") is not None:
            keys["curve"] = tuple(_vec(p) for p in keys["curve"])
        joint = Joint(name, type, bodies[0], bodies[1], **keys)
        self.joints[name] = joint
        return joint

    def add_frame(self, name: str, *, body: str, x, y, at=(0.0, 0.0, 0.0)) -> None:
        """A named frame on `body`: origin `at` (m), axes x, y (z = x cross y) at design."""
        ex = np.asarray(_unit(x))
        ey = np.asarray(y, dtype=float) - (np.asarray(y, dtype=float) @ ex) * ex
        ey = np.asarray(_unit(ey))
        self.frames[name] = (body, np.column_stack([ex, ey, np.cross(ex, ey)]), _vec(at))

    def add_motion(
        self, name: str, *, joint: str, function: TimeFunction, coordinate: str | None = None
    ) -> Motion:
        motion = Motion(name, joint, function, coordinate)
        self.motions[name] = motion
        return motion

    def add_force(self, element: Any) -> Any:
        """Add a force element (see mechlib.elements.forces); it carries its own `name`."""
        self.forces[element.name] = element
        return element


def inertia_matrix(values) -> np.ndarray:
    """3x3 inertia tensor (kg*m^2) from 3 principal-axis entries, 6 entries or a 3x3 array.

    Six entries are [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] with Ixy the tensor entry
    (= -integral of x*y dm), as SPEC 1.2 defines.
    """
    arr = np.asarray(values, dtype=float)
    if arr.shape == (3, 3):
        return arr.copy()
    if arr.shape == (3,):
        return np.diag(arr)
    if arr.shape == (6,):
        ixx, iyy, izz, ixy, ixz, iyz = arr
        return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    raise ValueError(f"inertia needs 3, 6 or 3x3 values, got shape {arr.shape}")


def _vec(v) -> tuple[float, float, float]:
    arr = np.asarray(v, dtype=float).reshape(3)
    return (float(arr[0]), float(arr[1]), float(arr[2]))


def _unit(v) -> tuple[float, float, float]:
    arr = np.asarray(v, dtype=float).reshape(3)
    n = np.linalg.norm(arr)
    if n == 0.0:
        raise ValueError("zero-length axis")
    return _vec(arr / n)
