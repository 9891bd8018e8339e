"""The mechanism in 3-D at one output time, as plotly trace dictionaries (`loads draw --html`).

Drawn as the PNG pictures draw it (`loadcases.draw.render`), in space: bodies are closed
outlines through their joint and point markers (ordered once, round their centre in the
mechanism's main plane), joints open circles named (coincident joints share one label),
points small dots, springs zigzags, wires dashed, seals thick translucent lines, contacts a
circle (roller, sphere; in the main plane) with the plane or profile it runs on. Reaction
forces are arrows from the joint point, on the joint's body 1 from its body 2, of length
proportional to the force's magnitude: the largest over the run and the joints drawn is
`ARROW_SHARE` of the mechanism's size. Text from the case file is HTML-escaped: plotly shows
it as written and never reads it as markup. Positions in the page are rounded to 1 µm.

Every label keeps its text on every frame (plotly.js draws a 3-D label whose text changes
during an animation at a fraction of its size): joints are grouped once, as those within
0.1 mm of each other all along the run, and force magnitudes are hover texts and the
slider's current value (`force_summary`), not labels.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from loadcases.draw.render import projection
from loadcases.draw.shapes import outline_order, zigzag
from loadcases.draw.trajectory import Trajectory

__all__ = ["ARROW_SHARE", "Scene", "force_summary", "frame_traces", "scene_of"]

ARROW_SHARE = 0.3
"""length of the largest force arrow, as a share of the mechanism's size."""
_HEAD_SHARE = 0.12  # arrowhead length, as a share of the largest arrow
_DECIMALS = 6  # m: 1 µm, far below what a screen shows
_COINCIDENT = 1e-4  # m: joints closer than this all along the run share one label
_CIRCLE_SEGMENTS = 36
_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2")
_CONTACT = "crimson"
_FORCE = "#d0021b"


@dataclass(frozen=True)
class Scene:
    """What stays the same on every frame: `outlines` body -> its markers in outline order,
    `plane` (2, 3) two unit vectors of the mechanism's main plane, `size` (m) the largest
    extent of the markers over the run, `metres_per_newton` the force arrows' scale,
    `joint_groups` the joints labelled together (coincident all along the run)."""

    outlines: dict[str, list[str]]
    plane: np.ndarray
    size: float
    metres_per_newton: float
    joint_groups: list[list[str]]

    @property
    def head(self) -> float:
        """Arrowhead length (m)."""
        return _HEAD_SHARE * ARROW_SHARE * self.size


def scene_of(traj: Trajectory) -> Scene:
    """The frame-independent part of the drawing of a trajectory (with at least one time)."""
    plane, _ = projection(traj, "auto")
    outlines = {}
    for body, markers in traj.skeleton.bodies.items():
        if body != "ground":
            at_start = np.array([traj.positions[m][0] for m in markers]) @ plane.T
            outlines[body] = [markers[i] for i in outline_order(at_start)]
    cloud = np.concatenate([p for p in traj.positions.values() if len(p)])
    size = max(float(np.max(np.ptp(cloud, axis=0))), 1e-3)
    largest = max(
        (float(np.max(np.linalg.norm(f, axis=1))) for f in traj.reactions.values()), default=0.0
    )
    scale = ARROW_SHARE * size / largest if largest > 0.0 else 0.0
    return Scene(outlines, np.asarray(plane, float), size, scale, _joint_groups(traj))


def _joint_groups(traj: Trajectory) -> list[list[str]]:
    """Joints in groups of those within `_COINCIDENT` of the group's first all along the run."""
    groups: list[list[str]] = []
    for name, marker in traj.skeleton.joints.items():
        path = traj.positions[marker]
        for group in groups:
            first = traj.positions[traj.skeleton.joints[group[0]]]
            if np.max(np.linalg.norm(path - first, axis=1)) < _COINCIDENT:
                group.append(name)
                break
        else:
            groups.append([name])
    return groups


def _xyz(points: Sequence[np.ndarray | None]) -> dict[str, list]:
    """x, y, z lists of a polyline (m, rounded); None breaks the line."""
    cols: dict[str, list] = {"x": [], "y": [], "z": []}
    for p in points:
        for axis, c in zip("xyz", range(3)):
            cols[axis].append(None if p is None else round(float(p[c]), _DECIMALS))
    return cols


def _lines(points: list, name: str, colour: str, width: float, **extra) -> dict:
    line = {"color": colour, "width": width} | extra.pop("line", {})
    return {
        "type": "scatter3d",
        "mode": "lines",
        "name": name,
        "line": line,
        "hoverinfo": "skip",
        **_xyz(points),
        **extra,
    }


def _labels(places: list[np.ndarray], texts: list[str], name: str, colour: str, **extra) -> dict:
    return {
        "type": "scatter3d",
        "mode": "text",
        "name": name,
        "text": texts,
        "textfont": {"color": colour, "size": 11},
        "hoverinfo": "text",
        **_xyz(places),
        **extra,
    }


def _bodies(traj: Trajectory, scene: Scene, k: int) -> list[dict]:
    traces = []
    for n, (body, markers) in enumerate(scene.outlines.items()):
        ring = [traj.positions[m][k] for m in markers]
        traces.append(_lines(ring, html.escape(body), _COLOURS[n % len(_COLOURS)], 5))
    return traces


