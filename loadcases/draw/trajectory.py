"""Trajectories of a mechanism's drawing markers: what `loads draw` renders.

A case is built as `loads run` builds it (`loadcases.build.model.build_run`), then solved with
requests of its own instead of the case's: the position of one marker per joint end, named
point, spring end, seal end and contact feature, each fixed on its body, and the reaction
force of the joints asked for. Result files are not touched. `loadcases.draw.render` turns
the trajectory into PNG pictures and animations, `loadcases.draw.page` into a 3-D HTML page.

Marker names are `<what>@<body>` (`hinge@door`, `wire#0@ground`); positions are in m,
global axes. The skeleton keeps each marker's drawn (design) position: the pictures show it
as a ghost where the run starts elsewhere, and the run's branch warnings travel along.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import mechlib as ml
from loadcases.build.model import build_run
from loadcases.inputs.loader import CaseFile, load_case

__all__ = [
    "Skeleton",
    "Trajectory",
    "skeleton_of",
    "solve_trajectory",
    "trajectory_of_file",
]

_PLANE_HALF_SIZE = 0.03
"""m: half size of the square drawn for the plane of a sphere-plane contact."""
_PREFIX = "__draw_"
_DRAWN_TOLERANCE = 1e-6  # of the mechanism's size: a first row this close is the drawing


@dataclass
class Skeleton:
    """What to draw, as markers fixed on bodies.

    `markers`: marker -> (body, position at design, m); `bodies`: body -> its markers;
    `joints`: joint -> marker on body 1; `points`: point -> marker; `links`: (name, kind,
    marker a, marker b) with kind `spring`, `wire` or `seal`; `contacts`: (name, kind,
    markers, radius m) with kind `circle` (roller, sphere, pin: one marker, its centre),
    `plane` (four corner markers) or `profile` (markers of the profile points in order).
    """

    markers: dict[str, tuple[str, tuple[float, float, float]]] = field(default_factory=dict)
    bodies: dict[str, list[str]] = field(default_factory=dict)
    joints: dict[str, str] = field(default_factory=dict)
    points: dict[str, str] = field(default_factory=dict)
    links: list[tuple[str, str, str, str]] = field(default_factory=list)
    contacts: list[tuple[str, str, list[str], float]] = field(default_factory=list)

    def add(self, marker: str, body: str, at, *, outline: bool = True) -> str:
        """Add a marker on `body` at `at` (m); `outline`: part of the body's drawn shape."""
        x, y, z = (float(v) for v in at)
        self.markers[marker] = (body, (x, y, z))
        if outline:
            self.bodies.setdefault(body, []).append(marker)
        return marker


@dataclass
class Trajectory:
    """Marker positions over a run: `time` (n,) s, `positions[marker]` (n, 3) m;
    `reactions[joint]` (n, 3) N: the force on the joint's body 1 from its body 2, global
    axes, for the joints asked for. `case` names the run (the case, or the run of a set)."""

    case: str
    skeleton: Skeleton
    time: np.ndarray
    positions: dict[str, np.ndarray]
    status: str = "ok"
    message: str = ""
    reactions: dict[str, np.ndarray] = field(default_factory=dict)
    branch_warnings: list[str] = field(default_factory=list)

    def index_at(self, t: float) -> int:
        """Index of the output time nearest to `t` (s)."""
        return int(np.argmin(np.abs(self.time - t)))

    def drawn(self, marker: str) -> np.ndarray:
        """The marker's position in the drawn (design) geometry, m."""
        return np.array(self.skeleton.markers[marker][1])

    def assembled_off_drawing(self) -> bool:
        """The first row is not the drawn geometry: some marker moved more than
        _DRAWN_TOLERANCE of the mechanism's size from its design position."""
        if len(self.time) == 0 or not self.positions:
            return False
        drawn = np.array([self.drawn(m) for m in self.positions])
        first = np.array([p[0] for p in self.positions.values()])
        size = max(float(np.ptp(drawn, axis=0).max()), 1e-3)
        return bool(np.abs(first - drawn).max() > _DRAWN_TOLERANCE * size)


def _perpendiculars(normal) -> tuple[np.ndarray, np.ndarray]:
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    d1 = np.cross(n, helper)
    d1 /= np.linalg.norm(d1)
    return d1, np.cross(n, d1)


