"""Normal-force laws of contact: impact, Hertz with Lankarani-Nikravesh damping, restitution.

Each law gives the normal force F_N (N, >= 0) from the penetration x (m, > 0 in contact),
its rate xd (m/s, > 0 approaching) and `approach`, the penetration rate stored when the
contact began (m/s, the element's memory; only the laws with `remembers` use it). The
force is continuous in x and xd (a kink at most), which keeps stiff contact stable under
the integrator's finite-difference Jacobian.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from mechlib.smooth import step

__all__ = ["step", "ImpactLaw", "HertzLaw", "RestitutionLaw", "hertz_stiffness",
           "MIN_APPROACH_SPEED", "RATE_RATIO_CAP"]

MIN_APPROACH_SPEED = 1.0e-3
"""m/s: floor of the stored approach speed (a contact that starts at rest would otherwise
divide by zero in the hysteresis damping factor)."""

RATE_RATIO_CAP = 10.0
"""|xd / xd(-)| beyond this (no impact reaches it: |xd| <= xd(-) in a free impact) is held
there, so that a wild Newton iterate cannot make the damping term explode."""


def _rate_ratio(xd: float, approach: float) -> float:
    ratio = xd / max(approach, MIN_APPROACH_SPEED)
    return min(max(ratio, -RATE_RATIO_CAP), RATE_RATIO_CAP)


def hertz_stiffness(E1: float, nu1: float, E2: float, nu2: float, radius: float) -> float:
    """K (N/m^1.5) of two elastic bodies (seed 004 eqs. 3.4-3.5):
    K = 4 / (3 pi (h1 + h2)) * sqrt(R), h = (1 - nu^2) / (pi E), R the effective radius (m)
    (R1 R2 / (R1 + R2) outside, R1 R2 / (R2 - R1) for a ball in a socket)."""
    h1 = (1.0 - nu1 * nu1) / (math.pi * E1)
    h2 = (1.0 - nu2 * nu2) / (math.pi * E2)
    return 4.0 / (3.0 * math.pi * (h1 + h2)) * math.sqrt(radius)


@dataclass(frozen=True)
class ImpactLaw:
    """F = k x^e + step(x, 0, 0, depth, c_max) * xd, never negative (seed 000 sec. 2.2.5).

    stiffness k (N/m^e), exponent e (-), damping c_max (N*s/m) reached at `depth` (m)."""

    stiffness: float
    exponent: float = 1.5
    damping: float = 0.0
    depth: float = 1.0e-4
    remembers = False

    def force(self, x: float, xd: float, approach: float = 0.0) -> float:
        if x <= 0.0:
            return 0.0
        damping = step(x, 0.0, 0.0, self.depth, self.damping) if self.damping else 0.0
        return max(self.stiffness * x ** self.exponent + damping * xd, 0.0)


@dataclass(frozen=True)
class HertzLaw:
    """F = K x^n (1 + 3 (1 - e^2) / 4 * xd / xd(-)), never negative: Hertz with the
    Lankarani-Nikravesh hysteresis damping mu = 3 K (1 - e^2) / (4 xd(-)) (seed 004
    eqs. 3.6-3.8); xd(-) the approach speed at the start of the contact (m/s). K (N/m^n),
    n (-), restitution e (-); without e the contact is purely elastic."""

    stiffness: float
    exponent: float = 1.5
    restitution: float | None = None
    remembers = True

    def force(self, x: float, xd: float, approach: float = 0.0) -> float:
        if x <= 0.0:
            return 0.0
        elastic = self.stiffness * x ** self.exponent
        if self.restitution is None:
            return elastic
        e = self.restitution
        ratio = _rate_ratio(xd, approach)
        return max(elastic * (1.0 + 0.75 * (1.0 - e * e) * ratio), 0.0)


@dataclass(frozen=True)
class RestitutionLaw:
    """A penalty force with the damping that gives restitution e, valid for low e too
    (Flores et al. 2011): F = k x^n (1 + 8 (1 - e) / (5 e) * xd / xd(-)), never negative.

    stiffness k (N/m^n, the penalty), exponent n (-), restitution e (0 < e <= 1)."""

    restitution: float
    stiffness: float = 1.0e8
    exponent: float = 1.5
    remembers = True

    def force(self, x: float, xd: float, approach: float = 0.0) -> float:
        if x <= 0.0:
            return 0.0
        e = self.restitution
        factor = 8.0 * (1.0 - e) / (5.0 * e)
        ratio = _rate_ratio(xd, approach)
        return max(self.stiffness * x ** self.exponent * (1.0 + factor * ratio), 0.0)
