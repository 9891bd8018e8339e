"""Pydantic models of force elements, contacts and tables of a mechanism (SPEC 1.2.1)."""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from loadcases.schema.types import (
    AnySI, Damping, Dimensionless, Direction, ForceOrTorque, Length, Name, NamePair, Position,
    Stiffness, Strict, TorsionalDamping, TorsionalStiffness, Values, Velocity, describe,
    expression, quantity, vector,
)

__all__ = [
    "Spring", "TorsionSpring", "Bushing", "PointForce", "BodyTorque", "JointFriction",
    "ForceElement", "SpherePlane", "SphereInSphere", "ContactFriction", "Materials",
    "ImpactContact", "HertzContact", "RestitutionContact", "Contact", "Table",
]

_ACTIVE = "false: the element starts switched off (an event may activate it)"
_ZERO3 = (0.0, 0.0, 0.0)
_F = expression("force")   # a force component expression, N
_T = expression("torque")  # a torque component expression, N*m


def _at_most_one(model: Strict, first: str, second: str) -> None:
    if getattr(model, first) is not None and getattr(model, second) is not None:
        raise PydanticCustomError("exclusive", "give '{a}' or '{b}', not both",
                                  {"a": first, "b": second})


class Spring(Strict):
    """Translational spring-damper between two points (tension positive)."""

    type: Literal["spring"]
    points: NamePair = Field(description="[point 1, point 2]")
    stiffness: Stiffness = Field(0.0, description=describe("stiffness", "stiffness"))
    damping: Damping = Field(0.0, description=describe("damping", "damping"))
    free_length: Length | None = Field(None, description=describe(
        "free length (absent and no preload: the design distance)", "length"))
    preload: quantity("force") | None = Field(  # type: ignore[valid-type]
        None, description=describe("tension at the design position", "force"))
    law: Name | None = Field(None, description="table of force [N] vs deflection [m]")
    tension_only: bool = Field(False, description="true for wires and ropes")
    active: bool = Field(True, description=_ACTIVE)

    @model_validator(mode="after")
    def _length_or_preload(self) -> "Spring":
        _at_most_one(self, "free_length", "preload")
        return self


class TorsionSpring(Strict):
    """Rotational spring-damper on a revolute joint's coordinate."""

    type: Literal["torsion_spring"]
    joint: Name
    stiffness: TorsionalStiffness = Field(0.0, description=describe("stiffness",
                                                                    "torsional_stiffness"))
    damping: TorsionalDamping = Field(0.0, description=describe("damping", "torsional_damping"))
    angle0: quantity("angle") | None = Field(  # type: ignore[valid-type]
        None, description=describe("free angle (absent and no preload: 0)", "angle"))
    preload: quantity("torque") | None = Field(  # type: ignore[valid-type]
        None, description=describe("torque at the design position", "torque"))
    law: Name | None = Field(None, description="table of torque [N*m] vs angle [rad]")
    active: bool = Field(True, description=_ACTIVE)

    @model_validator(mode="after")
    def _angle_or_preload(self) -> "TorsionSpring":
        _at_most_one(self, "angle0", "preload")
        return self


class Bushing(Strict):
    """6-DOF linear spring-damper between two bodies at `at`, global axes at design."""

    type: Literal["bushing"]
    bodies: NamePair
    at: Position = Field(description=describe("connection point", "length"))
    stiffness: vector("stiffness") = Field(_ZERO3, description=describe(  # type: ignore
        "[kx, ky, kz]", "stiffness"))
    torsional_stiffness: vector("torsional_stiffness") = Field(  # type: ignore[valid-type]
        _ZERO3, description=describe("[krx, kry, krz]", "torsional_stiffness"))
    damping: vector("damping") = Field(_ZERO3, description=describe(  # type: ignore
        "[cx, cy, cz]", "damping"))
    torsional_damping: vector("torsional_damping") = Field(  # type: ignore[valid-type]
        _ZERO3, description=describe("[crx, cry, crz]", "torsional_damping"))
    active: bool = Field(True, description=_ACTIVE)


class PointForce(Strict):
    """Force on a body: at a named `point`, or on `body` at `at` (default: its cm)."""

    type: Literal["force"]
    body: Name | None = None
    point: Name | None = None
    at: Position | None = Field(None, description=describe("point of application", "length"))
    value: tuple[_F, _F, _F] = Field(  # type: ignore[valid-type]
        description="[ex, ey, ez] expressions in N (numbers SI) along the axes of `frame`")
    frame: Name = Field("ground", description="ground, a body (axes turn with it) or a frame")
    active: bool = Field(True, description=_ACTIVE)

    @model_validator(mode="after")
    def _where(self) -> "PointForce":
        if (self.body is None) == (self.point is None):
            raise PydanticCustomError("where", "give 'body' (with optional 'at') or 'point'")
        _at_most_one(self, "point", "at")
        return self


