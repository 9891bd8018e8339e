"""mechlib: rigid multibody mechanics in absolute coordinates (NumPy/SciPy, SI units).

Build a `Mechanism`, pick an analysis, name the requests, and call `solve`. Each name is
imported on first use (PEP 562): `from mechlib.joints import ROTATIONAL` (the schema's
joint types, `loads validate`) then loads no solver, SciPy or numba.
"""

from __future__ import annotations

import sys
import types
from typing import TYPE_CHECKING, Any

from mechlib.lazy import lazy_names

if TYPE_CHECKING:
    from mechlib.analysis import (
        DEFAULT_MAX_STEPS,
        Dynamic,
        InitialBodyVelocity,
        InitialValue,
        Kinematic,
        Modes,
        QuasiStatic,
        Static,
    )
    from mechlib.check import ModelError
    from mechlib.contract import Status
    from mechlib.elements import Bushing, CableLoop, JointFriction, RotationalDamper, Seal, TableLaw
    from mechlib.energy import EnergyBalance
    from mechlib.events import Action, Event
    from mechlib.forces import PointForce, PointTorque, Spring, TorsionSpring
    from mechlib.model import GROUND, Mechanism
    from mechlib.model_check import MechanismCheck, check_model, inspect_mechanism
    from mechlib.planar import make_system
    from mechlib.requests import (
        CouplerEffort,
        ElementOutput,
        ExpressionOutput,
        FlexibleOutput,
        JointCoordinate,
        JointReaction,
        MotionEffort,
        PointKinematics,
    )
    from mechlib.solution import Solution, SolverFailure, SolverStats
    from mechlib.solve import solve
    from mechlib.system import System
    from mechlib.view import StateView

# name -> the module that defines it
_HOMES = {
    "DEFAULT_MAX_STEPS": "mechlib.analysis",
    "GROUND": "mechlib.model",
    "Action": "mechlib.events",
    "Bushing": "mechlib.elements",
    "CableLoop": "mechlib.elements",
    "CouplerEffort": "mechlib.requests",
    "Dynamic": "mechlib.analysis",
    "ElementOutput": "mechlib.requests",
    "EnergyBalance": "mechlib.energy",
    "Event": "mechlib.events",
    "ExpressionOutput": "mechlib.requests",
    "FlexibleOutput": "mechlib.requests",
    "InitialBodyVelocity": "mechlib.analysis",
    "InitialValue": "mechlib.analysis",
    "JointCoordinate": "mechlib.requests",
    "JointFriction": "mechlib.elements",
    "JointReaction": "mechlib.requests",
    "Kinematic": "mechlib.analysis",
    "Mechanism": "mechlib.model",
    "MechanismCheck": "mechlib.model_check",
    "ModelError": "mechlib.check",
    "Modes": "mechlib.analysis",
    "MotionEffort": "mechlib.requests",
    "PointForce": "mechlib.forces",
    "PointKinematics": "mechlib.requests",
    "PointTorque": "mechlib.forces",
    "QuasiStatic": "mechlib.analysis",
    "RotationalDamper": "mechlib.elements",
    "Seal": "mechlib.elements",
    "Solution": "mechlib.solution",
    "SolverFailure": "mechlib.solution",
    "SolverStats": "mechlib.solution",
    "Spring": "mechlib.forces",
    "StateView": "mechlib.view",
    "Static": "mechlib.analysis",
    "Status": "mechlib.contract",
    "System": "mechlib.system",
    "TableLaw": "mechlib.elements",
    "TorsionSpring": "mechlib.forces",
    "check_model": "mechlib.model_check",
    "inspect_mechanism": "mechlib.model_check",
    "make_system": "mechlib.planar",
    "solve": "mechlib.solve",
}

__all__ = [
    "DEFAULT_MAX_STEPS",
    "GROUND",
    "Action",
    "Bushing",
    "CableLoop",
    "CouplerEffort",
    "Dynamic",
    "ElementOutput",
    "EnergyBalance",
    "Event",
    "ExpressionOutput",
    "FlexibleOutput",
    "InitialBodyVelocity",
    "InitialValue",
    "JointCoordinate",
    "JointFriction",
    "JointReaction",
    "Kinematic",
    "Mechanism",
    "MechanismCheck",
    "ModelError",
    "Modes",
    "MotionEffort",
    "PointForce",
    "PointKinematics",
    "PointTorque",
    "QuasiStatic",
    "RotationalDamper",
    "Seal",
    "Solution",
    "SolverFailure",
    "SolverStats",
    "Spring",
    "StateView",
    "Static",
    "Status",
    "System",
    "TableLaw",
    "TorsionSpring",
    "check_model",
    "inspect_mechanism",
    "make_system",
    "solve",
]


__getattr__, __dir__ = lazy_names(__name__, _HOMES, globals(), __all__)


class _Package(types.ModuleType):
    """mechlib itself: importing the submodule `mechlib.solve` does not hide the function
    `mechlib.solve` (as the eager imports had it, the public name wins)."""

    def __setattr__(self, name: str, value: Any) -> None:
        if name in _HOMES and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
