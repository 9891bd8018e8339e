"""Pydantic models of contacts and clearance joints of a mechanism (SPEC 1.2.1, docs/elements.md).

A contact joins body 1 (the sphere, ball, pin or roller) to body 2 (the plane, socket, hole or
profile); `sphere_in_sphere` and `cylinder_in_cylinder` are the spherical and revolute
clearance joints (they also report their eccentricity).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from loadcases.schema.types import (
    AnySI,
    Damping,
    Dimensionless,
    Direction,
    Length,
    NamePair,
    Position,
    Strict,
    Velocity,
    describe,
    quantity,
)

__all__ = [
    "CLEARANCE_SHAPES",
    "ArchardWearInput",
    "CircleVsProfile",
    "Contact",
    "ContactFriction",
    "CylinderInCylinder",
    "HertzContact",
    "ImpactContact",
    "Materials",
    "RestitutionContact",
    "SphereInSphere",
    "SpherePlane",
]

_ACTIVE = "false: the element starts switched off (an event may activate it)"


def _at_most_one(model: Strict, first: str, second: str) -> None:
    if getattr(model, first) is not None and getattr(model, second) is not None:
        raise PydanticCustomError(
            "exclusive", "give '{a}' or '{b}', not both", {"a": first, "b": second}
        )


class SpherePlane(Strict):
    """Sphere on body 1 against a plane on body 2 (normal from body 2 towards body 1)."""

    shape: Literal["sphere_plane"]
    center: Position = Field(description=describe("sphere centre", "length"))
    radius: Length = Field(description=describe("sphere radius", "length"))
    plane_point: Position = Field(description=describe("a point of the plane", "length"))
    normal: Direction = Field(description="plane normal, from body 2 to body 1")
    extent: Length | None = Field(
        None,
        gt=0,
        description=describe(
            "radius of the plane's pad about plane_point (absent: an unbounded plane)", "length"
        ),
    )


class SphereInSphere(Strict):
    """Ball on body 1 inside the socket of body 2 (a spherical clearance joint); the socket
    is centred on `center` at design, the ball on `center` + `offset`."""

    shape: Literal["sphere_in_sphere"]
    center: Position = Field(description=describe("common centre at design", "length"))
    radius: Length = Field(description=describe("ball radius", "length"))
    clearance: Length = Field(description=describe("radial clearance", "length"))
    polar_axis: Direction = Field(
        (0.0, 0.0, 1.0),
        description="axis (body 2) about which the eccentricity's polar angle is measured",
    )
    offset: Position = Field(
        (0.0, 0.0, 0.0),
        description=describe(
            "the ball's centre minus the socket's at design (an assembly error, the "
            "eccentricity at the start; its size below the clearance)",
            "length",
        ),
    )


class CylinderInCylinder(Strict):
    """Pin on body 1 inside the hole of body 2 (a revolute clearance joint); axes coincide
    at design."""

    shape: Literal["cylinder_in_cylinder"]
    center: Position = Field(description=describe("a point of the common axis", "length"))
    axis: Direction = Field(description="hole axis (body 2)")
    radius: Length = Field(description=describe("pin radius", "length"))
    clearance: Length = Field(description=describe("radial clearance", "length"))


class CircleVsProfile(Strict):
    """Roller circle on body 1 against a planar profile (cam, guide) of body 2."""

    shape: Literal["circle_vs_profile"]
    center: Position = Field(description=describe("roller centre", "length"))
    radius: Length = Field(description=describe("roller radius", "length"))
    points: list[Position] = Field(
        description=describe("profile points in order (a cubic spline runs through them)", "length")
    )
    plane_normal: Direction = Field(description="normal of the plane of roller and profile")


class ContactFriction(Strict):
    """Friction law of a contact: step-function Stribeck (seed 004 eq. 3.9) or Coulomb."""

    mu_static: Dimensionless | None = Field(
        None, ge=0, description="static coefficient (stribeck; absent: mu_dynamic)"
    )
    mu_dynamic: Dimensionless = Field(ge=0, description="sliding coefficient [dimensionless]")
    v_static: Velocity = Field(1.0e-3, gt=0, description=describe("stiction speed", "velocity"))
    v_dynamic: Velocity = Field(
        1.0e-2, gt=0, description=describe("full sliding speed", "velocity")
    )
    viscous: AnySI = Field(0.0, ge=0, description="viscous coefficient mu_v [s/m, SI]")
    model: Literal["stribeck", "coulomb"] = Field(
        "stribeck",
        description="stribeck (eq. 3.9) or coulomb (mu_dynamic, regularised below v_static)",
    )


class Materials(Strict):
    """Elastic materials of the two bodies (Hertz stiffness from E and nu)."""

    E: tuple[quantity("pressure"), quantity("pressure")]
    nu: tuple[Dimensionless, Dimensionless]


Geometry = Annotated[
    SpherePlane | SphereInSphere | CylinderInCylinder | CircleVsProfile,
    Field(discriminator="shape"),
]
_K = "contact stiffness k in F = k * x^exponent [N/m^exponent, SI]"


CLEARANCE_SHAPES = ("sphere_in_sphere", "cylinder_in_cylinder")
"""Geometries that make a clearance joint (eccentricity, wear work, wear depth)."""


class ArchardWearInput(Strict):
    """Archard wear law of a clearance joint: depth = k W / (H * 2 pi r * track_width), W
    the wear work (J), r the socket or hole radius."""

    coefficient: Dimensionless = Field(gt=0, description="Archard wear coefficient k [1]")
    hardness: quantity("pressure") = Field(
        gt=0, description=describe("hardness H of the softer surface", "pressure")
    )
    track_width: Length = Field(
        gt=0, description=describe("width of the worn track round the socket", "length")
    )


class _Contact(Strict):
    bodies: NamePair = Field(
        description="[body 1 (sphere, ball, pin, roller), body 2 (plane, socket, hole, profile)]"
    )
    geometry: Geometry
    exponent: Dimensionless = Field(1.5, gt=0, description="force exponent [dimensionless]")
    friction: ContactFriction | None = None
    wear: ArchardWearInput | None = Field(
        None, description="Archard wear law (clearance joints): the wear_depth request"
    )
    active: bool = Field(True, description=_ACTIVE)


class ImpactContact(_Contact):
    """F = k x^e + step(x, 0, 0, depth, c_max) * x_dot."""

    type: Literal["impact"]
    stiffness: AnySI = Field(gt=0, description=_K)
    damping: Damping = Field(0.0, ge=0, description=describe("c_max reached at depth", "damping"))
    depth: Length | None = Field(
        None, gt=0, description=describe("penetration of full damping", "length")
    )


class HertzContact(_Contact):
    """Hertz force with Lankarani-Nikravesh hysteresis damping from `restitution`."""

    type: Literal["hertz"]
    stiffness: AnySI | None = Field(None, gt=0, description=_K)
    materials: Materials | None = None
    restitution: Dimensionless | None = Field(None, description="coefficient of restitution")

    @model_validator(mode="after")
    def _stiffness(self) -> HertzContact:
        _at_most_one(self, "stiffness", "materials")
        if self.stiffness is None and self.materials is None:
            raise PydanticCustomError("stiffness", "give 'stiffness' or 'materials'")
        return self


class RestitutionContact(_Contact):
    """Contact by coefficient of restitution (stiffness optional)."""

    type: Literal["restitution"]
    restitution: Dimensionless = Field(description="coefficient of restitution")
    stiffness: AnySI | None = Field(None, gt=0, description=_K + "; default 1e8")


Contact = Annotated[ImpactContact | HertzContact | RestitutionContact, Field(discriminator="type")]
