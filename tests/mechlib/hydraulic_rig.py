"""The equivalent single-DOF rig of the servo-actuator tests: a rod of mass M on a prismatic
joint along x, the actuator between the rod (x = 0 at design) and ground 0.5 m behind it."""

from __future__ import annotations

import numpy as np

import mechlib as ml
from mechlib.elements.hydraulics import ServoActuator

REQUESTS = [
    ml.ElementOutput("act", "act"),
    ml.JointCoordinate("x", "slide", "travel"),
    ml.JointCoordinate("v", "slide", "speed"),
]


def rig(command=lambda t: 0.0, *, mass: float = 100.0, load: float = 0.0, **actuator):
    """The rig; `load` (N): a constant force on the rod resisting extension."""
    m = ml.Mechanism()
    m.add_body("rod", mass=mass, cm=(0, 0, 0), inertia=[1, 1, 1])
    m.add_joint("slide", "prismatic", bodies=("rod", "ground"), at=(0, 0, 0), axis=(1, 0, 0))
    points = (("rod", (0.0, 0.0, 0.0)), ("ground", (-0.5, 0.0, 0.0)))
    m.add_force(ServoActuator("act", points, command, **actuator))
    if load:
        m.add_force(ml.PointForce("load", "rod", (0, 0, 0), lambda t, view: (-load, 0.0, 0.0)))
    return m


def crossings(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Times (s) of the upward zero crossings of y, linearly interpolated."""
    i = np.nonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))[0]
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])


def rise_time(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """First time (s) y reaches `level`, linearly interpolated."""
    i = int(np.argmax(y >= level))
    return float(t[i - 1] + (level - y[i - 1]) * (t[i] - t[i - 1]) / (y[i] - y[i - 1]))
