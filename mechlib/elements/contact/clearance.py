"""Clearance joints as force elements: a ball in a socket, a pin in a hole (seed 004 ch. 3).

A clearance joint is a `Contact` whose geometry is `SphereInSphere` (spherical clearance
joint) or `CylinderInCylinder` (revolute clearance joint). Besides the contact outputs it
reports the eccentricity e = centre 1 - centre 2 (m, global axes: `ex ey ez`, magnitude
`eccentricity`) and its polar angle `angle` (rad, in (-pi, pi]) about a body-2-fixed axis (the
hole's axis, or `polar_axis` for a ball), measured from a body-2-fixed reference direction
normal to it (global x at design, or global y when the axis is along x), with its parts
normal to the axis (`radial`, m) and along it (`axial`, m), and the joint's `clearance` (m).

The wear indicator of seed 004 ch. 5 is the contact's `wear` output, F_N * |v_t| (W: normal
force times the tangential sliding speed at the contact point). A clearance joint also
integrates it in time, as an element state (mechlib.elements.states: trapezoidal rule over each
step of the analysis, with the mechanism), into the wear work `wear_work` = integral of
F_N |v_t| dt (J) since the start of the analysis. With an Archard wear law (`ArchardWear`)
it also reports the wear depth `wear_depth` (m) that work removes from the track.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from mechlib.elements.contact.element import Contact
from mechlib.elements.contact.geometry import CylinderInCylinder, SphereInSphere, unit
from mechlib.kinematics.view import StateView

__all__ = [
    "ArchardWear",
    "ClearanceJoint",
    "polar_reference",
    "revolute_clearance",
    "spherical_clearance",
]

_ECCENTRICITY_UNITS = {
    "ex": "m",
    "ey": "m",
    "ez": "m",
    "eccentricity": "m",
    "angle": "rad",
    "radial": "m",
    "axial": "m",
    "clearance": "m",
    "wear_work": "J",
    "wear_depth": "m",
}
_CLEARANCE_UNITS = {**Contact.output_units, **_ECCENTRICITY_UNITS}


def polar_reference(axis: np.ndarray) -> np.ndarray:
    """Unit reference direction normal to `axis`: global x projected, else global y."""
    for candidate in (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])):
        r = candidate - (candidate @ axis) * axis
        if np.linalg.norm(r) > 0.5:
            return unit(r)
    raise ValueError("no reference direction")  # unreachable for a unit axis


@dataclass(frozen=True)
class ArchardWear:
    """Archard's law: worn volume V = k W / H, W the wear work F_N * sliding distance (J),
    k the dimensionless wear coefficient, H the hardness of the softer surface (Pa). The
    depth is V over the worn area, a track of `track_width` (m) round the socket or hole
    of radius r (m): depth = k W / (H * 2 pi r * track_width), the mean depth round it; a
    sector of the track that took the fraction f of W is worn f * 2 pi / (its angle) times
    as deep."""

    coefficient: float
    hardness: float
    track_width: float

    def depth(self, work: float, radius: float) -> float:
        """Mean wear depth (m) round the track of radius `radius` (m) after wear work (J)."""
        area = 2.0 * math.pi * radius * self.track_width
        return self.coefficient * work / (self.hardness * area)


@dataclass
class ClearanceJoint(Contact):
    """A contact between a ball and its socket or a pin and its hole, with eccentricity."""

    polar_axis: Sequence[float] = (0.0, 0.0, 1.0)
    wear_law: ArchardWear | None = None
    _polar: tuple = field(default=(), repr=False)
    n_states = 1  # the wear work (J), mechlib.elements.states
    states_drive_forces = False  # an output only: the contact force never reads it
    output_units = _CLEARANCE_UNITS

    def bind(self, system) -> None:
        super().bind(system)
        axis = unit(getattr(self.geometry, "axis", self.polar_axis))
        self._polar = (axis, polar_reference(axis))  # body-2 axes = global at design

    def eccentricity(self, view: StateView) -> tuple[np.ndarray, float]:
        """Eccentricity vector (m, global) and its polar angle (rad) about the body-2 axis."""
        e, angle, _ = self._polar_parts(view)
        return e, angle

    def _polar_parts(self, view: StateView) -> tuple[np.ndarray, float, float]:
        """Eccentricity (m, global), its polar angle (rad) and its part along the axis (m)."""
        e = self.geometry.gap(view).eccentricity
        rot2 = view.rotation(self._b2)
        axis, ref = rot2 @ self._polar[0], rot2 @ self._polar[1]
        angle = math.atan2(float(np.cross(ref, e) @ axis), float(ref @ e))
        return e, angle, float(axis @ e)

    def initial_states(self) -> np.ndarray:
        """The wear work at the start of an analysis: 0 J."""
        return np.zeros(1)

    def state_rates(self, view: StateView, z: np.ndarray) -> np.ndarray:
        """d(wear work)/dt = F_N |v_t| (W) at the state `view` (0 while switched off)."""
        if not self.active:
            return np.zeros(1)
        f = self.forces(view)
        return np.array([f.normal * f.sliding_speed])

    def output(self, view: StateView) -> dict[str, float]:
        out = super().output(view)
        e, angle, axial = self._polar_parts(view)
        size = float(np.linalg.norm(e))
        out.update(ex=e[0], ey=e[1], ez=e[2], eccentricity=size, angle=angle)
        out.update(
            radial=math.sqrt(max(size * size - axial * axial, 0.0)),
            axial=axial,
            clearance=float(self.geometry.clearance),
            wear_work=self._wear_work(view),
        )
        if self.wear_law is not None:
            socket = float(self.geometry.radius + self.geometry.clearance)
            out["wear_depth"] = self.wear_law.depth(out["wear_work"], socket)
        return out

    def _wear_work(self, view: StateView) -> float:
        """The integrated wear work (J); 0 for a joint evaluated outside a system's
        analysis (bound by hand: no state was integrated for it)."""
        states = getattr(view.system, "states", None)
        if states is None or id(self) not in states.slices:
            return 0.0
        return float(view.states(self)[0])


def spherical_clearance(
    name: str,
    bodies: tuple[str, str],
    *,
    center,
    radius: float,
    clearance: float,
    law,
    friction=None,
    polar_axis=(0.0, 0.0, 1.0),
    offset=(0.0, 0.0, 0.0),
    wear_law: ArchardWear | None = None,
) -> ClearanceJoint:
    """Ball (radius, m) of body 1 in the socket (radius + clearance) of body 2 at `center`;
    the ball's centre at design is `center` + `offset` (m, an assembly error)."""
    return ClearanceJoint(
        name,
        bodies,
        SphereInSphere(center, radius, clearance, offset),
        law,
        friction,
        polar_axis=polar_axis,
        wear_law=wear_law,
    )


def revolute_clearance(
    name: str,
    bodies: tuple[str, str],
    *,
    center,
    axis,
    radius: float,
    clearance: float,
    law,
    friction=None,
) -> ClearanceJoint:
    """Pin (radius, m) of body 1 in the hole (radius + clearance) of body 2, along `axis`."""
    return ClearanceJoint(
        name, bodies, CylinderInCylinder(center, axis, radius, clearance), law, friction
    )
