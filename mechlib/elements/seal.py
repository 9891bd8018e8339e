"""Distributed seal: N springs spread along a line (seed 000 section 3.1.6).

Body 1 carries the sealing knife, a line from `start` to `end` (design points, m); body 2 the
rubber seal, with `normal` (fixed in body 2) pointing from the seal towards body 1. Station
i = 0..N-1 sits at the midpoint of its 1/N share of the line, s_i = start + (i + 1/2)/N
(end - start), and has a twin point fixed in body 2 at the same design position. Penetration
x_i = -(P_i - S_i) . n - gap (m); line load w(x) = stiffness x^exponent (N/m per metre of
seal, i.e. stiffness in N/m^(1+exponent)) or a table `law(x)`; force of a station
F_i = (length / N) w(x_i) for x_i > 0, along n on body 1 (the reverse on body 2).
Friction mu F_i opposes the tangential slip of P_i on body 2 (regularised Coulomb, see
`mechlib.elements.regularize`). The stations integrate the line load by the midpoint rule,
exact for a linear law under a linearly varying penetration.

Energy (the energy request, mechlib.outputs.energy): `potential` sums the stations' share times
the integral of the line load over their penetration (exact for the power law and a
tabulated law, `TableLaw.integral`); `dissipation` is the friction's power.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from mechlib.core.rotation import omega_global, rotate
from mechlib.elements.forces import has_potential, stored
from mechlib.elements.regularize import StaticSlipAnchor, at_rest
from mechlib.elements.seal_kernels import seal_apply, seal_friction, seal_stations, seal_wrench
from mechlib.kinematics.view import StateView

__all__ = ["Seal"]


@dataclass
class Seal(StaticSlipAnchor):
    """Seal between `bodies` (knife on body 1, seal on body 2) along `start`-`end` (m) with
    `count` springs; `stiffness`, `exponent`, `law` (line load, N/m, vs penetration, m),
    `gap` (m), `mu` (-), `v_threshold` (m/s), `slip_threshold` (m)."""

    name: str
    bodies: tuple[str, str]
    start: Sequence[float]
    end: Sequence[float]
    normal: Sequence[float]
    count: int = 7
    stiffness: float = 0.0
    exponent: float = 1.0
    law: Callable[[float], float] | None = None
    gap: float = 0.0
    mu: float = 0.0
    v_threshold: float = 1.0e-3
    slip_threshold: float = 1.0e-6
    effect: str = "contact"
    active: bool = True
    output_units: ClassVar[dict[str, str]] = {
        "normal": "N",
        "friction": "N",
        "penetration": "m",
        "fx": "N",
        "fy": "N",
        "fz": "N",
    }
    _anchor: np.ndarray | None = field(default=None, repr=False)

    def bind(self, system) -> None:
        if self.count < 1:
            raise ValueError(f"seal '{self.name}': springs must be >= 1")
        start, end = np.asarray(self.start, float), np.asarray(self.end, float)
        self._share = float(np.linalg.norm(end - start)) / self.count  # m of seal per spring
        stations = start + (np.arange(self.count)[:, None] + 0.5) / self.count * (end - start)
        self._b1 = system.body_index(self.bodies[0])
        self._b2 = system.body_index(self.bodies[1])
        self._s1 = stations - system.cm[self._b1]
        self._s2 = stations - system.cm[self._b2]
        n = np.asarray(self.normal, float)
        self._n = n / np.linalg.norm(n)  # in body 2 (design axes = global at design)
        self._anchor = np.zeros((self.count, 3))

    def _line_load(self, x: np.ndarray) -> np.ndarray:
        """w(x) (N/m) for penetrations x > 0, zero elsewhere."""
        inside = np.maximum(x, 0.0)
        if self.law is not None:
            return np.array([self.law(v) if v > 0.0 else 0.0 for v in x])
        return self.stiffness * inside**self.exponent

    def _loads(self, view: StateView) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(P_i (N, 3), normal forces F_i (N,), friction forces on body 1 (N, 3), x_i)."""
        p1, _, normal, friction, x = self._parts(view)
        return p1, normal, friction, x

    def _parts(self, view: StateView):
        """(P_i (N, 3), the normal n (3,), F_i (N,), friction forces on body 1 (N, 3), x_i)."""
        p1, p2, n, x = self._stations(view)
        normal = self._share * self._line_load(x)
        friction = np.zeros_like(p1)
        if self.mu != 0.0:
            k, rest = view.kin, at_rest(view)
            threshold = self.slip_threshold if rest else self.v_threshold
            anchor = self._anchor if rest else p1  # the static slip's start (unused moving)
            seal_friction(
                k.x, k.xd, self._b1, self._b2, self._s1, p1, p2, n, normal, self.mu,
                anchor, rest, threshold, friction,
            )  # fmt: skip
        return p1, n, normal, friction, x

    def _stations(self, view: StateView):
        """(P_i (N, 3), their twins S_i in body 2 (N, 3), the normal (3,), x_i (m))."""
        p1, p2 = np.empty((self.count, 3)), np.empty((self.count, 3))
        n, x = np.empty(3), np.empty(self.count)
        seal_stations(
            view.kin.x, self._b1, self._b2, self._s1, self._s2, self._n, self.gap, p1, p2, n, x
        )
        return p1, p2, n, x

    def _slip_velocity(self, view: StateView, p1: np.ndarray) -> np.ndarray:
        """Velocity (m/s, (N, 3)) of body 1's points P_i relative to body 2's points under
        them."""
        k = view.kin
        v1 = np.array([view.point_velocity(self._b1, s) for s in self._s1])
        omega2 = omega_global(k.p[self._b2], k.pd[self._b2])
        return v1 - (k.rd[self._b2] + np.cross(omega2, p1 - k.r[self._b2]))

    @property
    def potential(self):
        """Elastic energy (J) at a view: the line load integrated over each station's
        penetration, times its share of the seal; None with a law that has no exact
        integral (its work is then load work)."""
        return self._potential if has_potential(self.law) else None

    def _potential(self, view: StateView) -> float:
        x = self._stations(view)[3]
        pressed = x[x > 0.0]
        if self.law is not None:
            return self._share * sum(stored(self.law, 0.0, float(v)) for v in pressed)
        n = self.exponent
        return self._share * self.stiffness * float(np.sum(pressed ** (n + 1.0))) / (n + 1.0)

    def dissipation(self, view: StateView) -> float:
        """Power (W, >= 0) of the friction: -sum friction_i . slip velocity_i."""
        return 0.0 if at_rest(view) else self.rest_dissipation(view, view.kin)

    def rest_dissipation(self, view: StateView, moving) -> float:
        """Power (W) of the friction of `view` (at an equilibrium: against the slip since
        the last accepted state) while the bodies move at the rates of `moving` (a Kin)."""
        if self.mu == 0.0:
            return 0.0
        p1, _, friction, _ = self._loads(view)
        slip = self._slip_velocity(view.system.view(moving), p1)
        return -float(np.sum(friction * slip))

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        if self.law is None:  # the power law: one compiled call
            k, rest = view.kin, at_rest(view)
            threshold = self.slip_threshold if rest else self.v_threshold
            seal_apply(
                k.x, k.xd, self._b1, self._b2, self._s1, self._s2, self._n, float(self.gap),
                self._share, float(self.stiffness), float(self.exponent), float(self.mu),
                self._anchor, rest, threshold, F, N,
            )  # fmt: skip
            return
        p1, n, normal, friction, _ = self._parts(view)
        seal_wrench(view.kin.x, self._b1, self._b2, p1, n, normal, friction, F, N)

    def commit(self, view: StateView) -> None:
        """Accepted state: anchors of the static slips."""
        k = view.kin
        self._anchor = (
            k.r[self._b1]
            + rotate(k.p[self._b1], self._s1)
            - k.r[self._b2]
            - rotate(k.p[self._b2], self._s2)
        )

    def body_pair(self) -> tuple[int, int]:
        """The two body indices whose states alone set this element's forces."""
        return self._b1, self._b2

    def state_bodies(self) -> tuple[int, int]:
        """The body pair (mechlib.system.fd_columns)."""
        return self.body_pair()

    def output(self, view: StateView) -> dict[str, float]:
        """normal, friction: totals of the stations (N); penetration: the largest (m);
        fx fy fz: resultant force on body 1 (N, global)."""
        _, n, normal, friction, x = self._parts(view)
        fx, fy, fz = normal.sum() * n + friction.sum(axis=0)
        return {
            "normal": float(normal.sum()),
            "friction": float(np.linalg.norm(friction, axis=1).sum()),
            "penetration": float(x.max()),
            "fx": fx,
            "fy": fy,
            "fz": fz,
        }
