"""Closed cable loop (CCL) synchronising two hinges (seed 003 section 2.2.5, eqs. 2.3-2.6).

Pulley 1 (radius r1) is fixed to the body of joint 1 that joint 2 does not share, coaxial with
joint 1 at its point A; pulley 2 (r2) likewise on joint 2 at B; the shared body (the yoke)
carries both hinge points. Two strands a and b, each of stiffness k (N/m) and pretension T0
(N), tension-only, an open loop (the strands do not cross):
    e_a = +(r1 phi1 - r2 phi2) + g(D) - g(D0),   e_b = -(r1 phi1 - r2 phi2) + g(D) - g(D0)
    F_a = max(0, T0 + k e_a),   F_b = max(0, T0 + k e_b)
with phi_k the rotation of pulley k relative to the yoke about joint 1's axis (+-theta_k of
the joint, by which body carries the pulley and the sense of the joint axes), D = |AB| and
g(D) = L + (r1 - r2) asin((r1 - r2) / D), L = sqrt(D^2 - (r1 - r2)^2) the free strand length
(dg/dD = L / D). The loads are those of the seed, work-consistent with these elongations:
    T1 = r1 (F_b - F_a)  on pulley 1 (2.3),   T2 = r2 (F_a - F_b)  on pulley 2 (2.4),
    F_ax = (F_a + F_b) L / D   pulling A and B together (2.5),
    F_lat = (F_a - F_b) (r1 - r2) / D   normal to AB, a couple on the pulleys (2.6).
The cable is massless: the loads on the two pulley bodies are in equilibrium, the yoke gets
none (the lateral couple carries what the torques T1 + T2 leave unbalanced).
Guided strands (`guided`, fig. 2.2.5-4): guides on the yoke hold each strand parallel to AB
(offset r1 at A, r2 at B), so g(D) = D: F_ax = F_a + F_b, no lateral force, and the yoke
takes the torque T_yoke = -(T1 + T2) = (F_a - F_b)(r1 - r2) about the hinge axis (each
pulley torque's reaction at the yoke's side of its joint; on a flexible yoke, the node
carrying that hinge).
Energy (the energy request): the loads are those of the potential
V = sum over the strands of (max(0, T0 + k e)^2 - T0^2) / (2 k) (`potential`, J; 0 at
design), the integral of each strand's tension over its elongation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from mechlib.elements import cable_loop_kernel as kernel
from mechlib.kinematics.view import StateView

__all__ = ["CableLoop"]


@dataclass
class CableLoop:
    """Cable loop over joints `joints` (revolute) with pulley `radii` (m), strand
    `stiffness` (N/m) and `pretension` (N); `guided`: strands guided along the yoke."""

    name: str
    joints: tuple[str, str]
    radii: tuple[float, float]
    stiffness: float
    pretension: float = 0.0
    guided: bool = False
    effect: str = "springs"
    active: bool = True
    output_units: ClassVar[dict[str, str]] = {
        "t1": "N*m",
        "t2": "N*m",
        "f_axial": "N",
        "f_lateral": "N",
        "t_yoke": "N*m",
        "tension_a": "N",
        "tension_b": "N",
    }

    def bind(self, system) -> None:
        joints = [system.mechanism.joints[j] for j in self.joints]
        owner = system.mechanism.owner  # a flexible yoke: its joints are on its node bodies
        shared = {owner(joints[0].body1), owner(joints[0].body2)} & {
            owner(joints[1].body1),
            owner(joints[1].body2),
        }
        if len(shared) != 1:
            raise ValueError(
                f"cable_loop '{self.name}': joints {self.joints[0]} and "
                f"{self.joints[1]} must share exactly one body (the yoke)"
            )
        self._m = [system.measure(j, "angle") for j in self.joints]
        self._ends = []  # (pulley body index, body-fixed vector of the hinge point)
        for j in joints:
            pulley = j.body1 if owner(j.body2) in shared else j.body2
            self._ends.append(system.body_point(pulley, j.at))
        along = float(self._m[0].axis_local @ self._m[1].axis_local)
        if abs(abs(along) - 1.0) > 1e-6:
            raise ValueError(f"cable_loop '{self.name}': the joint axes must be parallel")
        # phi_k = sense_k * theta_k: + when the pulley is body 1 of its joint, and joint 2's
        # rotation counted about joint 1's axis
        self._sense = [1.0 if m.bi == b else -1.0 for m, (b, _) in zip(self._m, self._ends)]
        self._sense[1] *= 1.0 if along > 0.0 else -1.0
        self._g0 = self._g(float(np.linalg.norm(np.subtract(joints[1].at, joints[0].at))))
        (b1, s1), (b2, s2) = self._ends
        m1, m2 = self._m
        yoke = m1.bj if m1.bi == b1 else m1.bi
        self._ints = np.array([b1, b2, m1.bi, m1.bj, m2.bi, m2.bj, yoke], dtype=np.int64)
        self._floats = np.concatenate(
            [s1, s2, m1.f, m1.g, m1.axis_local, m2.f, m2.g, m2.axis_local, self._sense]
            + [[*self.radii, self.stiffness, self.pretension, self._g0, float(self.guided)]]
        ).astype(float)
        assert self._ints.size == kernel.INTS and self._floats.size == kernel.FLOATS

    def state_bodies(self) -> set[int]:
        """The bodies of the two joints (pulleys and yoke): their angles and the hinge
        distance set the loads (mechlib.system.fd_columns)."""
        return {b for m in self._m for b in (m.bi, m.bj)} | {b for b, _ in self._ends}

    def _g(self, d: float) -> float:
        dr = self.radii[0] - self.radii[1]
        if d <= abs(dr):
            raise ValueError(
                f"cable_loop '{self.name}': hinge distance {d:.6g} m must exceed "
                f"|r1 - r2| = {abs(dr):.6g} m"
            )
        if self.guided:
            return d  # strands parallel to AB between the guides
        return math.sqrt(d * d - dr * dr) + dr * math.asin(dr / d)

    def _distance(self, view: StateView) -> float:
        """Hinge distance D = |AB| (m)."""
        (b1, s1), (b2, s2) = self._ends
        return float(np.linalg.norm(view.point_position(b2, s2) - view.point_position(b1, s1)))

    def _elongations(self, view: StateView) -> tuple[float, float, float]:
        """(e_a, e_b (m), hinge distance D (m))."""
        d = self._distance(view)
        r1, r2 = self.radii
        phi1, phi2 = (c * m.value(view.kin) for c, m in zip(self._sense, self._m))
        wrap, common = r1 * phi1 - r2 * phi2, self._g(d) - self._g0
        return wrap + common, -wrap + common, d

    def potential(self, view: StateView) -> float:
        """Elastic energy (J) of the two strands, 0 at design."""
        k, t0 = self.stiffness, self.pretension
        return sum(
            (max(0.0, t0 + k * e) ** 2 - t0 * t0) / (2.0 * k) for e in self._elongations(view)[:2]
        )

    def _state(self, view: StateView) -> dict:
        (b1, s1), (b2, s2) = self._ends
        a, b = view.point_position(b1, s1), view.point_position(b2, s2)
        ea, eb, d = self._elongations(view)
        r1, r2 = self.radii
        fa = max(0.0, self.pretension + self.stiffness * ea)
        fb = max(0.0, self.pretension + self.stiffness * eb)
        length = d if self.guided else math.sqrt(d * d - (r1 - r2) ** 2)
        lateral, on_yoke = (fa - fb) * (r1 - r2) / d, (fa - fb) * (r1 - r2)
        return {
            "t1": r1 * (fb - fa),
            "t2": r2 * (fa - fb),
            "f_axial": (fa + fb) * length / d,
            "f_lateral": 0.0 if self.guided else lateral,
            "t_yoke": on_yoke if self.guided else 0.0,
            "tension_a": fa,
            "tension_b": fb,
            "a": a,
            "b": b,
            "d": d,
        }

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        """Add the loads (eqs. 2.3-2.6) to F and N (mechlib.elements.cable_loop_kernel: the
        pulley torques as pairs on each joint's bodies; the yoke's share of them moved to a
        couple of forces at A and B on the pulleys, the same virtual work since A and B are
        points of the yoke; a part along AB stays a torque on the yoke)."""
        m1, m2 = self._m
        x, xd = view.kin.x, view.kin.xd
        if not kernel.cable_loop_wrench(
            x, xd, self._ints, self._floats, m1.reference, m2.reference, F, N
        ):
            self._g(self._distance(view))  # raises: the hinges are too close
            F[self._ints[0]] += (
                np.nan
            )  # a non-finite state: non-finite loads (mechlib.solvers.finite)

    def output(self, view: StateView) -> dict[str, float]:
        """t1, t2 (N*m, eqs. 2.3-2.4), f_axial, f_lateral (N, eqs. 2.5-2.6), the guided
        strands' torque on the yoke t_yoke (N*m, about joint 1's axis in the sense of phi; 0
        when free), strand tensions tension_a, tension_b (N)."""
        st = self._state(view)
        return {k: st[k] for k in self.output_units}
