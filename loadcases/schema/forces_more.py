"""Pydantic models of the domain force elements: seal, damper, cable loop (issue 3); a joint
limit of `limits:` (issue 36)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from loadcases.schema.types import (
    AnySI,
    Dimensionless,
    Direction,
    Force,
    Length,
    Name,
    NamePair,
    Position,
    RawQuantity,
    Stiffness,
    Strict,
    TorsionalDamping,
    Velocity,
    describe,
    vector,
)

__all__ = ["CableLoop", "Damper", "Limit", "Seal"]

_ACTIVE = "false: the element starts switched off (an event may activate it)"


class Seal(Strict):
    """N springs spread along a line (knife on body 1 pressing the seal on body 2)."""

    type: Literal["seal"]
    bodies: NamePair = Field(description="[body 1 (knife), body 2 (seal)]")
    start: Position = Field(description=describe("first end of the seal line", "length"))
    end: Position = Field(description=describe("second end of the seal line", "length"))
    normal: Direction = Field(description="seal normal, from body 2 towards body 1")
    springs: int = Field(7, ge=1, description="number of springs N spread along the line")
    stiffness: AnySI = Field(
        0.0,
        ge=0,
        description="line stiffness k of the line load "
        "w = k x^exponent [N/m per metre of seal at exponent 1, SI]",
    )
    exponent: Dimensionless = Field(1.0, gt=0, description="exponent of the line load [-]")
    law: Name | None = Field(
        None,
        description="table of line load [N/m] vs penetration "
        "[m], instead of stiffness and exponent",
    )
    gap: Length = Field(
        0.0, description=describe("gap at design (negative: pre-compressed)", "length")
    )
    mu: Dimensionless = Field(0.0, ge=0, description="friction coefficient [dimensionless]")
    v_threshold: Velocity = Field(
        1.0e-3, gt=0, description=describe("sliding speed of full friction", "velocity")
    )
    active: bool = Field(True, description=_ACTIVE)


class Damper(Strict):
    """Rotational (eddy-current) damper on a revolute joint: torque = -damping * omega."""

    type: Literal["damper"]
    joint: Name
    damping: TorsionalDamping = Field(ge=0, description=describe("damping c", "torsional_damping"))
    active: bool = Field(True, description=_ACTIVE)


class CableLoop(Strict):
    """Closed cable loop synchronising two revolute joints that share one body."""

    type: Literal["cable_loop"]
    joints: tuple[Name, Name] = Field(description="[joint 1 (pulley r1), joint 2 (pulley r2)]")
    radii: vector("length", 2) = Field(description=describe("[r1, r2] pulley radii", "length"))
    stiffness: Stiffness = Field(
        gt=0, description=describe("stiffness of each strand", "stiffness")
    )
    pretension: Force = Field(0.0, ge=0, description=describe("strand tension at design", "force"))
    guided: bool = Field(
        False,
        description="strands guided along the yoke (seed 003 fig. 2.2.5-4): the yoke takes "
        "the torque (F_a - F_b)(r1 - r2), no lateral force",
    )
    active: bool = Field(True, description=_ACTIVE)


class Limit(Strict):
    """A limit (stop) on a joint coordinate with the IMPACT law, an entry of a mechanism's
    `limits:` (docs/elements.md, Joint limits)."""

    joint: Name = Field(description="a revolute, prismatic or cylindrical joint")
    coordinate: Literal["angle", "travel"] | None = Field(
        None, description="the coordinate stopped (cylindrical joints; default: angle)"
    )
    min: RawQuantity | None = Field(
        None, description="lower limit of the coordinate [angle or length]; absent: none"
    )
    max: RawQuantity | None = Field(
        None, description="upper limit of the coordinate [angle or length]; absent: none"
    )
    stiffness: AnySI = Field(
        gt=0, description="k of k x^e [N*m/rad^e (angle) or N/m^e (travel), bare numbers SI]"
    )
    exponent: Dimensionless = Field(1.5, gt=0, description="e of k x^e [dimensionless]")
    damping: AnySI = Field(
        0.0, ge=0, description="c_max [N*m*s/rad or N*s/m, bare numbers SI], full at `depth`"
    )
    depth: RawQuantity | None = Field(
        None, description="penetration where the damping is full [angle or length]"
    )
    restitution: Dimensionless | None = Field(
        None, gt=0, le=1, description="coefficient of restitution instead of `damping`"
    )
    active: bool = Field(True, description=_ACTIVE)

    @model_validator(mode="after")
    def _complete(self) -> Limit:
        if self.min is None and self.max is None:
            raise PydanticCustomError("limit", "give 'min', 'max' or both")
        if self.restitution is not None and self.damping:
            raise PydanticCustomError("exclusive", "give 'damping' or 'restitution', not both")
        if self.damping and self.depth is None:
            raise PydanticCustomError("limit", "'damping' needs 'depth' (full damping there)")
        return self