def _contact(sk: Skeleton, name: str, c) -> None:
    """Markers of one contact: the roller/sphere/pin centre on body 1, the plane or profile
    on body 2."""
    g, (b1, b2) = c.geometry, c.bodies
    centre = sk.add(f"{name}@{b1}", b1, g.center, outline=False)
    sk.contacts.append((name, "circle", [centre], float(g.radius)))
    if g.shape == "sphere_plane":
        d1, d2 = _perpendiculars(g.normal)
        pp, h = np.asarray(g.plane_point), _PLANE_HALF_SIZE
        corners = [pp + h * (s1 * d1 + s2 * d2) for s1, s2 in ((1, 1), (1, -1), (-1, -1), (-1, 1))]
        marks = [sk.add(f"{name}#{i}@{b2}", b2, p, outline=False) for i, p in enumerate(corners)]
        sk.contacts.append((name, "plane", marks, 0.0))
    elif g.shape == "circle_vs_profile":
        marks = [sk.add(f"{name}#{i}@{b2}", b2, p, outline=False) for i, p in enumerate(g.points)]
        sk.contacts.append((name, "profile", marks, 0.0))


def _links(sk: Skeleton, mech) -> None:
    """Springs and wires between their points; seals along their line on body 2."""
    for name, f in mech.forces.items():
        if f.type == "spring":
            ends = [
                sk.add(
                    f"{name}#{i}@{mech.points[p].body}",
                    mech.points[p].body,
                    mech.points[p].at,
                    outline=False,
                )
                for i, p in enumerate(f.points)
            ]
            kind = "wire" if f.tension_only else "spring"
            sk.links.append((name, kind, ends[0], ends[1]))
        elif f.type == "seal":
            body = f.bodies[1]
            a = sk.add(f"{name}#0@{body}", body, f.start, outline=False)
            b = sk.add(f"{name}#1@{body}", body, f.end, outline=False)
            sk.links.append((name, "seal", a, b))


def skeleton_of(mech) -> Skeleton:
    """The markers of a mechanism model (`loadcases.schema` MechanismModel, SI values)."""
    sk = Skeleton()
    for name, j in mech.joints.items():
        at = getattr(j, "at", None)
        bodies = getattr(j, "bodies", None)
        if at is None or bodies is None:
            continue  # couplers and axis-only primitives have no point to draw
        sk.joints[name] = sk.add(f"{name}@{bodies[0]}", bodies[0], at)
        sk.add(f"{name}@{bodies[1]}", bodies[1], at)
    for name, p in mech.points.items():
        sk.points[name] = sk.add(f"{name}@{p.body}", p.body, p.at)
    _links(sk, mech)
    for name, c in mech.contacts.items():
        _contact(sk, name, c)
    return sk


def solve_trajectory(
    cf: CaseFile, *, forces: Sequence[str] = (), name: str | None = None
) -> Trajectory:
    """Solve a loaded case for the positions of every marker of its mechanism and the
    reaction forces of the joints `forces` (names of `skeleton_of(...).joints`).

    The case's own requests are replaced by one point position request per marker and one
    reaction request per joint of `forces`; a failed solve gives the trajectory up to the
    failure (`status`, `message`). `name` names the trajectory (default: the case name).
    A modes analysis has no reaction forces: ValueError when `forces` are asked of one.
    """
    if forces and cf.case.analysis.type == "modes":
        raise ValueError(f"{cf.case.case}: a modes analysis computes no reaction forces")
    sk = skeleton_of(cf.mechanism)
    built = build_run(cf)
    requests: list = []
    for i, (body, at) in enumerate(sk.markers.values()):
        point = f"{_PREFIX}{i}"
        built.mechanism.add_point(point, body=body, at=at)
        requests.append(ml.PointKinematics(point, point, "position"))
    requests += [ml.JointReaction(f"{_PREFIX}force_{j}", j) for j in forces]
    solution = built.solve(requests=requests)

    def columns(request: str, components: Sequence[str]) -> np.ndarray:
        return np.column_stack(
            [solution.channels.get(f"{request}.{c}", np.zeros(0)) for c in components]
        )

    positions = {m: columns(f"{_PREFIX}{i}", "xyz") for i, m in enumerate(sk.markers)}
    reactions = {j: columns(f"{_PREFIX}force_{j}", ("fx", "fy", "fz")) for j in forces}
    return Trajectory(
        name or cf.case.case,
        sk,
        np.asarray(solution.time),
        positions,
        solution.status,
        solution.message,
        reactions,
        [w for w in solution.warnings if w.startswith("assembly branch changed")],
    )


def trajectory_of_file(path: Path | str) -> Trajectory:
    """Load a case file (InputError on bad input) and solve its marker trajectory."""
    return solve_trajectory(load_case(path))
