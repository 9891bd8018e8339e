"""The case's requests as mechlib outputs with the unit of every column; the abscissa a set
records as one more request; what a modes analysis reports of them."""

from __future__ import annotations

import re
from collections.abc import Mapping

import mechlib as ml
from loadcases.build.contacts import CONTACT_COMPONENTS, CONTACT_UNITS
from loadcases.build.context import Builder
from loadcases.build.elements import ELEMENT_EFFECTS
from loadcases.build.flexible_bodies import flexible_output_units, flexible_request
from loadcases.build.limits import LIMIT_EFFECT
from loadcases.build.sections import section_joint
from mechlib.elements.friction import friction_units

__all__ = [
    "ABSCISSA_COLUMN",
    "ABSCISSA_REQUEST",
    "abscissa_request",
    "abscissa_unit",
    "build_requests",
    "modal_requests",
    "request_kinds",
]

# A run of a set records the case's `abscissa:` expression as one more result column, so
# envelopes and curves over it can be made from the saved results alone.
ABSCISSA_REQUEST = "abscissa"
ABSCISSA_COLUMN = f"{ABSCISSA_REQUEST}.value"
# Unit of an abscissa that is one state measure, e.g. `angle(hinge)` -> rad.
_MEASURE_UNITS = {
    "angle": "rad",
    "omega": "rad/s",
    "travel": "m",
    "speed": "m/s",
    "dist": "m",
    "x": "m",
    "y": "m",
    "z": "m",
    "vx": "m/s",
    "vy": "m/s",
    "vz": "m/s",
    "t": "s",
}
_MEASURE = re.compile(r"^\s*(\w+)\s*(\(\s*\w+\s*(,\s*\w+\s*)?\))?\s*$")
_COORDINATE_UNITS = {
    "angle": "rad",
    "omega": "rad/s",
    "alpha": "rad/s^2",
    "travel": "m",
    "speed": "m/s",
    "accel": "m/s^2",
}
_POINT_UNITS = {"position": "m", "velocity": "m/s", "acceleration": "m/s^2"}


def build_requests(
    b: Builder, expression_units: Mapping[str, str] | None = None
) -> tuple[list, dict[str, str]]:
    """The outputs of the case's requests (those with an error left out) and {column: unit};
    `expression_units`: the unit of each expression request (`CaseFile.expression_units`)."""
    out, units = [], {}
    for name, r in b.case.requests.items():
        req = _request(b, name, r)
        if req is None:
            continue
        out.append(req)
        if isinstance(req, ml.ExpressionOutput):
            units[f"{name}.value"] = (expression_units or {}).get(name, "")
            continue
        for comp, unit in _units_of(req, b).items():
            units[f"{name}.{comp}"] = unit
    return out, units


# What each kind of request reports (`kinds` of a run's summary): the report charts the
# loads (`loadcases.report.curves.LOAD_KINDS`), friction and energy only when asked.
_KINDS = {
    "MotionRequest": "effort",
    "SectionRequest": "reaction",  # the load a body carries at a section: a joint's reaction
    "LimitRequest": "contact",  # a joint limit's stop load
    "PointRequest": "kinematics",
    "FlexibleRequest": "flexible",
    "EnergyRequest": "energy",
    "ExpressionRequest": "expression",
}


def request_kinds(b: Builder) -> dict[str, str]:
    """{request: kind} of the case's requests: `reaction` (joint and section forces), `effort`
    (motions), `element` (force elements), `friction` (joint friction), `contact` (contacts
    and joint limits), `kinematics`, `flexible`, `energy`, `expression`."""
    kinds = {}
    for name, r in b.case.requests.items():
        kind = type(r).__name__
        if kind == "JointRequest":
            kinds[name] = "reaction" if r.quantity == "force" else "kinematics"
        elif kind == "ElementRequest" and r.force in b.mech.limits:
            kinds[name] = "contact"  # a joint limit's stop load, as {limit: NAME}
        elif kind == "ElementRequest":
            element = b.mech.forces.get(r.force)
            friction = element is not None and element.type == "joint_friction"
            kinds[name] = "friction" if friction else "element"
        else:
            kinds[name] = _KINDS.get(kind, "contact")
    return kinds


def _request(b: Builder, name: str, r):
    kind = type(r).__name__
    if kind == "JointRequest":
        if r.quantity == "force" and b.mech.joints[r.joint].type in ("coupler", "gear"):
            return ml.CouplerEffort(name, r.joint)
        if r.quantity == "force":
            return ml.JointReaction(name, r.joint, r.frame)
        return ml.JointCoordinate(name, r.joint, r.quantity)
    if kind == "MotionRequest":
        return ml.MotionEffort(name, r.motion)
    if kind == "PointRequest":
        return ml.PointKinematics(name, r.point, r.quantity, r.frame)
    if kind == "FlexibleRequest":
        return flexible_request(b, name, r)
    if kind == "ElementRequest":
        if r.force in b.mech.limits:
            return _limit_request(b, name, r.force, "force")
        return _element_request(b, name, r)
    if kind == "SectionRequest":
        frame = r.frame or b.mech.sections[r.section].body
        return ml.JointReaction(name, section_joint(r.section), frame)
    if kind == "LimitRequest":
        return _limit_request(b, name, r.limit, "limit")
    if kind == "EnergyRequest":
        return ml.EnergyBalance(name)
    if kind == "ExpressionRequest":
        return ml.ExpressionOutput(name, b.compile(r.expression, f"requests.{name}", "case"))
    return _contact_request(b, name, r)


