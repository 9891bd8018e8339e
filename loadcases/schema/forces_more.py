"""Pydantic models of the domain force elements: seal, damper, cable loop (issue 3)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from loadcases.schema.types import (
    AnySI,
    Dimensionless,
    Direction,
    Force,
    Length,
    Name,
    NamePair,
    Position,
    Stiffness,
    Strict,
    TorsionalDamping,
    Velocity,
    describe,
    vector,
)

__all__ = ["CableLoop", "Damper", "Seal"]

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
    active: bool = Field(True, description=_ACTIVE)
