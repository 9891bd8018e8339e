"""Contact elements (impact, hertz, restitution between primitive geometries) of a case's
model: `add_contacts` adds them as force elements of the contact's effect (`contact`), so
that `effects: {contact: false}` removes them; a case with `effects: {friction: false}` gets
its contacts without friction. `sphere_in_sphere` and `cylinder_in_cylinder` geometries make
clearance joints (they report an eccentricity).

`CONTACT_MAKERS[type](builder, name, model) -> mechlib element or None` (None after the
builder recorded a diagnostic).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import mechlib as ml
from loadcases.build.context import NOT_YET, Builder
from loadcases.schema.contacts import CLEARANCE_SHAPES
from mechlib.elements import contact as mc

__all__ = [
    "CLEARANCE_QUANTITIES",
    "CLEARANCE_SHAPES",
    "CONTACT_COMPONENTS",
    "CONTACT_MAKERS",
    "CONTACT_UNITS",
    "add_contacts",
]


# Request quantity -> (column component, key of the element's output), SPEC 1.2.1.
CONTACT_COMPONENTS: dict[str, tuple[tuple[str, str], ...]] = {
    "force": (
        ("normal", "normal"),
        ("friction", "friction"),
        ("fx", "fx"),
        ("fy", "fy"),
        ("fz", "fz"),
    ),
    "penetration": (("value", "penetration"),),
    "point": (("x", "px"), ("y", "py"), ("z", "pz")),
    "sliding_speed": (("value", "sliding_speed"),),
    "wear": (("value", "wear"),),
    "eccentricity": (
        ("ex", "ex"),
        ("ey", "ey"),
        ("ez", "ez"),
        ("value", "eccentricity"),
        ("angle", "angle"),
    ),
    "wear_work": (("value", "wear_work"),),
    "wear_depth": (("value", "wear_depth"),),
    "force_split": (("elastic", "elastic"), ("damping", "damping")),
    "polar": (
        ("radial", "radial"),
        ("axial", "axial"),
        ("angle", "angle"),
        ("clearance", "clearance"),
        ("normal", "normal"),
        ("wear", "wear"),
        ("wear_work", "wear_work"),
    ),
}
CLEARANCE_QUANTITIES = ("eccentricity", "wear_work", "wear_depth", "polar")
"""Request quantities only a clearance joint has."""
# Unit of each element output key: the contact's own, and the clearance joints' eccentricity.
CONTACT_UNITS: dict[str, str] = {**mc.Contact.output_units, **mc.ClearanceJoint.output_units}

DEFAULT_PENALTY = 1.0e8
"""N/m^n: penalty stiffness of a `restitution` contact that gives none."""


def _geometry(g) -> Any:
    """The mechlib geometry of a schema geometry (SI values)."""
    if g.shape == "sphere_plane":
        return mc.SpherePlane(g.center, g.radius, g.plane_point, g.normal, g.extent)
    if g.shape == "sphere_in_sphere":
        return mc.SphereInSphere(g.center, g.radius, g.clearance, g.offset)
    if g.shape == "cylinder_in_cylinder":
        return mc.CylinderInCylinder(g.center, g.axis, g.radius, g.clearance)
    return mc.CircleProfile(g.center, g.radius, g.points, g.plane_normal)


def effective_radius(g) -> float:
    """Hertz effective radius (m): R for a sphere or roller on a plane or profile (the
    profile's own curvature ignored), R (R + c) / c for a ball or pin in its socket or hole."""
    if g.shape in CLEARANCE_SHAPES:
        return g.radius * (g.radius + g.clearance) / max(g.clearance, 1e-12)
    return g.radius


def _friction(builder, model) -> Any:
    f = model.friction
    if f is None or not builder.effects.get("friction", True):
        return None
    if f.model == "coulomb":
        return mc.CoulombFriction(f.mu_dynamic, f.v_static)
    mu_static = f.mu_dynamic if f.mu_static is None else f.mu_static
    return mc.StribeckFriction(mu_static, f.mu_dynamic, f.v_static, f.v_dynamic, f.viscous)


def _element(builder, name: str, model, law) -> Any:
    """A Contact, or a ClearanceJoint for a ball in a socket or a pin in a hole."""
    geometry, friction = _geometry(model.geometry), _friction(builder, model)
    if model.geometry.shape in CLEARANCE_SHAPES:
        axis = getattr(model.geometry, "polar_axis", (0.0, 0.0, 1.0))
        w = model.wear
        wear = None if w is None else mc.ArchardWear(w.coefficient, w.hardness, w.track_width)
        return mc.ClearanceJoint(
            name, tuple(model.bodies), geometry, law, friction, polar_axis=axis, wear_law=wear
        )
    return mc.Contact(name, tuple(model.bodies), geometry, law, friction)


def _impact(builder, name: str, model) -> Any:
    depth = model.depth if model.depth else 1.0e-4
    law = mc.ImpactLaw(model.stiffness, model.exponent, model.damping, depth)
    return _element(builder, name, model, law)


def _hertz(builder, name: str, model) -> Any:
    stiffness = model.stiffness
    if stiffness is None:
        m = model.materials
        stiffness = mc.hertz_stiffness(
            m.E[0], m.nu[0], m.E[1], m.nu[1], effective_radius(model.geometry)
        )
    law = mc.HertzLaw(stiffness, model.exponent, model.restitution)
    return _element(builder, name, model, law)


def _restitution(builder, name: str, model) -> Any:
    stiffness = DEFAULT_PENALTY if model.stiffness is None else model.stiffness
    law = mc.RestitutionLaw(model.restitution, stiffness, model.exponent)
    return _element(builder, name, model, law)


CONTACT_MAKERS: dict[str, Callable[[Any, str, Any], Any]] = {
    "impact": _impact,
    "hertz": _hertz,
    "restitution": _restitution,
}


def add_contacts(b: Builder, m: ml.Mechanism) -> None:
    """The contacts of the mechanism model, unless the case switches contact off."""
    for name, c in b.mech.contacts.items() if b.effects.get("contact", True) else ():
        maker = CONTACT_MAKERS.get(c.type)
        element = maker(b, name, c) if maker else None
        if element is not None:
            element.active = c.active  # `active: false`: built, switched on by an event
        if maker is None:
            b.error("mechanism", f"contacts.{name}", f"{c.type} contacts {NOT_YET}")
        elif element is not None:
            m.add_force(element)
