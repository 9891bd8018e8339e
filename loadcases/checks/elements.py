"""Semantic checks of force elements, contacts, couplers and tables of a mechanism."""

from __future__ import annotations

import numpy as np

from loadcases.foundation.diagnostics import Diagnostic
from loadcases.schema import MechanismModel
from loadcases.schema.contacts import CLEARANCE_SHAPES
from loadcases.yamlfiles.source import Locator
from mechlib.elements.hydraulics.parameters import Supply
from mechlib.model.joints import ROTATIONAL

__all__ = ["check_elements"]

_PIN_JOINTS = ("revolute", "cylindrical", "spherical")
_ROTARY_JOINTS = ROTATIONAL
_COINCIDENT = 1.0e-9  # m: attachment points closer than this coincide


def _joint_elements(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """torsion springs on rotary joints; joint friction with or without pin radius."""
    found = []
    for name, force in model.forces.items():
        joint = model.joints.get(getattr(force, "joint", None) or "")
        if joint is None:
            continue
        path = ("forces", name, "joint")
        if force.type == "torsion_spring" and joint.type not in _ROTARY_JOINTS:
            found.append(
                at.diagnostic(
                    path,
                    f"a torsion spring needs a revolute, cylindrical "
                    f"or screw joint, '{force.joint}' is {joint.type}",
                )
            )
        if force.type != "joint_friction":
            continue
        if joint.type not in (*_PIN_JOINTS, "prismatic"):
            found.append(
                at.diagnostic(
                    path,
                    "joint friction needs a revolute, cylindrical, "
                    f"spherical or prismatic joint, '{force.joint}' is "
                    f"{joint.type}",
                )
            )
        elif joint.type == "prismatic" and force.pin_radius is not None:
            found.append(
                at.diagnostic(
                    ("forces", name, "pin_radius"),
                    "a prismatic joint has no pin radius",
                    hint="remove pin_radius",
                )
            )
        elif joint.type != "prismatic" and force.pin_radius is None:
            found.append(
                at.diagnostic(
                    ("forces", name), f"joint friction on a {joint.type} joint needs 'pin_radius'"
                )
            )
    return found


def _contacts(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """Positive radii, damping needs a depth, a wear law needs a clearance joint."""
    found = []
    for name, contact in model.contacts.items():
        geometry = contact.geometry
        if geometry.radius <= 0.0:
            found.append(
                at.diagnostic(("contacts", name, "geometry", "radius"), "radius must be positive")
            )
        if getattr(geometry, "clearance", 0.0) < 0.0:
            found.append(
                at.diagnostic(
                    ("contacts", name, "geometry", "clearance"), "clearance must not be negative"
                )
            )
        if contact.type == "impact" and contact.damping > 0.0 and not contact.depth:
            found.append(
                at.diagnostic(
                    ("contacts", name),
                    "impact damping needs 'depth' (the penetration of full damping)",
                )
            )
        if contact.wear is not None and geometry.shape not in CLEARANCE_SHAPES:
            found.append(
                at.diagnostic(
                    ("contacts", name, "wear"),
                    f"a wear law needs a clearance joint, not a {geometry.shape}",
                    hint="sphere_in_sphere or cylinder_in_cylinder",
                )
            )
        found += _contact_laws(name, contact, at)
    return found


def _contact_laws(name: str, contact, at: Locator) -> list[Diagnostic]:
    """A profile of >= 2 points, a restitution in (0, 1], friction speeds in order."""
    found = []
    points = getattr(contact.geometry, "points", None)
    if points is not None and len(points) < 2:
        found.append(
            at.diagnostic(
                ("contacts", name, "geometry", "points"),
                f"a profile needs at least 2 points, got {len(points)}",
            )
        )
    e = getattr(contact, "restitution", None)
    if e is not None and not 0.0 < e <= 1.0:
        found.append(
            at.diagnostic(
                ("contacts", name, "restitution"), f"restitution must be in (0, 1], got {e:g}"
            )
        )
    f = contact.friction
    if f is not None and f.model == "stribeck" and not 0.0 < f.v_static < f.v_dynamic:
        found.append(
            at.diagnostic(
                ("contacts", name, "friction"),
                f"expected 0 < v_static < v_dynamic, got {f.v_static:g} and {f.v_dynamic:g} m/s",
            )
        )
    return found


def _couplers(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    return [
        at.diagnostic(("joints", name, "joints"), f"a {joint.type} needs two different joints")
        for name, joint in model.joints.items()
        if joint.type in ("coupler", "gear") and joint.joints[0] == joint.joints[1]
    ]


def _tables(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """x and y of equal length (>= 2), x strictly increasing."""
    found = []
    for name, table in model.tables.items():
        if len(table.x) != len(table.y):
            found.append(
                at.diagnostic(
                    ("tables", name, "y"),
                    f"expected {len(table.x)} values (as many as x), got {len(table.y)}",
                )
            )
        if len(table.x) < 2:
            found.append(
                at.diagnostic(
                    ("tables", name, "x"), f"expected at least 2 values, got {len(table.x)}"
                )
            )
        elif np.any(np.diff(table.x) <= 0.0):
            index = int(np.argmax(np.diff(table.x) <= 0.0)) + 1
            found.append(
                at.diagnostic(
                    ("tables", name, "x"),
                    f"values must be strictly increasing (item {index + 1} is not)",
                )
            )
    return found


def _servo_actuators(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """A stroke [retracted, extended] around the design (0); two positive dead volumes."""
    found = []
    for name, force in model.forces.items():
        if force.type != "servo_actuator":
            continue
        lo, hi = force.stroke
        if not lo <= 0.0 <= hi or lo == hi:
            found.append(
                at.diagnostic(
                    ("forces", name, "stroke"),
                    f"expected [retracted, extended] limits around the design length (0), "
                    f"got [{lo:g}, {hi:g}] m",
                    hint="the stroke is measured from the design distance of the two points",
                )
            )
        dead = force.cylinder.dead_volumes if force.cylinder is not None else None
        if dead is not None and (len(dead) != 2 or min(dead) <= 0.0):
            found.append(
                at.diagnostic(
                    ("forces", name, "cylinder", "dead_volumes"),
                    f"expected two positive volumes [V1, V2], got {len(dead)} values",
                )
            )
        found += _servo_relations(model, name, force, at)
    return found


def _servo_relations(model: MechanismModel, name: str, force, at: Locator) -> list[Diagnostic]:
    """Supply above return (library values where absent), two distinct attachment points,
    non-negative (absolute) initial pressures."""
    found = []
    supply = force.supply
    p_s = supply.pressure if supply and supply.pressure is not None else Supply.pressure
    p_r = (
        supply.return_pressure
        if supply and supply.return_pressure is not None
        else Supply.return_pressure
    )
    if p_s <= p_r:
        key = "pressure" if supply and supply.pressure is not None else "return_pressure"
        found.append(
            at.diagnostic(
                ("forces", name, "supply", key),
                f"supply pressure must be > return pressure, got {p_s:g} <= {p_r:g} Pa",
            )
        )
    first, second = (model.points.get(p) for p in force.points)
    if force.points[0] == force.points[1] or (
        first is not None
        and second is not None
        and np.linalg.norm(np.subtract(first.at, second.at)) <= _COINCIDENT
    ):
        found.append(
            at.diagnostic(
                ("forces", name, "points"),
                f"the attachment points must be distinct, '{force.points[0]}' and "
                f"'{force.points[1]}' coincide at design",
            )
        )
    pressures = force.initial_pressures
    if pressures is not None and min(pressures) < 0.0:
        found.append(
            at.diagnostic(
                ("forces", name, "initial_pressures"),
                "pressures are absolute and must be >= 0, got "
                f"[{pressures[0]:g}, {pressures[1]:g}] Pa",
            )
        )
    return found


# vector parameters of force elements: (type, key, positive (> 0) or non-negative (>= 0))
_VECTOR_RANGES = (
    ("bushing", "stiffness", False),
    ("bushing", "torsional_stiffness", False),
    ("bushing", "damping", False),
    ("bushing", "torsional_damping", False),
    ("cable_loop", "radii", True),
)


def _vector_ranges(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """Components of vector parameters in range; contact materials E > 0, -1 < nu <= 0.5."""
    found = []
    for name, force in model.forces.items():
        for kind, key, positive in _VECTOR_RANGES:
            values = getattr(force, key) if force.type == kind else ()
            for i, value in enumerate(values):
                if value < 0.0 or (positive and value == 0.0):
                    found.append(
                        at.diagnostic(
                            ("forces", name, key, i),
                            f"must be {'>' if positive else '>='} 0, got {value:g}",
                        )
                    )
    for name, contact in model.contacts.items():
        materials = getattr(contact, "materials", None)
        if materials is None:
            continue
        for i, (e, nu) in enumerate(zip(materials.E, materials.nu, strict=True)):
            if e <= 0.0:
                found.append(
                    at.diagnostic(
                        ("contacts", name, "materials", "E", i), f"must be > 0, got {e:g} Pa"
                    )
                )
            if not -1.0 < nu <= 0.5:
                found.append(
                    at.diagnostic(
                        ("contacts", name, "materials", "nu", i),
                        f"must be in (-1, 0.5], got {nu:g}",
                    )
                )
    return found


def check_elements(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """All element, contact, coupler and table problems of a mechanism."""
    return (
        _joint_elements(model, at)
        + _contacts(model, at)
        + _couplers(model, at)
        + _tables(model, at)
        + _servo_actuators(model, at)
        + _vector_ranges(model, at)
    )
