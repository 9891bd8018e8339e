"""The planes of a planar mechanism and which joints keep their bodies in one.

Light (NumPy only): the loader's checks use it before anything is built. Plane `xy` has
e1 = x, e2 = y, normal n = z; `yz`: y, z, x; `xz`: z, x, y (always n = e1 x e2).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "PLANES",
    "contact_problem",
    "flexible_problem",
    "joint_problem",
    "normal_name",
    "plane_axes",
]

PLANES = ("xy", "yz", "xz")
_AXES = {"xy": (0, 1, 2), "yz": (1, 2, 0), "xz": (2, 0, 1)}  # e1, e2, n
_ALIGNED = 1e-9  # |sin| (or |cos|) below this: along (or across) the normal
_ALONG_NORMAL = ("revolute", "cylindrical")  # `axis` = the normal (a cylindrical: a revolute)
_IN_THE_PLANE = ("prismatic", "inline")  # `axis` in the plane
_AXIS_FREE = ("fixed", "spherical", "orientation", "coupler", "gear")
_NOT_PLANAR = ("screw", "perpendicular", "parallel", "point_on_curve")  # screw: no travel


def plane_axes(plane: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(e1, e2, n) of plane `plane` (xy, yz or xz), global unit vectors, n = e1 x e2."""
    e1, e2, n = (np.eye(3)[i] for i in _AXES[plane])
    return e1, e2, n


def normal_name(plane: str) -> str:
    """The global axis normal to `plane`: z for xy."""
    return "xyz"[_AXES[plane][2]]


def _along(vector, n: np.ndarray) -> bool:
    u = np.asarray(vector, dtype=float)
    return float(np.linalg.norm(np.cross(u, n))) <= _ALIGNED * float(np.linalg.norm(u))


def _across(vector, n: np.ndarray) -> bool:
    u = np.asarray(vector, dtype=float)
    return abs(float(u @ n)) <= _ALIGNED * float(np.linalg.norm(u))


def joint_problem(
    kind: str, plane: str, axis=None, axes=None, normal=None
) -> tuple[str, str] | None:
    """(key, message) when a joint of type `kind` does not keep its bodies' motion in
    `plane` (its axis not along the normal, a slide not in the plane, a type with no
    planar form), else None. A universal joint with one axis along the normal and the
    other in the plane acts as a revolute; a spherical joint acts as one too."""
    n = plane_axes(plane)[2]
    along = f"along the normal of plane {plane} ({normal_name(plane)})"
    if kind in _NOT_PLANAR:
        return "type", f"a {kind} joint has no planar form"
    if kind in _ALONG_NORMAL and axis is not None and not _along(axis, n):
        return "axis", f"the axis of a {kind} joint must be {along}"
    if kind in _IN_THE_PLANE and axis is not None and not _across(axis, n):
        return "axis", f"the axis of a {kind} joint must lie in plane {plane}"
    if kind == "planar" and normal is not None and not _along(normal, n):
        return "normal", f"the normal of a planar joint must be {along}"
    if kind == "inplane" and normal is not None and not (_along(normal, n) or _across(normal, n)):
        return "normal", f"the normal of an inplane joint must be {along} or lie in the plane"
    if kind == "universal" and axes is not None:
        a1, a2 = axes
        if not ((_along(a1, n) and _across(a2, n)) or (_along(a2, n) and _across(a1, n))):
            return "axes", f"a universal joint needs one axis {along} and the other in the plane"
    return None


