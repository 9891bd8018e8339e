"""Checks of a planar mechanism (`plane: xy|yz|xz`): what would leave the plane is refused.

Joints whose axis is not along the plane's normal (or a slide not in the plane), gravity
and loads with out-of-plane components (a force along the normal, a torque about an
in-plane axis), flexible bodies and contacts whose geometry leaves the plane, and initial
velocities out of the plane: each names its key. The joint, contact and flexible-body
rules are mechlib.model.plane's.
"""

from __future__ import annotations

import numpy as np

from loadcases.foundation.diagnostics import Diagnostic
from loadcases.schema import CaseModel, MechanismModel
from loadcases.schema.elements import BodyTorque, PointForce
from loadcases.yamlfiles.source import Locator
from mechlib.core.rotation import frame_axes
from mechlib.model.plane import (
    contact_problem,
    flexible_problem,
    joint_problem,
    normal_name,
    plane_axes,
)

__all__ = ["check_plane", "check_plane_initial"]

_HINT = "remove `plane` to use the 3-D model"


def check_plane(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """The problems of a mechanism with `plane` (none without it)."""
    plane = model.plane
    if plane is None:
        return []
    n = plane_axes(plane)[2]
    found = []
    for name, j in model.joints.items():
        problem = joint_problem(
            j.type,
            plane,
            axis=getattr(j, "axis", None),
            axes=getattr(j, "axes", None),
            normal=getattr(j, "normal", None),
        )
        if problem is not None:
            found.append(at.diagnostic(("joints", name, problem[0]), problem[1], hint=_HINT))
    if np.asarray(model.gravity, dtype=float) @ n != 0.0:
        found.append(
            at.diagnostic(("gravity",), _along_normal("gravity", plane), hint="set it to 0")
        )
    for name, body in model.bodies.items():
        flexible = getattr(body, "flexible", None)
        leaves = None if flexible is None else flexible_problem(flexible, plane)
        if leaves is not None:
            found.append(
                at.diagnostic(("bodies", name, "flexible", *leaves[0]), leaves[1], hint=_HINT)
            )
    for name, contact in model.contacts.items():
        problem = contact_problem(contact.geometry, plane)
        if problem is not None:
            found.append(
                at.diagnostic(
                    ("contacts", name, "geometry", problem[0]),
                    f"{problem[1]}: the contact would leave the plane",
                    hint=_HINT,
                )
            )
    return found + _loads(model, at, plane)


def _along_normal(what: str, plane: str) -> str:
    return f"{what} has a component along {normal_name(plane)}, out of plane {plane}"


def _frame_axes(model: MechanismModel, frame: str) -> np.ndarray:
    """Columns: the axes of `frame` at design (ground and bodies: the global axes)."""
    f = model.frames.get(frame)
    return np.eye(3) if f is None else frame_axes(f.x, f.y)


def _zero(text: str) -> bool:
    """An expression that is the number 0."""
    try:
        return float(text) == 0.0
    except ValueError:
        return False


def _loads(model: MechanismModel, at: Locator, plane: str) -> list[Diagnostic]:
    """Forces with a component along the normal, torques with one about an in-plane axis."""
    n = plane_axes(plane)[2]
    found = []
    for name, force in model.forces.items():
        if not isinstance(force, PointForce | BodyTorque):
            continue
        kind = force.type
        axes = _frame_axes(model, force.frame)
        for i, text in enumerate(force.value):
            reach = abs(float(axes[:, i] @ n))  # share of component i along the normal
            leaves = reach > 1e-12 if kind == "force" else reach < 1.0 - 1e-12
            if leaves and not _zero(text):
                what = "a force" if kind == "force" else "a torque"
                where = "along the normal" if kind == "force" else "about an in-plane axis"
                found.append(
                    at.diagnostic(
                        ("forces", name, "value", i),
                        f"{what} component {where} ({text}) leaves plane {plane}",
                        hint="make it 0, or " + _HINT,
                    )
                )
    return found


def check_plane_initial(case: CaseModel, model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """Initial body velocities (along the normal) and angular velocities (about in-plane
    axes) out of the plane of a planar mechanism."""
    if model.plane is None:
        return []
    n = plane_axes(model.plane)[2]
    found = []
    for name, entry in case.initial.items():
        for key, off in (
            ("velocity", lambda v: abs(float(np.asarray(v) @ n)) > 0.0),
            ("omega", lambda v: float(np.linalg.norm(np.cross(np.asarray(v), n))) > 0.0),
        ):
            value = getattr(entry, key, None)
            if value is not None and off(np.asarray(value, dtype=float)):
                found.append(
                    at.diagnostic(
                        ("initial", name, key),
                        f"an initial {key} out of plane {model.plane}",
                        hint="keep velocities in the plane and omega along "
                        + normal_name(model.plane),
                    )
                )
    return found
