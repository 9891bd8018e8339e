"""mechlib: rigid multibody mechanics in absolute coordinates (NumPy/SciPy, SI units).

Build a `Mechanism`, pick an analysis, name the requests, and call `solve`.
"""

from mechlib.analysis import DEFAULT_MAX_STEPS, Dynamic, Kinematic, QuasiStatic, Static
from mechlib.assembly import InitialBodyVelocity, InitialValue
from mechlib.check import ModelError
from mechlib.contract import Status
from mechlib.elements import Bushing, CableLoop, JointFriction, RotationalDamper, Seal, TableLaw
from mechlib.energy import EnergyBalance
from mechlib.events import Action, Event
from mechlib.forces import PointForce, PointTorque, Spring, TorsionSpring
from mechlib.model import GROUND, Mechanism
from mechlib.modes import Modes
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
from mechlib.solve import MechanismCheck, check_model, inspect_mechanism, solve
from mechlib.system import System
from mechlib.view import StateView

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
    "solve",
]
