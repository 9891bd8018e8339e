"""The joint limit (`type: joint_limit`) of a case's model: its limits and depth read in the
unit of the joint's coordinate (angle: rad, travel: m; bare numbers in the file's units),
the stiffness and damping in SI."""

from __future__ import annotations

from typing import Any

import mechlib as ml
from loadcases.foundation.units import UnitError, to_si
from mechlib.elements.joint_limit import LIMIT_JOINTS

__all__ = ["joint_limit"]

_DIMENSION = {"angle": "angle", "travel": "length"}
_DEFAULT_DEPTH = 1.0e-4  # rad or m: the ramp of a limit without damping (unused then)


def _coordinate(builder, name: str, f) -> str | None:
    """The joint's coordinate the limit stops, or None after a diagnostic."""
    j = builder.mech.joints.get(f.joint)
    key = f"forces.{name}"
    if j is None:
        builder.error("mechanism", f"{key}.joint", f"unknown joint '{f.joint}'")
        return None
    coordinates = LIMIT_JOINTS.get(j.type)
    if coordinates is None:
        builder.error(
            "mechanism",
            f"{key}.joint",
            f"joint '{f.joint}' is {j.type}; a joint limit needs a {', '.join(LIMIT_JOINTS)} joint",
        )
        return None
    coordinate = f.coordinate or coordinates[0]
    if coordinate not in coordinates:
        builder.error(
            "mechanism",
            f"{key}.coordinate",
            f"joint '{f.joint}' is {j.type}: it has no {coordinate} coordinate",
        )
        return None
    return coordinate


def _value(builder, key: str, raw, dimension: str) -> float | None:
    """A limit or depth in SI (a parameter name gives the parameter's value)."""
    if raw is None:
        return None
    if isinstance(raw, str) and raw.strip() in builder.parameters:
        return float(builder.parameters[raw.strip()])
    try:
        return to_si(raw, dimension, builder.mech.units.as_dict())
    except UnitError as error:
        builder.error("mechanism", key, str(error))
        return None


def joint_limit(builder, name: str, f) -> Any:
    """A mechlib JointLimit, or None after a diagnostic."""
    coordinate = _coordinate(builder, name, f)
    if coordinate is None:
        return None
    dimension, key = _DIMENSION[coordinate], f"forces.{name}"
    lower = _value(builder, f"{key}.min", f.min, dimension)
    upper = _value(builder, f"{key}.max", f.max, dimension)
    depth = _value(builder, f"{key}.depth", f.depth, dimension)
    if (f.min is not None and lower is None) or (f.max is not None and upper is None):
        return None
    if lower is not None and upper is not None and lower >= upper:
        builder.error("mechanism", f"{key}.max", f"must be > min, got {upper:g} <= {lower:g}")
        return None
    if depth is not None and depth <= 0.0:
        builder.error("mechanism", f"{key}.depth", f"must be > 0, got {depth:g}")
        return None
    damping = f.damping if builder.effects.get("damping", True) else 0.0
    return ml.JointLimit(
        name,
        f.joint,
        coordinate,
        lower=lower,
        upper=upper,
        stiffness=f.stiffness,
        exponent=f.exponent,
        damping=damping,
        depth=_DEFAULT_DEPTH if depth is None else depth,
        restitution=f.restitution,
    )
