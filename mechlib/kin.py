"""Per-body kinematic arrays of one state, ground appended as the last body.

Symbols: ``q`` stacks ``[r_b, p_b]`` (7 per moving body; r in m, p Euler parameters),
``qd`` their rates. Ground is body index ``nb`` with r = 0, p = (1, 0, 0, 0) and no columns
in the Jacobians that leave this module (its 7 columns are sliced off).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Kin", "GROUND_Q"]

GROUND_Q = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])


@dataclass
class Kin:
    """Positions ``r`` (nb+1, 3), Euler parameters ``p`` (nb+1, 4) and their rates."""

    r: np.ndarray
    p: np.ndarray
    rd: np.ndarray
    pd: np.ndarray
    t: float = 0.0

    @property
    def nb(self) -> int:
        """Number of moving bodies."""
        return self.r.shape[0] - 1

    @property
    def ncol(self) -> int:
        """Columns of the working Jacobian (ground included)."""
        return 7 * (self.nb + 1)

    @classmethod
    def from_state(cls, q: np.ndarray, qd: np.ndarray | None = None, t: float = 0.0) -> "Kin":
        """Split the stacked state (7 nb,) into per-body arrays with ground appended."""
        full = np.concatenate([q, GROUND_Q]).reshape(-1, 7)
        if qd is None:
            fulld = np.zeros_like(full)
        else:
            fulld = np.concatenate([qd, np.zeros(7)]).reshape(-1, 7)
        return cls(full[:, :3], full[:, 3:], fulld[:, :3], fulld[:, 3:], t)