def contact_problem(geometry, plane: str) -> tuple[str, str] | None:
    """(key, message) when a contact geometry would push its bodies out of `plane`, else
    None (its force and friction then stay in the plane, its moments about the normal).
    `geometry`: any object with the keys of its shape (`normal`, `axis`, `plane_normal`,
    `offset`), the mechlib geometry or its schema model. A plane's normal must lie in the
    plane, a hole's axis or a profile's plane normal be along the normal, a ball's assembly
    offset lie in the plane (its component along the normal is constant in planar motion)."""
    n = plane_axes(plane)[2]
    along = f"along the normal of plane {plane} ({normal_name(plane)})"
    normal = getattr(geometry, "normal", None)
    if normal is not None and not _across(normal, n):
        return "normal", f"the plane's normal must lie in plane {plane}"
    axis = getattr(geometry, "axis", None)
    if axis is not None and not _along(axis, n):
        return "axis", f"the hole's axis must be {along}"
    plane_normal = getattr(geometry, "plane_normal", None)
    if plane_normal is not None and not _along(plane_normal, n):
        return "plane_normal", f"the profile's plane_normal must be {along}"
    offset = np.asarray(getattr(geometry, "offset", (0.0, 0.0, 0.0)), dtype=float)
    if abs(float(offset @ n)) > 0.0:
        return "offset", f"the ball's offset has a component along {normal_name(plane)}"
    return None


def _level(point, n: np.ndarray) -> float:
    return float(np.asarray(point, dtype=float) @ n)


def _source_problem(flexible, n: np.ndarray, plane: str):
    """(key path, message, level along n) of the source of a flexible body: a beam with
    its ends at one level along n and a section axis along n or in the plane, a panel
    with both edges in the plane; an imported model is refused (its elements may break
    the mirror symmetry about the plane, which cannot be checked here)."""
    beam = getattr(flexible, "beam", None)
    if beam is not None:
        level = _level(beam.start, n)
        if abs(_level(beam.end, n) - level) > _ALIGNED * _size(beam.start, beam.end):
            return (
                ("beam", "end"),
                f"the beam leaves plane {plane}: its ends differ along the normal",
                level,
            )
        if not (_along(beam.y_axis, n) or _across(beam.y_axis, n)):
            return (
                ("beam", "y_axis"),
                (
                    f"the section's y_axis must be along the normal of plane {plane} "
                    f"({normal_name(plane)}) or lie in the plane "
                    "(a section symmetric about the plane)"
                ),
                level,
            )
        return None, "", level
    for kind in ("grillage", "plate"):
        panel = getattr(flexible, kind, None)
        if panel is None:
            continue
        for key in ("x", "y"):
            if not _across(getattr(panel, key), n):
                return (kind, key), f"the panel's {key} edge must lie in plane {plane}", 0.0
        return None, "", _level(panel.at, n)
    return (
        ("file",),
        (
            f"an imported FE model cannot be checked to stay in plane {plane} "
            "(its elements may not be symmetric about it)"
        ),
        0.0,
    )


def _size(*points) -> float:
    span = np.ptp(np.asarray(points, dtype=float), axis=0) if len(points) > 1 else np.zeros(3)
    return max(float(np.linalg.norm(span)), 1.0)


def flexible_problem(flexible, plane: str) -> tuple[tuple, str] | None:
    """(key path, message) when a flexible body's geometry leaves `plane`, else None.
    `flexible`: the schema's `Flexible` (or any object with its keys: `beam`, `grillage`,
    `plate`, `file`, `interface`, `load_points`), positions in m. In the plane: the body's
    FE model lies in one plane parallel to `plane`, symmetric about it, and its interface
    and load points lie on that plane; its out-of-plane modes then stay unloaded and at
    rest (mirror symmetry), and the 3-D model of it moves in the plane."""
    n = plane_axes(plane)[2]
    key, message, level = _source_problem(flexible, n, plane)
    if key is not None:
        return key, message
    points = {**flexible.interface, **getattr(flexible, "load_points", {})}
    size = _size(*points.values())
    for group in ("interface", "load_points"):
        for name, at in getattr(flexible, group, {}).items():
            off = _level(at, n) - level
            if abs(off) > _ALIGNED * size:
                return (group, name), (
                    f"point '{name}' is {off:.6g} m off the body's plane along "
                    f"{normal_name(plane)}: it would leave plane {plane}"
                )
    return None
