"""Pydantic model of a case's `torque_margin:` block (seed 003 section 2.1, eq. 2.1).

TM_j = sum D_j / sum R_j >= required per hinge line j, the resistive torques multiplied by
the uncertainty factor of their kind. Computation: `loadcases/torque_margin.py`.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field

from loadcases.schema.types import Dimensionless, Expression, Name, Strict

__all__ = ["CONTRIBUTOR_KINDS", "DEFAULT_FACTORS", "Contributor", "HingeLine", "TorqueMargin"]

CONTRIBUTOR_KINDS = ("spring", "friction", "harness", "damper", "inertia", "hysteresis", "other")
# Uncertainty factors on resistive torques, in the style of ECSS-E-ST-33-01C table 4-1
# (spring 1.2, friction 1.5, harness 3 unless measured, inertia 1.1, hysteresis 3); the
# damper is taken as friction-like (1.5). A project's tailored values go in the case.
DEFAULT_FACTORS = {
    "spring": 1.2,
    "friction": 1.5,
    "harness": 3.0,
    "damper": 1.5,
    "inertia": 1.1,
    "hysteresis": 3.0,
    "other": 1.5,
}
Kind = Literal["spring", "friction", "harness", "damper", "inertia", "hysteresis", "other"]


def _kind_shorthand(value: Any) -> Any:
    """`drive_hl2: spring` is `drive_hl2: {kind: spring}`."""
    return {"kind": value} if isinstance(value, str) else value


class Contributor(Strict):
    """One torque on a hinge line: a force element on the hinge's joint (named by the key)
    or an `expression` (N*m, positive resisting the deployment)."""

    kind: Kind = Field(
        description="spring, friction, harness, damper, inertia, hysteresis "
        "or other: picks the default uncertainty factor"
    )
    factor: Dimensionless | None = Field(
        None,
        gt=0,
        description="uncertainty factor on the "
        "torque while it resists (default by kind: "
        + ", ".join(f"{k} {v:g}" for k, v in DEFAULT_FACTORS.items())
        + ")",
    )
    expression: Expression | None = Field(
        None,
        description="torque resisting the deployment "
        "(N*m; e.g. an inertia torque I * alpha); absent: "
        "the force element named by the key",
    )


class HingeLine(Strict):
    """A hinge line: its joint, the way it deploys and the torques acting on it."""

    joint: Name = Field(description="revolute joint of the hinge line")
    sense: Literal["positive", "negative"] = Field(
        "positive", description="deployment direction of the joint angle"
    )
    contributors: dict[str, Annotated[Contributor, BeforeValidator(_kind_shorthand)]] = Field(
        min_length=1,
        description="element name (or label of an expression): kind or {kind, factor, expression}",
    )


class TorqueMargin(Strict):
    """Torque margin of every hinge line along the run (seed 003 eq. 2.1)."""

    required: Dimensionless = Field(2.0, gt=0, description="required TM_j (ECSS: 2)")
    restart_friction: Dimensionless = Field(
        1.0,
        gt=0,
        description="breakaway / sliding friction ratio for the restart check "
        "(a deployment stopped part-way restarts from rest: no damper nor inertia torque, "
        "friction times this)",
    )
    hinge_lines: dict[str, HingeLine] = Field(min_length=1)
    system: bool = Field(
        False,
        description="also the system margin of hinge lines synchronised by cable loops: "
        "every line's torques reduced to the first line by virtual work (columns "
        "tm_system.*; reported beside the per-line check, which alone decides passed)",
    )
