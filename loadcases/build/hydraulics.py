"""Builder of the hydraulic servo-actuator (schema -> mechlib.elements.hydraulics.ServoActuator):
keys given replace the library values, absent ones keep them; the analyses it cannot act in."""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any

import mechlib as ml
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.inputs.loader import CaseFile
from mechlib.elements.hydraulics import (
    Controller,
    Cylinder,
    HeldDemand,
    JetPipe,
    ServoActuator,
    ServoValve,
    Supply,
    TorqueMotor,
)
from mechlib.elements.hydraulics.actuator import LAG_DAMPING


@dataclass(frozen=True)
class Lag:
    """The `lag:` keys of a servo actuator: None keeps the element's own default."""

    velocity_gain: float | None = None
    stiffness: float | None = None
    damping: float = LAG_DAMPING


__all__ = ["servo_actuator", "servo_problems"]


def _given(defaults, model, **renamed) -> Any:
    """`defaults` (a parameter dataclass) with the keys `model` gives (not None; no model:
    none)."""
    names = {f.name for f in fields(defaults)}
    given = model.model_dump() if model is not None else {}
    values = {k: v for k, v in given.items() if v is not None and k in names}
    values.update({k: v for k, v in renamed.items() if v is not None})
    return replace(defaults, **values)


def _cylinder(f) -> Cylinder:
    c = f.cylinder
    dead = (c.dead_volumes if c is not None else None) or (None, None)
    return _given(
        Cylinder(),
        c,
        stroke=tuple(f.stroke),
        dead_volume_1=dead[0],
        dead_volume_2=dead[1],
    )


def _jet_pipe(f) -> JetPipe:
    """The jet-pipe values given, with the torque motor's reluctance law when given."""
    j = f.jet_pipe
    motor = None if j is None or j.torque_motor is None else j.torque_motor.model_dump()
    return replace(_given(JetPipe(), j), torque_motor=motor and TorqueMotor(**motor))


def _demand(command) -> Any:
    """The stroke demand of a compiled `command` expression: held at its value when it
    folds to a number (a compiled run reads it once, mechlib.elements.hydraulics.command),
    else the expression called at each time."""
    if command.compiled.is_constant:
        return HeldDemand(float(command.compiled.value))
    return lambda t: command(t)


def servo_actuator(builder, name: str, f) -> Any:
    """The element, or None after a diagnostic (unknown point; the stroke and volumes are
    checked by loadcases.checks.elements)."""
    missing = [p for p in f.points if p not in builder.mech.points]
    if missing:
        builder.error("mechanism", f"forces.{name}.points", f"unknown point '{missing[0]}'")
        return None
    p1, p2 = (builder.mech.points[p] for p in f.points)
    lag = _given(Lag(), f.lag)
    return ServoActuator(
        name,
        ((p1.body, p1.at), (p2.body, p2.at)),
        _demand(builder.compile(f.command, f"forces.{name}.command")),
        f.fidelity,
        cylinder=_cylinder(f),
        supply=_given(Supply(), f.supply),
        valve=_given(ServoValve(), f.valve),
        controller=_given(Controller(), f.controller),
        jet_pipe=_jet_pipe(f),
        velocity_gain=lag.velocity_gain,
        lag_stiffness=lag.stiffness,
        lag_damping=lag.damping,
        initial_pressures=tuple(f.initial_pressures) if f.initial_pressures else None,
    )


def servo_problems(cf: CaseFile, mechanism: ml.Mechanism, analysis) -> list[Diagnostic]:
    """Servo actuators with valve dynamics in an equilibrium analysis, or in a modes
    analysis (linearised about one): their chamber pressures follow the piston flow, which
    an equilibrium (piston at rest) does not have, so they cannot give a force there
    (docs/hydraulics.md, Analyses)."""
    if not isinstance(analysis, (ml.QuasiStatic, ml.Static, ml.Modes)):
        return []
    modes = isinstance(analysis, ml.Modes)
    where = "its modes are linearised about a static equilibrium, where" if modes else "and"
    instead = "use a dynamic analysis" if modes else "use a dynamic or kinematic analysis"
    file, line, column = cf.where("case", "analysis.type")
    return [
        Diagnostic(
            file,
            line,
            column,
            "analysis.type",
            f"servo actuator '{name}' ({element.fidelity}) cannot act in a {analysis.name} "
            f"analysis: its chamber pressures follow the piston flow, {where} the piston is "
            "at rest",
            hint=f"{instead}, the actuator's fidelity lag (an oil column of stiffness k_h), "
            "or effects: {hydraulics: false}",
        )
        for name, element in mechanism.forces.items()
        if isinstance(element, ServoActuator) and element.fidelity != "lag"
    ]
