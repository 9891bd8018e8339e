"""Semantic checks of a case's requests: names, frames and quantities that fit the joint."""

from __future__ import annotations

from loadcases.checks.common import Names, unknown
from loadcases.checks.mechanism import node_bodies
from loadcases.expressions import ExpressionError, parse
from loadcases.expressions.dimensions import DimensionScope, Dims, infer_dimension, same_dimension
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.units import (
    UnitError,
    describe_dimension,
    quantity_dimension,
    si_unit_text,
)
from loadcases.schema import COORDINATE_DIMENSION, CaseModel, MechanismModel
from loadcases.schema.contacts import CLEARANCE_SHAPES
from loadcases.yamlfiles.source import Locator
from mechlib.model.joints import ROTATIONAL, TRANSLATIONAL

__all__ = ["check_requests", "expression_units", "unit_problems"]

_ANGLE_QUANTITIES = ("angle", "omega", "alpha")
_TRAVEL_QUANTITIES = ("travel", "speed")
_ANGLE_JOINTS, _TRAVEL_JOINTS = ROTATIONAL, TRANSLATIONAL
_CLEARANCE_QUANTITIES = ("eccentricity", "wear_work", "wear_depth", "polar")  # as build.contacts
_TARGETS = {
    "joint": "joints",
    "motion": "motions",
    "point": "points",
    "force": "forces",
    "limit": "limits",
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
    known["forces"] = names.get("forces") | names.get("limits")  # {force: LIMIT} reads it too
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


def _expression_dims(request: object, scope: DimensionScope) -> tuple[Dims | None, Dims | None]:
    """(the dimension its `unit:` names, the one inferred from the expression) of an
    expression request; None where not known."""
    unit = getattr(request, "unit", None)
    try:
        named = quantity_dimension(f"1 {unit}") if unit else None
    except UnitError:
        named = None
    try:
        inferred = infer_dimension(parse(getattr(request, "expression", "")).tree, scope)
    except ExpressionError:
        inferred = None  # reported by the expression's own check
    return named, inferred


def unit_problems(case: CaseModel, at: Locator, scope: DimensionScope) -> list[Diagnostic]:
    """An expression request whose `unit:` is not of the dimension its expression gives."""
    found = []
    for name, request in case.requests.items():
        named, inferred = _expression_dims(request, scope)
        if named is not None and inferred is not None and not same_dimension(named, inferred):
            found.append(
                at.diagnostic(
                    ("requests", name, "unit"),
                    f"the expression gives {describe_dimension(dict(inferred))}; unit "
                    f"'{getattr(request, 'unit', '')}' is {describe_dimension(dict(named))}",
                )
            )
    return found


def expression_units(case: CaseModel, scope: DimensionScope) -> dict[str, str]:
    """The SI unit of each expression request's `value` column: that of the dimension its
    `unit:` names, else the one inferred from the expression (`""` when not known)."""
    units = {}
    for name, request in case.requests.items():
        if not hasattr(request, "expression"):
            continue
        named, inferred = _expression_dims(request, scope)
        dims = named if named is not None else inferred
        units[name] = "" if dims is None else si_unit_text(dict(dims))
    return units
