"""Hydraulic servo-actuator: element, parameters and orifice laws (SI units; the
equations per fidelity are in docs/hydraulics.md)."""

from mechlib.elements.hydraulics.actuator import FIDELITIES, ServoActuator
from mechlib.elements.hydraulics.command import HeldDemand
from mechlib.elements.hydraulics.orifice import floored, regularised_root, spool_flows
from mechlib.elements.hydraulics.parameters import (
    Controller,
    Cylinder,
    JetPipe,
    ServoValve,
    Supply,
    TorqueMotor,
)

__all__ = [
    "FIDELITIES",
    "Controller",
    "Cylinder",
    "HeldDemand",
    "JetPipe",
    "ServoActuator",
    "ServoValve",
    "Supply",
    "TorqueMotor",
    "floored",
    "regularised_root",
    "spool_flows",
]
