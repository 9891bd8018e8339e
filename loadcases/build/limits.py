"""The joint limits (`limits:`) of a case's model: each a mechlib JointLimit, its limits
and depth in the unit of the joint's coordinate (loadcases.checks.limits reads them), the
stiffness and damping in SI. Built unless the case switches the `contact` effect off."""

from __future__ import annotations

import mechlib as ml
from loadcases.checks.limits import read_limit

__all__ = ["LIMIT_EFFECT", "add_limits"]

LIMIT_EFFECT = "contact"
_DEFAULT_DEPTH = 1.0e-4  # rad or m: the ramp of a limit without damping (unused then)


def _limit(builder, name: str, f) -> ml.JointLimit | None:
    """A mechlib JointLimit, or None after a diagnostic."""
    key = f"limits.{name}"
    joint = builder.mech.joints.get(f.joint)
    if joint is None:
        builder.error("mechanism", f"{key}.joint", f"unknown joint '{f.joint}'")
        return None
    units = builder.mech.units.as_dict()
    values, problems = read_limit(f, joint.type, units, builder.parameters)
    for where, message in problems:
        builder.error("mechanism", f"{key}.{where}", message)
    if values is None:
        return None
    damping = f.damping if builder.effects.get("damping", True) else 0.0
    return ml.JointLimit(
        name,
        f.joint,
        values.coordinate,
        lower=values.lower,
        upper=values.upper,
        stiffness=f.stiffness,
        exponent=f.exponent,
        damping=damping,
        depth=_DEFAULT_DEPTH if values.depth is None else values.depth,
        restitution=f.restitution,
    )


def add_limits(builder, m: ml.Mechanism) -> None:
    """The mechanism's limits as force elements of effect `contact` (unless it is off)."""
    if not builder.effects.get(LIMIT_EFFECT, True):
        return
    for name, f in builder.mech.limits.items():
        element = _limit(builder, name, f)
        if element is not None:
            element.active = f.active  # `active: false`: built, switched on by an event
            m.add_force(element)
