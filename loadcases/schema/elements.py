"""Pydantic models of force elements, contacts and tables of a mechanism (SPEC 1.2.1)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from loadcases.schema.forces_more import CableLoop, Damper, Seal
from loadcases.schema.hydraulics import ServoActuator
from loadcases.schema.types import (
    Damping,
    Dimensionless,
    ForceOrTorque,
    Length,
    Name,
    NamePair,
    Position,
    Stiffness,
    Strict,
    TorsionalDamping,
    TorsionalStiffness,
    Values,
    describe,
    expression,
    quantity,
    vector,
)

__all__ = [
    "BodyTorque",
    "Bushing",
    "CircleVsProfile",
    "Contact",
    "ContactFriction",
    "CylinderInCylinder",
    "ForceElement",
    "HertzContact",
    "ImpactContact",
    "JointFriction",
    "Materials",
    "PointForce",
    "RestitutionContact",
    "SphereInSphere",
    "SpherePlane",
    "Spring",
    "Table",
    "TorsionSpring",
]

# contacts live in their own module; re-exported here for the existing imports
from loadcases.schema.contacts import (
    CircleVsProfile,
    Contact,
    ContactFriction,
    CylinderInCylinder,
    HertzContact,
    ImpactContact,
    Materials,
    RestitutionContact,
    SphereInSphere,
    SpherePlane,
)

_ACTIVE = "false: the element starts switched off (an event may activate it)"
_ZERO3 = (0.0, 0.0, 0.0)
_F = expression("force")  # a force component expression, N
_T = expression("torque")  # a torque component expression, N*m


def _at_most_one(model: Strict, first: str, second: str) -> None:
    if getattr(model, first) is not None and getattr(model, second) is not None:
        raise PydanticCustomError(
            "exclusive", "give '{a}' or '{b}', not both", {"a": first, "b": second}
        )


class Spring(Strict):
    """Translational spring-damper between two points (tension positive)."""

    type: Literal["spring"]
    points: NamePair = Field(description="[point 1, point 2]")
    stiffness: Stiffness = Field(0.0, ge=0, description=describe("stiffness", "stiffness"))
    damping: Damping = Field(0.0, ge=0, description=describe("damping", "damping"))
    free_length: Length | None = Field(
        None,
        description=describe("free length (absent and no preload: the design distance)", "length"),
    )
    preload: quantity("force") | None = Field(
        None, description=describe("tension at the design position", "force")
    )
    law: Name | None = Field(None, description="table of force [N] vs deflection [m]")
    tension_only: bool = Field(False, description="true for wires and ropes")
    active: bool = Field(True, description=_ACTIVE)

    @model_validator(mode="after")
    def _length_or_preload(self) -> Spring:
        _at_most_one(self, "free_length", "preload")
        return self


class TorsionSpring(Strict):
    """Rotational spring-damper on a revolute joint's coordinate."""

    type: Literal["torsion_spring"]
    joint: Name
    stiffness: TorsionalStiffness = Field(
        0.0, ge=0, description=describe("stiffness", "torsional_stiffness")
    )
    damping: TorsionalDamping = Field(
        0.0, ge=0, description=describe("damping", "torsional_damping")
    )
    angle0: quantity("angle") | None = Field(
        None, description=describe("free angle (absent and no preload: 0)", "angle")
    )
    preload: quantity("torque") | None = Field(
        None, description=describe("torque at the design position", "torque")
    )
    law: Name | None = Field(None, description="table of torque [N*m] vs angle [rad]")
    series_stiffness: TorsionalStiffness | None = Field(
        None,
        gt=0,
        description=describe(
            "stiffness of the structure in series with the "
            "hinge given by stiffness or law (seed 003 eq. 2.7)",
            "torsional_stiffness",
        ),
    )
    active: bool = Field(True, description=_ACTIVE)

    @model_validator(mode="after")
    def _angle_or_preload(self) -> TorsionSpring:
        _at_most_one(self, "angle0", "preload")
        return self


class Bushing(Strict):
    """6-DOF linear spring-damper between two bodies at `at`, global axes at design."""

    type: Literal["bushing"]
    bodies: NamePair
    at: Position = Field(description=describe("connection point", "length"))
    stiffness: vector("stiffness") = Field(
        _ZERO3, description=describe("[kx, ky, kz]", "stiffness")
    )
    torsional_stiffness: vector("torsional_stiffness") = Field(
        _ZERO3, description=describe("[krx, kry, krz]", "torsional_stiffness")
    )
    damping: vector("damping") = Field(_ZERO3, description=describe("[cx, cy, cz]", "damping"))
    torsional_damping: vector("torsional_damping") = Field(
        _ZERO3, description=describe("[crx, cry, crz]", "torsional_damping")
    )
    active: bool = Field(True, description=_ACTIVE)


class PointForce(Strict):
    """Force on a body: at a named `point`, or on `body` at `at` (default: its cm)."""

    type: Literal["force"]
    body: Name | None = None
    point: Name | None = None
    at: Position | None = Field(None, description=describe("point of application", "length"))
    value: tuple[_F, _F, _F] = Field(
        description="[ex, ey, ez] expressions in N (numbers SI) along the axes of `frame`"
    )
    frame: Name = Field("ground", description="ground, a body (axes turn with it) or a frame")
    active: bool = Field(True, description=_ACTIVE)

    @model_validator(mode="after")
    def _where(self) -> PointForce:
        if (self.body is None) == (self.point is None):
            raise PydanticCustomError("where", "give 'body' (with optional 'at') or 'point'")
        _at_most_one(self, "point", "at")
        return self


class BodyTorque(Strict):
    """Torque on a body."""

    type: Literal["torque"]
    body: Name
    value: tuple[_T, _T, _T] = Field(
        description="[ex, ey, ez] expressions in N*m (numbers SI) along the axes of `frame`"
    )
    frame: Name = Field("ground", description="ground, a body (axes turn with it) or a frame")
    active: bool = Field(True, description=_ACTIVE)


class JointFriction(Strict):
    """Coulomb friction in a joint: mu * pin_radius * |radial reaction| + preload."""

    type: Literal["joint_friction"]
    joint: Name
    mu: Dimensionless = Field(ge=0, description="friction coefficient [dimensionless]")
    pin_radius: Length | None = Field(
        None, gt=0, description=describe("pin (ball) radius; not for prismatic joints", "length")
    )
    preload: ForceOrTorque = Field(
        0.0, ge=0, description="torque (N*m) or, on a prismatic joint, force (N) [bare numbers SI]"
    )
    active: bool = Field(True, description=_ACTIVE)


ForceElement = Annotated[
    Spring
    | TorsionSpring
    | Bushing
    | PointForce
    | BodyTorque
    | JointFriction
    | Seal
    | Damper
    | CableLoop
    | ServoActuator,
    Field(discriminator="type"),
]


class Table(Strict):
    """x/y data: `table(name, x)` interpolates (SI values; texts may carry units)."""

    x: Values = Field(
        description="abscissae, increasing [any dimension, SI; e.g. '[0, 30, 60] deg']"
    )
    y: Values = Field(description="ordinates [any dimension, SI]")
    interpolation: Literal["akima", "linear", "cubic"] = "linear"
    extrapolate: Literal["error", "hold", "linear"] = Field(
        "error", description="outside the data: error (default), hold the end value, linear"
    )
