"""The skeleton of a case's model: bodies (rigid, or flexible through `flexible_bodies`),
points, frames and joints."""

from __future__ import annotations

import mechlib as ml
from loadcases.build.context import Builder
from loadcases.build.flexible_bodies import add_flexible_body, at_interface
from loadcases.schema import FlexibleBody

__all__ = ["add_bodies", "add_joints"]

_JOINT_KEYS = ("at", "axis", "axes", "normal", "pitch", "joints", "ratio")


def add_bodies(b: Builder, m: ml.Mechanism) -> None:
    """The bodies of the mechanism model, then its points and frames."""
    for name, body in b.mech.bodies.items():
        if isinstance(body, FlexibleBody):
            add_flexible_body(b, m, name, body.flexible)
        else:
            m.add_body(name, mass=body.mass, cm=body.cm, inertia=body.inertia)
    for name, p in b.mech.points.items():
        at_interface(b, p.body, p.at, f"points.{name}.at")
        m.add_point(name, body=p.body, at=p.at)
    for name, f in b.mech.frames.items():
        m.add_frame(name, body=f.body, x=f.x, y=f.y, at=f.at)


def add_joints(b: Builder, m: ml.Mechanism) -> None:
    """Every joint of the mechanism model."""
    for name, j in b.mech.joints.items():
        _joint(b, m, name, j)


def _joint(b: Builder, m: ml.Mechanism, name: str, j) -> None:
    if j.type == "point_on_curve":
        m.add_joint(
            name,
            j.type,
            bodies=tuple(j.bodies),
            at=j.at,
            curve=j.curve,
            interpolation=j.interpolation,
        )
        return
    keys = {k: getattr(j, k) for k in _JOINT_KEYS if getattr(j, k, None) is not None}
    bodies = tuple(getattr(j, "bodies", (ml.GROUND, ml.GROUND)))
    for body in bodies:
        at_interface(b, body, keys.get("at", (0.0, 0.0, 0.0)), f"joints.{name}.at")
    if j.type == "orientation" and keys.get("at") is None:
        keys.pop("at", None)
    m.add_joint(name, j.type, bodies=bodies, **keys)