def _links(traj: Trajectory, scene: Scene, k: int) -> list[dict]:
    """Springs, wires and seals (one trace each), and their names."""
    drawn: dict[str, list] = {"spring": [], "wire": [], "seal": []}
    places, names = [], []
    for name, kind, a, b in traj.skeleton.links:
        pa, pb = traj.positions[a][k], traj.positions[b][k]
        if kind == "spring":
            side = np.cross(np.cross(*scene.plane), pb - pa)
            norm = float(np.linalg.norm(side))
            side = side / norm if norm > 1e-12 else scene.plane[0]
            drawn[kind] += [*zigzag(pa, pb, side), None]
        else:
            drawn[kind] += [pa, pb, None]
        places.append((pa + pb) / 2)
        names.append(html.escape(name))
    return [
        _lines(drawn["spring"], "springs", "green", 3),
        _lines(drawn["wire"], "wires", "black", 3, line={"dash": "dash"}),
        _lines(drawn["seal"], "seals", "dimgray", 12, opacity=0.35),
        _labels(places, names, "spring, wire and seal names", "darkgreen"),
    ]


def _contacts(traj: Trajectory, scene: Scene, k: int) -> list[dict]:
    """Contact circles, planes and profiles (one trace) and the contacts' names."""
    drawn: list = []
    places, names = [], []
    angles = np.linspace(0.0, 2.0 * np.pi, _CIRCLE_SEGMENTS + 1)
    for name, kind, markers, radius in traj.skeleton.contacts:
        pts = [traj.positions[m][k] for m in markers]
        if kind == "circle":
            ring = pts[0] + radius * np.outer(np.cos(angles), scene.plane[0])
            drawn += [*(ring + radius * np.outer(np.sin(angles), scene.plane[1])), None]
            places.append(pts[0])
            names.append(html.escape(name))
        else:
            drawn += [*pts, *(pts[:1] if kind == "plane" else []), None]
    return [
        _lines(drawn, "contacts", _CONTACT, 3),
        _labels(places, names, "contact names", _CONTACT),
    ]


def _joints_and_points(traj: Trajectory, scene: Scene, k: int) -> list[dict]:
    """Points (gray dots), joints (open circles, coincident ones named together), body names."""
    sk = traj.skeleton
    points = [traj.positions[m][k] for m in sk.points.values()]
    joints = [traj.positions[sk.joints[group[0]]][k] for group in scene.joint_groups]
    names = [", ".join(html.escape(j) for j in group) for group in scene.joint_groups]
    centres = [
        np.mean([traj.positions[m][k] for m in markers], axis=0)
        for markers in scene.outlines.values()
    ]
    marker = {"size": 5, "color": "white", "line": {"color": "black", "width": 2}}
    return [
        {
            "type": "scatter3d",
            "mode": "markers",
            "name": "points",
            "marker": {"size": 2.5, "color": "gray"},
            "text": [html.escape(p) for p in sk.points],
            "hoverinfo": "text",
            **_xyz(points),
        },
        _labels(joints, names, "joints", "black")
        | {"mode": "markers+text", "marker": marker, "textposition": "top right"},
        _labels(
            centres, [f"<i>{html.escape(b)}</i>" for b in scene.outlines], "body names", "dimgray"
        ),
    ]


def _arrows(traj: Trajectory, scene: Scene, k: int) -> list[dict]:
    """Reaction force arrows: shafts, heads (cones at the tips) and magnitudes."""
    shafts: list = []
    tips, heads, hover = [], [], []
    for joint, force in traj.reactions.items():
        start = traj.positions[traj.skeleton.joints[joint]][k]
        f = force[k]
        magnitude = float(np.linalg.norm(f))
        tip = start + scene.metres_per_newton * f
        shafts += [start, tip, None]
        tips.append(tip)
        heads.append(f / magnitude * scene.head if magnitude > 0.0 else np.zeros(3))
        hover.append(f"{html.escape(joint)}: {magnitude:.4g} N")
    cones = {
        "type": "cone",
        "name": "force arrowheads",
        "anchor": "tip",
        "sizemode": "raw",
        "sizeref": 1.0,
        "colorscale": [[0.0, _FORCE], [1.0, _FORCE]],
        "showscale": False,
        "hoverinfo": "skip",
        **_xyz(tips),
        **{c: [round(float(h[i]), _DECIMALS) for h in heads] for i, c in enumerate("uvw")},
    }
    return [
        _lines(shafts, "reaction forces", _FORCE, 6),
        cones,
        _labels(
            tips,
            [html.escape(j) for j in traj.reactions],
            "reaction force names",
            _FORCE,
            textposition="top center",
            hovertext=hover,
        ),
    ]


def force_summary(traj: Trajectory, k: int) -> str:
    """The magnitudes of the reaction forces drawn, at output index k (N)."""
    return ", ".join(
        f"{html.escape(j)} {float(np.linalg.norm(f[k])):.4g} N" for j, f in traj.reactions.items()
    )


def _ghost(traj: Trajectory, scene: Scene) -> list[dict]:
    """The drawn (design) geometry as one grey dashed trace, where the run starts away
    from it (the same in every frame)."""
    if not traj.assembled_off_drawing():
        return []
    points: list[np.ndarray | None] = []
    for markers in scene.outlines.values():
        points += [traj.drawn(m) for m in markers] + [None]
    return [_lines(points, "as drawn", "gray", 2, line={"dash": "dash"}, opacity=0.5)]


def frame_traces(traj: Trajectory, scene: Scene, k: int) -> list[dict]:
    """Every trace of the drawing at output index k, always the same traces in one order
    (an animation updates trace i of each frame): the drawing's ghost where the run starts
    away from it; the force arrows only with reactions."""
    traces = (
        _ghost(traj, scene)
        + _bodies(traj, scene, k)
        + _links(traj, scene, k)
        + _contacts(traj, scene, k)
        + _joints_and_points(traj, scene, k)
    )
    if traj.reactions:
        traces += _arrows(traj, scene, k)
    return traces