class BodyTorque(Strict):
    """Torque on a body."""

    type: Literal["torque"]
    body: Name
    value: tuple[_T, _T, _T] = Field(  # type: ignore[valid-type]
        description="[ex, ey, ez] expressions in N*m (numbers SI) along the axes of `frame`")
    frame: Name = Field("ground", description="ground, a body (axes turn with it) or a frame")
    active: bool = Field(True, description=_ACTIVE)


class JointFriction(Strict):
    """Coulomb friction in a joint: mu * pin_radius * |radial reaction| + preload."""

    type: Literal["joint_friction"]
    joint: Name
    mu: Dimensionless = Field(description="friction coefficient [dimensionless]")
    pin_radius: Length | None = Field(None, description=describe(
        "pin (ball) radius; not for prismatic joints", "length"))
    preload: ForceOrTorque = Field(0.0, description="torque (N*m) or, on a prismatic joint, "
                                   "force (N) [bare numbers SI]")
    active: bool = Field(True, description=_ACTIVE)


from loadcases.schema.forces_more import CableLoop, Damper, Seal  # noqa: E402

ForceElement = Annotated[Spring | TorsionSpring | Bushing | PointForce | BodyTorque
                         | JointFriction | Seal | Damper | CableLoop,
                         Field(discriminator="type")]


class SpherePlane(Strict):
    """Sphere on body 1 against a plane on body 2 (normal from body 2 towards body 1)."""

    shape: Literal["sphere_plane"]
    center: Position = Field(description=describe("sphere centre", "length"))
    radius: Length = Field(description=describe("sphere radius", "length"))
    plane_point: Position = Field(description=describe("a point of the plane", "length"))
    normal: Direction = Field(description="plane normal, from body 2 to body 1")


class SphereInSphere(Strict):
    """Ball on body 1 inside the socket of body 2; centres coincide at design."""

    shape: Literal["sphere_in_sphere"]
    center: Position = Field(description=describe("common centre at design", "length"))
    radius: Length = Field(description=describe("ball radius", "length"))
    clearance: Length = Field(description=describe("radial clearance", "length"))


class ContactFriction(Strict):
    """Stribeck-type friction law of a contact."""

    mu_static: Dimensionless
    mu_dynamic: Dimensionless
    v_static: Velocity = Field(1.0e-3, description=describe("stiction speed", "velocity"))
    v_dynamic: Velocity = Field(1.0e-2, description=describe("full sliding speed", "velocity"))


class Materials(Strict):
    """Elastic materials of the two bodies (Hertz stiffness from E and nu)."""

    E: tuple[quantity("pressure"), quantity("pressure")]  # type: ignore[valid-type]
    nu: tuple[Dimensionless, Dimensionless]


Geometry = Annotated[SpherePlane | SphereInSphere, Field(discriminator="shape")]
_K = "contact stiffness k in F = k * x^exponent [N/m^exponent, SI]"


class _Contact(Strict):
    bodies: NamePair = Field(description="[body 1 (sphere), body 2 (plane or socket)]")
    geometry: Geometry
    exponent: Dimensionless = Field(1.5, description="force exponent [dimensionless]")
    friction: ContactFriction | None = None
    active: bool = Field(True, description=_ACTIVE)


class ImpactContact(_Contact):
    """F = k x^e + step(x, 0, 0, depth, c_max) * x_dot."""

    type: Literal["impact"]
    stiffness: AnySI = Field(description=_K)
    damping: Damping = Field(0.0, description=describe("c_max reached at depth", "damping"))
    depth: Length | None = Field(None, description=describe("penetration of full damping",
                                                            "length"))


class HertzContact(_Contact):
    """Hertz force with Lankarani-Nikravesh hysteresis damping from `restitution`."""

    type: Literal["hertz"]
    stiffness: AnySI | None = Field(None, description=_K)
    materials: Materials | None = None
    restitution: Dimensionless | None = Field(None, description="coefficient of restitution")

    @model_validator(mode="after")
    def _stiffness(self) -> "HertzContact":
        _at_most_one(self, "stiffness", "materials")
        if self.stiffness is None and self.materials is None:
            raise PydanticCustomError("stiffness", "give 'stiffness' or 'materials'")
        return self


class RestitutionContact(_Contact):
    """Contact by coefficient of restitution (stiffness optional)."""

    type: Literal["restitution"]
    restitution: Dimensionless = Field(description="coefficient of restitution")
    stiffness: AnySI | None = Field(None, description=_K)


Contact = Annotated[ImpactContact | HertzContact | RestitutionContact,
                    Field(discriminator="type")]


class Table(Strict):
    """x/y data: `table(name, x)` interpolates (SI values; texts may carry units)."""

    x: Values = Field(description="abscissae, increasing [any dimension, SI; e.g. "
                      "'[0, 30, 60] deg']")
    y: Values = Field(description="ordinates [any dimension, SI]")
    interpolation: Literal["akima", "linear", "cubic"] = "linear"
    extrapolate: Literal["error", "hold", "linear"] = Field(
        "error", description="outside the data: error (default), hold the end value, linear")
