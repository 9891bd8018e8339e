"""The coordinate equations of a system (motions, locks, couplers, gears, screws, held
coordinates) evaluated together.

Each angle measure is a pair of Dot1 rows (sine and cosine), each travel one Dot2 row
(mechlib.kinematics.coordinates); here all angles are one Dot1 group and all travels one Dot2 group,
so that a system's coordinate rows cost four compiled calls, not two per measure (the door:
five equations on eight measures were 80 % of its constraint Jacobian's time). Equations
are the measures combined by a coefficient matrix. Other equations (a point on a curve)
are evaluated one by one, as they give themselves.
"""

from __future__ import annotations

import numpy as np

from mechlib.kinematics.constraints import Dot1, Dot2
from mechlib.kinematics.coordinates import (
    TWO_PI,
    AngleMeasure,
    CoordinateEquation,
    TravelMeasure,
    angle_gradient,
    angle_quad,
)
from mechlib.kinematics.kin import Kin

__all__ = ["CoordinateBlock"]


class CoordinateBlock:
    """phi, gradient rows and gamma of `equations` (a system's coordinate equations, in
    order); rad for angles, m for travels."""

    def __init__(self, equations: list):
        self.equations = equations
        self.size = len(equations)
        self.linear = [i for i, e in enumerate(equations) if isinstance(e, CoordinateEquation)]
        self.own = [i for i, e in enumerate(equations) if not isinstance(e, CoordinateEquation)]
        measures = {id(m): m for i in self.linear for _, m in equations[i].terms}
        self.angles = [m for m in measures.values() if isinstance(m, AngleMeasure)]
        self.travels = [m for m in measures.values() if isinstance(m, TravelMeasure)]
        self._sines = _joined(Dot1, [m.sine_cosine for m in self.angles])
        self._distances = _joined(Dot2, [m.distance for m in self.travels])
        ordered: list = [*self.angles, *self.travels]
        column = {id(m): j for j, m in enumerate(ordered)}
        # equations = coefficients @ measures
        self._coefficients = np.zeros((len(self.linear), len(column)))
        for row, i in enumerate(self.linear):
            for c, m in equations[i].terms:
                self._coefficients[row, column[id(m)]] += c
        na = len(self.angles)
        # the equations on angles alone driven by a function of time fix the turn of the
        # angles they hold; a constant one (a lock, a stick anchor: a held value read on
        # the angle's own turn) and a gear without a function leave the angle continuous
        driven = np.array(
            [
                (f := equations[i].function) is not None and not getattr(f, "constant", False)
                for i in self.linear
            ],
            dtype=bool,
        )
        self._angle_rows = np.flatnonzero(
            ~self._coefficients[:, na:].any(axis=1)
            & self._coefficients[:, :na].any(axis=1)
            & driven
        )

    def _function(self, t: float, part: str) -> np.ndarray:
        """value, rate or accel of each linear equation's function of time (0 without)."""
        return np.array(
            [getattr(f, part)(t) if (f := self.equations[i].function) else 0.0 for i in self.linear]
        )

    def aim_references(self, t: float, limit: float) -> list[tuple[str, float]]:
        """Move the angles' unwrapping references (rad) by the least change that meets the
        motions on angles alone at time t (a drive's value), so that
        Newton at t unwraps each held angle on its own turn: from the reference before, an
        angle more than pi away could not be reached (a drive turning thousands of radians
        between two solved states). Angles no such equation holds keep theirs. Returns
        (label, target) of the equations whose target is not finite or beyond `limit` (rad),
        the references then unchanged."""
        rows = self._angle_rows
        if not rows.size:
            return []
        target = self._function(t, "value")[rows]
        beyond = ~(np.abs(target) <= limit)
        if beyond.any():
            labels = [self.equations[self.linear[r]].label for r in rows[beyond]]
            return list(zip(labels, target[beyond].tolist()))
        matrix = self._coefficients[rows, : len(self.angles)]
        ref = np.array([m.reference for m in self.angles])
        change, *_ = np.linalg.lstsq(matrix, target - matrix @ ref, rcond=None)
        for m, value in zip(self.angles, ref + change):
            m.reference = float(value)
        return []

    def sines(self, k: Kin) -> np.ndarray | None:
        """The angles' interleaved (sine, cosine) rows at k, for `phi` and `jacobian` to
        share (None without angles)."""
        return None if self._sines is None else self._sines.phi(k)

    def phi(self, k: Kin, sines: np.ndarray | None = None) -> np.ndarray:
        """The equations' residuals; `sines`: `self.sines(k)` when the caller has them."""
        out = np.empty(self.size)
        if not self.size:
            return out
        values = np.concatenate((self._angle_values(k, sines), self._travel_values(k)))
        out[self.linear] = self._coefficients @ values - self._function(k.t, "value")
        for i in self.own:
            out[i] = self.equations[i].phi(k)
        return out

    def jacobian(self, k: Kin, out: np.ndarray, sines: np.ndarray | None = None) -> None:
        """The rows (size, ncol) into `out`; `sines` as for `phi`."""
        if not self.size:
            return
        grads = np.empty((len(self.angles) + len(self.travels), k.ncol))
        na = len(self.angles)
        if self._sines is not None:
            s, c = self._pairs(self._sines.phi(k) if sines is None else sines)
            rows = np.zeros((2 * na, k.ncol))
            self._sines.jacobian(k, rows)
            grads[:na] = angle_gradient(s[:, None], c[:, None], rows[0::2], rows[1::2])
        if self._distances is not None:
            grads[na:] = 0.0
            self._distances.jacobian(k, grads[na:])
        out[self.linear] = self._coefficients @ grads
        for i in self.own:
            out[i] = self.equations[i].gradient(k)

    def gamma(self, k: Kin) -> np.ndarray:
        out = np.empty(self.size)
        if not self.size:
            return out
        quads = np.concatenate((self._angle_quads(k), self._travel_quads(k)))
        out[self.linear] = self._function(k.t, "accel") - self._coefficients @ quads
        for i in self.own:
            out[i] = self.equations[i].gamma(k)
        return out

    @staticmethod
    def _pairs(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(sines, cosines) of interleaved rows."""
        return values[0::2], values[1::2]

    def _angle_values(self, k: Kin, sines: np.ndarray | None = None) -> np.ndarray:
        """Unwrapped angles (rad) against each measure's committed reference."""
        if self._sines is None:
            return np.zeros(0)
        s, c = self._pairs(self._sines.phi(k) if sines is None else sines)
        raw = np.arctan2(s, c)
        ref = np.array([m.reference for m in self.angles])
        return raw + TWO_PI * np.round((ref - raw) / TWO_PI)

    def _travel_values(self, k: Kin) -> np.ndarray:
        return np.zeros(0) if self._distances is None else self._distances.phi(k)

    def _angle_quads(self, k: Kin) -> np.ndarray:
        """Part of each angle's second derivative not multiplying qdd (rad/s^2)."""
        if self._sines is None:
            return np.zeros(0)
        s, c = self._pairs(self._sines.phi(k))
        sd, cd = self._pairs(self._sines.rate(k))
        sq, cq = self._pairs(-self._sines.gamma(k))
        return angle_quad(s, c, sd, cd, sq, cq)

    def _travel_quads(self, k: Kin) -> np.ndarray:
        return np.zeros(0) if self._distances is None else -self._distances.gamma(k)


def _joined(kind, groups: list):
    """One group of `kind` holding the items of `groups` in order (None when empty)."""
    if not groups:
        return None
    args = [np.concatenate([g.args[i] for g in groups]) for i in range(len(groups[0].args))]
    return kind(*args)
