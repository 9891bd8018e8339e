"""Pydantic models of the three input file kinds (SI floats) and their JSON Schema."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel
from pydantic.json_schema import models_json_schema

from loadcases.schema.case import (
    ANALYSIS_TYPES,
    KNOWN_EFFECTS,
    REQUEST_KINDS,
    Analysis,
    CaseModel,
    ContactRequest,
    ElementRequest,
    ExpressionRequest,
    Initial,
    JointRequest,
    Motion,
    MotionRequest,
    PointRequest,
    Request,
)
from loadcases.schema.elements import (
    BodyTorque,
    Bushing,
    Contact,
    ContactFriction,
    ForceElement,
    HertzContact,
    ImpactContact,
    JointFriction,
    Materials,
    PointForce,
    RestitutionContact,
    SphereInSphere,
    SpherePlane,
    Spring,
    Table,
    TorsionSpring,
)
from loadcases.schema.mechanism import (
    COORDINATE_DIMENSION,
    JOINT_TYPES,
    AxesJoint,
    AxisJoint,
    Body,
    Coupler,
    Event,
    EventAction,
    FileUnits,
    Fixed,
    FlexibleBody,
    Frame,
    Joint,
    MechanismModel,
    NormalJoint,
    Orientation,
    Point,
    PointOnCurve,
    Screw,
    Spherical,
)
from loadcases.schema.setfile import Allowable, Report, SetModel

__all__ = [
    "ANALYSIS_TYPES",
    "COORDINATE_DIMENSION",
    "JOINT_TYPES",
    "KNOWN_EFFECTS",
    "MODELS",
    "REQUEST_KINDS",
    "Allowable",
    "Analysis",
    "AxesJoint",
    "AxisJoint",
    "Body",
    "BodyTorque",
    "Bushing",
    "CaseModel",
    "Contact",
    "ContactFriction",
    "ContactRequest",
    "Coupler",
    "ElementRequest",
    "Event",
    "EventAction",
    "ExpressionRequest",
    "FileUnits",
    "Fixed",
    "FlexibleBody",
    "ForceElement",
    "Frame",
    "HertzContact",
    "ImpactContact",
    "Initial",
    "Joint",
    "JointFriction",
    "JointRequest",
    "Materials",
    "MechanismModel",
    "Motion",
    "MotionRequest",
    "NormalJoint",
    "Orientation",
    "Point",
    "PointForce",
    "PointOnCurve",
    "PointRequest",
    "Report",
    "Request",
    "RestitutionContact",
    "Screw",
    "SetModel",
    "SphereInSphere",
    "SpherePlane",
    "Spherical",
    "Spring",
    "Table",
    "TorsionSpring",
    "json_schema",
]

MODELS: dict[str, type[BaseModel]] = {
    "mechanism": MechanismModel,
    "case": CaseModel,
    "set": SetModel,
}


def json_schema() -> dict[str, Any]:
    """JSON Schema (draft 2020-12) of the three file kinds: a document is one of them."""
    _, top = models_json_schema(
        [(model, "validation") for model in MODELS.values()], ref_template="#/$defs/{model}"
    )
    refs = [{"$ref": f"#/$defs/{model.__name__}"} for model in MODELS.values()]
    defs = top["$defs"]
    defs["CaseModel"]["properties"]["mechanism"] = {
        "anyOf": [{"type": "string"}, {"$ref": "#/$defs/MechanismModel"}],
        "description": "mechanism file relative to the case file, or the mechanism inline",
    }
    # `off` is a string too: oneOf (exactly one branch) would refuse it; the engine tells
    # the forms apart itself (loadcases.schema.case._accuracy_form)
    accuracy = defs["Analysis"]["properties"]["accuracy"]["anyOf"][0]
    accuracy["anyOf"] = accuracy.pop("oneOf")
    defs["MechanismModel"]["properties"]["points"]["properties"] = {
        "from": {
            "type": "string",
            "description": "hardpoint CSV file (relative to this file, inside its folder "
            "tree) with the columns name, body, x, y, z, units; its points join the inline "
            "ones",
        }
    }
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "loads input file (mechanism *.mech.yaml, case *.case.yaml, set *.set.yaml)",
        "description": "Bare numbers are SI unless the file's `units:` header sets the unit of "
        "length, angle, mass, time or force; any scalar may be a text with a "
        "unit ('110 mm'). Expressions are texts, numbers in them SI.",
        "anyOf": refs,
        "$defs": defs,
    }
