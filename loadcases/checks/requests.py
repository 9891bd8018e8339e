"""Semantic checks of a case's requests: names, frames and quantities that fit the joint."""

from __future__ import annotations

from loadcases.checks.common import Names, unknown
from loadcases.checks.mechanism import node_bodies
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.schema import COORDINATE_DIMENSION, CaseModel, MechanismModel
from loadcases.schema.contacts import CLEARANCE_SHAPES
from loadcases.yamlfiles.source import Locator
from mechlib.model.joints import ROTATIONAL, TRANSLATIONAL

__all__ = ["check_requests"]

_ANGLE_QUANTITIES = ("angle", "omega", "alpha")
_TRAVEL_QUANTITIES = ("travel", "speed")
_ANGLE_JOINTS, _TRAVEL_JOINTS = ROTATIONAL, TRANSLATIONAL
_CLEARANCE_QUANTITIES = ("eccentricity", "wear_work", "wear_depth", "polar")  # as build.contacts
_TARGETS = {
    "joint": "joints",
    "motion": "motions",
    "point": "points",
    "force": "forces",
    "contact": "contacts",
    "section": "sections",
}


def _quantity_fits(
    case: CaseModel, mechanism: MechanismModel, at: Locator, name: str, request: object
) -> list[Diagnostic]:
    """angle/omega/alpha need a rotary joint, travel/speed a sliding one; motion torque/force."""
    path = ("requests", name, "quantity")
    quantity = getattr(request, "quantity", None)
    if hasattr(request, "joint") and request.joint in mechanism.joints:
        kind = mechanism.joints[request.joint].type
        if (quantity in _ANGLE_QUANTITIES and kind not in _ANGLE_JOINTS) or (
            quantity in _TRAVEL_QUANTITIES and kind not in _TRAVEL_JOINTS
        ):
            return [at.diagnostic(path, f"joint '{request.joint}' is {kind}: it has no {quantity}")]
    if hasattr(request, "motion") and request.motion in case.motions:
        joint = mechanism.joints.get(case.motions[request.motion].joint)
        dimension = COORDINATE_DIMENSION.get(joint.type) if joint is not None else None
        wanted = {"angle": "torque", "length": "force"}.get(dimension or "")
        if joint is not None and wanted and quantity != wanted:
            return [
                at.diagnostic(
                    path,
                    f"motion '{request.motion}' drives a {joint.type} joint: request its {wanted}",
                    hint=f"quantity: {wanted}",
                )
            ]
    contact_name = getattr(request, "contact", None) or ""
    contact = mechanism.contacts.get(contact_name)
    if (
        quantity in _CLEARANCE_QUANTITIES
        and contact is not None
        and contact.geometry.shape not in CLEARANCE_SHAPES
    ):
        return [
            at.diagnostic(
                path,
                f"contact '{contact_name}' is a "
                f"{contact.geometry.shape}, not a clearance joint: it has no "
                f"{quantity}",
                hint="sphere_in_sphere or cylinder_in_cylinder",
            )
        ]
    if quantity == "wear_depth" and contact is not None and contact.wear is None:
        return [
            at.diagnostic(
                path,
                f"contact '{contact_name}' has no wear law: its wear_depth needs one",
                hint="wear: {coefficient: 1.0e-4, hardness: 2 GPa, track_width: 2 mm}",
            )
        ]
    return []


def check_requests(
    case: CaseModel, mechanism: MechanismModel, at: Locator, names: Names
) -> list[Diagnostic]:
    """Unknown joints, motions, points, force elements, contacts and frames of requests."""
    found = []
    known = dict(names.kinds, motions=set(case.motions))
    frames = names.get("bodies") | node_bodies(mechanism) | names.get("frames")
    for name, request in case.requests.items():
        for key, section in _TARGETS.items():
            target = getattr(request, key, None)
            if isinstance(target, str) and target not in known.get(section, set()):
                what = "force element" if key == "force" else key
                found.append(
                    unknown(at, ("requests", name, key), what, target, known.get(section, set()))
                )
        frame = getattr(request, "frame", None)
        if frame is not None and frame not in frames:
            found.append(unknown(at, ("requests", name, "frame"), "frame", frame, frames))
        found += _quantity_fits(case, mechanism, at, name, request)
    return found
