"""mechlib: rigid multibody mechanics in absolute coordinates (NumPy/SciPy, SI units).

Build a `Mechanism`, pick an analysis, name the requests, and call `solve`. Each name is
imported on first use (PEP 562): `from mechlib.model.joints import ROTATIONAL` (the schema's
joint types, `loads validate`) then loads no solver, SciPy or numba.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from mechlib.core.lazy import lazy_names

if TYPE_CHECKING:
    from mechlib.checks.model_check import MechanismCheck, check_model, inspect_mechanism
    from mechlib.core.outcome import ModelError, Solution, SolverFailure, SolverStats, Status
    from mechlib.elements import (
        Bushing,
        CableLoop,
        JointFriction,
        JointLimit,
        RotationalDamper,
        Seal,
        TableLaw,
    )
    from mechlib.elements.forces import PointForce, PointTorque, Spring, TorsionSpring
    from mechlib.kinematics.view import StateView
    from mechlib.model.analysis import (
        DEFAULT_MAX_STEPS,
        BranchCheck,
        Dynamic,
        InitialBodyVelocity,
        InitialModes,
        InitialValue,
        Kinematic,
        Modes,
        Phase,
        Phases,
        QuasiStatic,
        Static,
    )
    from mechlib.model.mechanism import GROUND, Mechanism
    from mechlib.model.step_grid import StepGrid
    from mechlib.outputs.energy import EnergyBalance
    from mechlib.outputs.requests import (
        CouplerEffort,
        ElementOutput,
        ExpressionOutput,
        FlexibleOutput,
        JointCoordinate,
        JointReaction,
        MotionEffort,
        PointKinematics,
    )
    from mechlib.solvers.events import Action, Event
    from mechlib.solvers.solve import solve
    from mechlib.solvers.solve_memo import SolveMemo
    from mechlib.system.planar import make_system
    from mechlib.system.system import System

# name -> the module that defines it
_HOMES = {
    "DEFAULT_MAX_STEPS": "mechlib.model.analysis",
    "GROUND": "mechlib.model.mechanism",
    "Action": "mechlib.solvers.events",
    "Bushing": "mechlib.elements.bushing",
    "CableLoop": "mechlib.elements.cable_loop",
    "CouplerEffort": "mechlib.outputs.requests",
    "Dynamic": "mechlib.model.analysis",
    "StepGrid": "mechlib.model.step_grid",
    "ElementOutput": "mechlib.outputs.requests",
    "EnergyBalance": "mechlib.outputs.energy",
    "Event": "mechlib.solvers.events",
    "ExpressionOutput": "mechlib.outputs.requests",
    "FlexibleOutput": "mechlib.outputs.requests",
    "InitialBodyVelocity": "mechlib.model.analysis",
    "InitialModes": "mechlib.model.analysis",
    "BranchCheck": "mechlib.model.analysis",
    "InitialValue": "mechlib.model.analysis",
    "JointCoordinate": "mechlib.outputs.requests",
    "JointFriction": "mechlib.elements.friction",
    "JointLimit": "mechlib.elements.joint_limit",
    "JointReaction": "mechlib.outputs.requests",
    "Kinematic": "mechlib.model.analysis",
    "Mechanism": "mechlib.model.mechanism",
    "MechanismCheck": "mechlib.checks.model_check",
    "ModelError": "mechlib.core.outcome",
    "Modes": "mechlib.model.analysis",
    "MotionEffort": "mechlib.outputs.requests",
    "PointForce": "mechlib.elements.forces",
    "PointKinematics": "mechlib.outputs.requests",
    "PointTorque": "mechlib.elements.forces",
    "Phase": "mechlib.model.analysis",
    "Phases": "mechlib.model.analysis",
    "QuasiStatic": "mechlib.model.analysis",
    "RotationalDamper": "mechlib.elements.damper",
    "Seal": "mechlib.elements.seal",
    "Solution": "mechlib.core.outcome",
    "SolverFailure": "mechlib.core.outcome",
    "SolverStats": "mechlib.core.outcome",
    "SolveMemo": "mechlib.solvers.solve_memo",
    "Spring": "mechlib.elements.forces",
    "StateView": "mechlib.kinematics.view",
    "Static": "mechlib.model.analysis",
    "Status": "mechlib.core.outcome",
    "System": "mechlib.system.system",
    "TableLaw": "mechlib.elements.laws",
    "TorsionSpring": "mechlib.elements.forces",
    "check_model": "mechlib.checks.model_check",
    "inspect_mechanism": "mechlib.checks.model_check",
    "make_system": "mechlib.system.planar",
    "solve": "mechlib.solvers.solve",
}

__all__ = [
    "DEFAULT_MAX_STEPS",
    "GROUND",
    "Action",
    "BranchCheck",
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
    "InitialModes",
    "InitialValue",
    "JointCoordinate",
    "JointFriction",
    "JointLimit",
    "JointReaction",
    "Kinematic",
    "Mechanism",
    "MechanismCheck",
    "ModelError",
    "Modes",
    "MotionEffort",
    "Phase",
    "Phases",
    "PointForce",
    "PointKinematics",
    "PointTorque",
    "QuasiStatic",
    "RotationalDamper",
    "Seal",
    "Solution",
    "SolveMemo",
    "SolverFailure",
    "SolverStats",
    "Spring",
    "StateView",
    "Static",
    "Status",
    "StepGrid",
    "System",
    "TableLaw",
    "TorsionSpring",
    "check_model",
    "inspect_mechanism",
    "make_system",
    "solve",
]


__getattr__, __dir__ = lazy_names(__name__, _HOMES, globals(), __all__)