def _element_request(b: Builder, name: str, r) -> ml.ElementOutput | None:
    """A force element's output, or None after an error: the element is not in the case's
    loads, or its effect is off."""
    f = b.mech.forces.get(r.force)
    if (
        f is None
        or (b.loads is not None and r.force not in b.loads)
        or not b.effects.get(ELEMENT_EFFECTS.get(f.type, ""), True)
    ):
        b.error(
            "case",
            f"requests.{name}.force",
            f"force element '{r.force}' is not active in this case",
        )
        return None
    return ml.ElementOutput(name, r.force, r.frame)


def _limit_request(b: Builder, name: str, limit: str, key: str) -> ml.ElementOutput | None:
    """A joint limit's output (`value`, `penetration`), or None after an error: contact off."""
    if limit in b.mech.limits and b.effects.get(LIMIT_EFFECT, True):
        return ml.ElementOutput(name, limit, "ground")
    b.error(
        "case",
        f"requests.{name}.{key}",
        f"limit '{limit}' is not simulated in this case (effects: {{{LIMIT_EFFECT}: false}})",
    )
    return None


def _contact_request(b: Builder, name: str, r) -> ml.ElementOutput | None:
    """A contact's output, or None after an error: contact off, or no such quantity."""
    components = CONTACT_COMPONENTS.get(r.quantity)
    if r.contact in b.mech.contacts and components and b.effects.get("contact", True):
        return ml.ElementOutput(name, r.contact, r.frame, components)
    b.error(
        "case",
        f"requests.{name}",
        f"contact '{r.contact}' is not simulated in this "
        "case (switched off, or its quantity is not available)",
    )
    return None


def _units_of(req, b: Builder) -> dict[str, str]:
    if isinstance(req, ml.JointReaction):
        return dict(req.units)
    if isinstance(req, ml.JointCoordinate):
        return {"value": _COORDINATE_UNITS[req.quantity]}
    if isinstance(req, ml.PointKinematics):
        return dict.fromkeys("xyz", _POINT_UNITS[req.quantity])
    if isinstance(req, ml.FlexibleOutput):
        return flexible_output_units(req, b)
    if isinstance(req, (ml.MotionEffort, ml.CouplerEffort)):
        return _effort_units(req, b)
    if isinstance(req, ml.ElementOutput) and req.components is not None:
        return {column: CONTACT_UNITS.get(key, "") for column, key in req.components}
    if isinstance(req, ml.ElementOutput):
        force = b.mech.forces.get(req.element)  # None for a joint limit (`limits:`)
        if force is not None and force.type == "joint_friction":  # units of its joint's type
            return friction_units(b.mech.joints[force.joint].type)
        element = b.built.forces.get(req.element)  # None if it failed to build: its error stands
        return dict(getattr(element, "output_units", {}))
    if isinstance(req, ml.EnergyBalance):
        return dict(req.units)
    return {"value": ""}


def _effort_units(req: ml.MotionEffort | ml.CouplerEffort, b: Builder) -> dict[str, str]:
    """N on a prismatic joint, N*m on the others: a motion's joint, a coupler's two ends."""
    if isinstance(req, ml.MotionEffort):
        joint = b.mech.joints[b.case.motions[req.motion].joint]
        return {"value": "N" if joint.type == "prismatic" else "N*m"}
    ends = b.mech.joints[req.joint].joints
    return {
        column: "N" if b.mech.joints[j].type == "prismatic" else "N*m"
        for column, j in zip(("input", "output"), ends)
    }


def abscissa_unit(text: str) -> str:
    """SI unit of an abscissa expression that is a single state measure, else `""`."""
    match = _MEASURE.match(text)
    if match is None or (match.group(1) != "t" and match.group(2) is None):
        return ""
    return _MEASURE_UNITS.get(match.group(1), "")


def abscissa_request(b: Builder, requests: list, units: dict[str, str]) -> None:
    """Append the case's abscissa as request `abscissa` (column `abscissa.value`)."""
    text = b.case.abscissa
    if text is None:
        return
    if ABSCISSA_REQUEST in b.case.requests:
        b.error(
            "case",
            f"requests.{ABSCISSA_REQUEST}",
            f"the request name "
            f"'{ABSCISSA_REQUEST}' is reserved for the case's abscissa in a set; rename it",
        )
        return
    requests.append(ml.ExpressionOutput(ABSCISSA_REQUEST, b.compile(text, "abscissa", "case")))
    units[ABSCISSA_COLUMN] = abscissa_unit(text)


def modal_requests(requests: list, units: dict[str, str]):
    """The requests a modes analysis reports (points, joint coordinates), their units (per
    unit modal amplitude), the mode number and frequency columns, and the names dropped."""
    kept = [r for r in requests if isinstance(r, (ml.PointKinematics, ml.JointCoordinate))]
    dropped = [r.name for r in requests if r not in kept]
    names = {r.name for r in kept}
    units = {"mode.number": "", "mode.frequency": "Hz"} | {
        c: (
            "m"
            if isinstance(next(r for r in kept if r.name == c.split(".")[0]), ml.PointKinematics)
            else u
        )
        for c, u in units.items()
        if c.split(".")[0] in names
    }
    return kept, units, dropped
