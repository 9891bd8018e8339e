"""Builders of the domain force elements (joint friction, seals, dampers, cable loops ...).

`ELEMENT_MAKERS[type](builder, name, model) -> mechlib element or None` (None after the
builder recorded a diagnostic with `builder.error(...)`). `loadcases.build.forces` calls the
maker of every force element type it does not build itself.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import mechlib as ml
from loadcases.build.hydraulics import servo_actuator

__all__ = ["ELEMENT_EFFECTS", "ELEMENT_MAKERS"]

# force element type -> the effect (case `effects:` switch) it belongs to
ELEMENT_EFFECTS = {
    "joint_friction": "friction",
    "damper": "damping",
    "seal": "contact",
    "servo_actuator": "hydraulics",
}
_ROTARY = ("revolute", "cylindrical", "inline")  # dampers: joints with an angle, screw aside


def _joint(builder, name: str, key: str, joint: str, types: tuple[str, ...]):
    """The joint model, or None after a diagnostic (unknown, or of the wrong type)."""
    j = builder.mech.joints.get(joint)
    if j is None:
        builder.error("mechanism", f"forces.{name}.{key}", f"unknown joint '{joint}'")
    elif j.type not in types:
        builder.error(
            "mechanism",
            f"forces.{name}.{key}",
            f"joint '{joint}' is {j.type}; this element needs a {' or '.join(types)} joint",
        )
    else:
        return j
    return None


def _joint_friction(builder, name: str, f) -> Any:
    from mechlib.elements.friction import FRICTION_JOINTS

    j = _joint(builder, name, "joint", f.joint, FRICTION_JOINTS)
    if j is None:
        return None
    radius = 0.0 if j.type == "prismatic" else (f.pin_radius or 0.0)
    return ml.JointFriction(name, f.joint, f.mu, radius, f.preload)


def _damper(builder, name: str, f) -> Any:
    if _joint(builder, name, "joint", f.joint, _ROTARY) is None:
        return None
    return ml.RotationalDamper(name, f.joint, f.damping)


def _cable_loop(builder, name: str, f) -> Any:
    joints = [
        _joint(builder, name, f"joints[{i}]", j, ("revolute",)) for i, j in enumerate(f.joints)
    ]
    if None in joints:
        return None
    owner = builder.body_owner  # a joint on a node of a flexible yoke is on the yoke
    shared = set(map(owner, joints[0].bodies)) & set(map(owner, joints[1].bodies))
    if len(shared) != 1 or f.radii[0] <= 0.0 or f.radii[1] <= 0.0:
        builder.error(
            "mechanism",
            f"forces.{name}",
            "a cable loop needs two revolute joints "
            "sharing exactly one body (the yoke) and positive radii",
        )
        return None
    return ml.CableLoop(
        name, tuple(f.joints), tuple(f.radii), f.stiffness, f.pretension, guided=f.guided
    )


def _seal(builder, name: str, f) -> Any:
    law = None
    if f.law is not None:
        if f.stiffness:
            builder.error("mechanism", f"forces.{name}.law", "give 'stiffness' or 'law', not both")
            return None
        law = ml.TableLaw(builder.tables[f.law], name)
    elif f.stiffness <= 0.0:
        builder.error("mechanism", f"forces.{name}", "a seal needs 'stiffness' > 0 or 'law'")
        return None
    return ml.Seal(
        name,
        tuple(f.bodies),
        f.start,
        f.end,
        f.normal,
        count=f.springs,
        stiffness=f.stiffness,
        exponent=f.exponent,
        law=law,
        gap=f.gap,
        mu=f.mu,
        v_threshold=f.v_threshold,
    )


def _bushing(builder, name: str, f) -> Any:
    damping = builder.effects.get("damping", True)  # off: the bushing is a pure spring
    zero = (0.0, 0.0, 0.0)
    return ml.Bushing(
        name,
        tuple(f.bodies),
        tuple(f.at),
        tuple(f.stiffness),
        tuple(f.torsional_stiffness),
        tuple(f.damping) if damping else zero,
        tuple(f.torsional_damping) if damping else zero,
    )


ELEMENT_MAKERS: dict[str, Callable[[Any, str, Any], Any]] = {
    "joint_friction": _joint_friction,
    "damper": _damper,
    "cable_loop": _cable_loop,
    "seal": _seal,
    "bushing": _bushing,
    "servo_actuator": servo_actuator,
}
