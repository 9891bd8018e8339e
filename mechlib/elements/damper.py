"""Rotational (eddy-current) damper on a joint: torque = -c * omega (seed 003 2.2.6, 4.2.4)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from mechlib.elements.forces import resist_rotation
from mechlib.kinematics.view import StateView

__all__ = ["RotationalDamper"]


@dataclass
class RotationalDamper:
    """Damper on revolute/cylindrical joint `joint`: moment = damping (N*m*s/rad) * omega
    (rad/s), resisting the rotation of body 1 relative to body 2 (body 1 gets -moment about
    the joint axis, body 2 +moment)."""

    name: str
    joint: str
    damping: float
    effect: str = "damping"
    active: bool = True
    output_units: ClassVar[dict[str, str]] = {"value": "N*m", "omega": "rad/s"}

    def bind(self, system) -> None:
        self._m = system.measure(self.joint, "angle")

    def state_bodies(self) -> set[int]:
        """The joint's two bodies, whose relative rate sets the moment
        (mechlib.system.fd_columns)."""
        return {self._m.bi, self._m.bj}

    def _moment(self, view: StateView) -> tuple[float, float]:
        omega = self._m.rate(view.kin)
        return self.damping * omega, omega

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        resist_rotation(view, self._m, self._moment(view)[0], N)

    def output(self, view: StateView) -> dict[str, float]:
        """value: the resisting moment c * omega (N*m); omega (rad/s)."""
        moment, omega = self._moment(view)
        return {"value": moment, "omega": omega}
