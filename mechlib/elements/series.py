"""A structure in series with a hinge (seed 003 eq. 2.7): the latch-up spring of a hinge
line whose hinges have a measured, non-linear stiffness law.

K_TOT = (1 / K_STRUCT + 1 / K_HINGES)^-1 for linear springs. With a tabulated hinge law
M = hinge(h) (N*m vs hinge turn h, rad) the turn phi of the hinge line splits as
phi = h + M / K_STRUCT, the same moment M in both; `SeriesLaw(phi)` solves
hinge(h) = K_STRUCT (phi - h) for h (Brent, to 1e-14 rad) and returns M.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["SeriesLaw", "series_stiffness"]

_XTOL = 1e-14  # rad: far below the finite-difference steps taken on the moment


def series_stiffness(structure: float, hinge: float) -> float:
    """(1 / structure + 1 / hinge)^-1 in N*m/rad (eq. 2.7)."""
    return 1.0 / (1.0 / structure + 1.0 / hinge)


@dataclass(frozen=True)
class SeriesLaw:
    """Moment (N*m) vs turn (rad) of `hinge` (a law, moment vs hinge turn, increasing
    through hinge(0) = 0) in series with a linear structure of `structure` N*m/rad."""

    hinge: Callable[[float], float]
    structure: float

    def __call__(self, turn: float) -> float:
        if turn == 0.0:
            return float(self.hinge(0.0))

        def unbalance(h: float) -> float:
            return self.hinge(h) - self.structure * (turn - h)

        from scipy.optimize import brentq  # here: building a model imports no scipy.optimize

        low, high = sorted((0.0, turn))
        h = brentq(unbalance, low, high, xtol=_XTOL, rtol=1e-15)
        return self.structure * (turn - h)
