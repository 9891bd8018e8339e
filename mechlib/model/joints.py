"""Joints as labelled constraint primitives (Haug's library of joint equations).

`expand_joint` turns one joint into rows of primitive equations, each with a label that
names the joint and the direction it stops ("hinge: rotation about x"), so that redundancy,
toggle positions and failures are reported by name, never by row index.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechlib.model.mechanism import Joint

__all__ = [
    "ROTATIONAL",
    "TRANSLATIONAL",
    "JointFrame",
    "Row",
    "direction_name",
    "expand_joint",
    "joint_frame",
]

# joints with an angle / a travel coordinate about / along their axis. An inline joint
# (point on a line) leaves 3 rotations and the slide free: its angle is the rotation about
# its axis, exact when its bodies turn about that axis only (a hinge line built from
# spherical + inline), else the projected angle of body 1's joint triad
ROTATIONAL = ("revolute", "cylindrical", "screw", "inline")
TRANSLATIONAL = ("prismatic", "cylindrical", "screw", "inline")
_ALIGNED = 1.0 - 1e-9


@dataclass(frozen=True)
class Row:
    """One primitive equation: `kind` in spherical|dot1|dot2, its body-fixed data, its label.

    spherical: (s_i, s_j) points; dot1: (u on body1, v on body2); dot2: (v on body2, s_i, s_j).
    A spherical row stands for 3 equations (translation x, y, z).
    """

    kind: str
    data: tuple
    label: str


@dataclass(frozen=True)
class JointFrame:
    """Orthonormal joint triad at the design position: f, g perpendicular to the axis h."""

    f: np.ndarray
    g: np.ndarray
    h: np.ndarray


def joint_frame(axis) -> JointFrame:
    """A right-handed triad (f, g, h) with h = axis; f taken from the least aligned global axis."""
    h = np.asarray(axis, dtype=float)
    with np.errstate(over="ignore"):
        length = float(np.linalg.norm(h))
    if not (np.isfinite(length) and length > 0.0):
        raise ValueError(f"a joint axis must be a finite, non-zero vector of moderate size: {axis}")
    h = h / length
    for e in np.eye(3):
        if abs(e @ h) < 0.9:
            f = e - (e @ h) * h
            break
    f = f / np.linalg.norm(f)
    return JointFrame(f, cross(h, f), h)


def cross(u, v) -> np.ndarray:
    """u x v of two 3-vectors: np.cross's products and differences (the same values to the
    last bit), without its axis handling (15 us a call; a model's joints call it often)."""
    u1, u2, u3 = (float(c) for c in u)
    v1, v2, v3 = (float(c) for c in v)
    return np.array([u2 * v3 - u3 * v2, u3 * v1 - u1 * v3, u1 * v2 - u2 * v1])


def direction_name(v: np.ndarray) -> str:
    """`x`, `y`, `z` when v is along a global axis (either sense), else the rounded vector."""
    v = np.asarray(v, dtype=float)
    v = v / np.linalg.norm(v)
    for name, e in zip("xyz", np.eye(3)):
        if abs(v @ e) > _ALIGNED:
            return name
    return "[" + ", ".join(f"{c:.3g}" for c in v) + "]"


def _dot1(joint: str, u, v) -> Row:
    return Row(
        "dot1",
        (np.asarray(u), np.asarray(v)),
        f"{joint}: rotation about {direction_name(cross(u, v))}",
    )


def _dot2(joint: str, v, si, sj) -> Row:
    return Row("dot2", (np.asarray(v), si, sj), f"{joint}: translation along {direction_name(v)}")


def _sph(joint: str, si, sj) -> Row:
    return Row("spherical", (si, sj), f"{joint}: translation")


def _axes(joint: Joint) -> tuple[np.ndarray, np.ndarray]:
    """The axes (a1 on body1, a2 on body2) of a universal or perpendicular joint."""
    a1, a2 = joint.required(joint.axes, "axes")
    return np.asarray(a1), np.asarray(a2)


def expand_joint(joint: Joint, s1: np.ndarray, s2: np.ndarray) -> list[Row]:
    """Primitive rows of a geometric joint; s1, s2: the joint point in body1/body2 axes (m).

    Coupler, gear and the screw's travel-angle relation are coordinate equations, built
    by `mechlib.kinematics.coordinates`, and a point on a curve has its own
    (`mechlib.kinematics.curve_joint`);
    this returns their geometric part only (none for couplers and curves).
    """
    n = joint.name
    t = joint.type
    if t in ("coupler", "gear", "point_on_curve"):
        return []
    if t == "spherical":
        return [_sph(n, s1, s2)]
    if t == "universal":
        a1, a2 = _axes(joint)
        return [_sph(n, s1, s2), _dot1(n, a1, a2)]
    if t == "perpendicular":
        a1, a2 = _axes(joint)
        return [_dot1(n, a1, a2)]
    if t in ("planar", "inplane"):
        fr = joint_frame(joint.normal)
        rows = [_dot2(n, fr.h, s1, s2)]
        if t == "planar":
            rows = [_dot1(n, fr.f, fr.h), _dot1(n, fr.g, fr.h)] + rows
        return rows
    fr = joint_frame(joint.axis if joint.axis is not None else (0.0, 0.0, 1.0))
    return [row for part in _PARTS[t] for row in _part(part, n, fr, s1, s2)]


# the rows of the joints about an axis, in order, by part (only a joint's own are built)
_PARTS = {
    "revolute": ("point", "parallel"),
    "fixed": ("point", "parallel", "twist"),
    "cylindrical": ("parallel", "on_line"),
    "screw": ("parallel", "on_line"),
    "prismatic": ("parallel", "on_line", "twist"),
    "inline": ("on_line",),
    "parallel": ("parallel",),
    "orientation": ("parallel", "twist"),
}


def _part(part: str, n: str, fr: JointFrame, s1: np.ndarray, s2: np.ndarray) -> list[Row]:
    """The rows of one part of joint `n` about its triad `fr`: its point (`point`), its
    axis kept parallel (`parallel`), no twist about it (`twist`), on its line (`on_line`)."""
    if part == "point":
        return [_sph(n, s1, s2)]
    if part == "parallel":
        return [_dot1(n, fr.f, fr.h), _dot1(n, fr.g, fr.h)]
    if part == "twist":
        return [_dot1(n, fr.f, fr.g)]
    return [_dot2(n, fr.f, s1, s2), _dot2(n, fr.g, s1, s2)]
