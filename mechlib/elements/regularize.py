"""Regularised Coulomb friction shared by the friction elements.

Dynamic and kinematic states: the direction of sliding is the relative velocity w, and the
friction reaches its full value at |w| = threshold through the odd cubic
g(s) = s (3 - s^2) / 2 (s = |w| / threshold): continuous with a continuous slope, finite
slope 1.5 / threshold at rest (a steep viscous "stick" that never chatters), exactly 1 above.
Static states (every velocity zero: static and quasi-static analyses) use the displacement
since the last accepted state instead, with its own (small) threshold: quasi-static friction
opposes the direction of travel between consecutive equilibria.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = [
    "StaticSlipAnchor",
    "at_rest",
    "coulomb_factor",
    "coulomb_vector",
    "rotation_increment",
]


class StaticSlipAnchor:
    """Mixin of the friction elements: static slips are measured from `_anchor`, set by
    `commit` on accepted states and kept with every recorded equilibrium (so that outputs
    see what the solver saw)."""

    def static_anchor(self):
        return self._anchor

    def restore_static_anchor(self, anchor) -> None:
        self._anchor = anchor


@njit(**KERNEL)
def coulomb_factor(w: float, threshold: float) -> float:
    """Signed fraction (-1..1) of the full friction for a slip w (same unit as threshold)."""
    s = w / threshold
    if abs(s) >= 1.0:
        return 1.0 if s > 0.0 else -1.0
    return 0.5 * s * (3.0 - s * s)


def coulomb_vector(w: np.ndarray, threshold: float) -> np.ndarray:
    """Direction of sliding (..., 3) scaled by g(|w| / threshold); zero at rest."""
    w = np.asarray(w, dtype=float)
    size = np.linalg.norm(w, axis=-1, keepdims=True)
    s = size / threshold
    slow = 0.5 * (3.0 - s * s) / threshold
    with np.errstate(invalid="ignore", divide="ignore"):
        fast = np.where(size > 0.0, 1.0 / np.where(size > 0.0, size, 1.0), 0.0)
    return w * np.where(s < 1.0, slow, fast)


def at_rest(view) -> bool:
    """True in static evaluations: no body of the state moves (static, quasi-static)."""
    return not view.kin.xd.any()


def rotation_increment(r_now: np.ndarray, r_then: np.ndarray) -> np.ndarray:
    """Rotation vector (rad, global) taking orientation `r_then` to `r_now` (small angles:
    the axial vector of the skew part of r_now r_then^T)."""
    d = r_now @ r_then.T
    return 0.5 * np.array([d[2, 1] - d[1, 2], d[0, 2] - d[2, 0], d[1, 0] - d[0, 1]])
