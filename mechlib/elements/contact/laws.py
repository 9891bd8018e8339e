"""Normal-force laws of contact: impact, Hertz with Lankarani-Nikravesh damping, restitution.

Each law gives the normal force F_N (N, >= 0) from the penetration x (m, > 0 in contact),
its rate xd (m/s, > 0 approaching) and `approach`, the penetration rate stored when the
contact began (m/s, the element's memory; only the laws with `remembers` use it). The
force is continuous in x and xd (a kink at most), which keeps stiff contact stable under
the integrator's Jacobian. The formulas are compiled (numba: `impact_force`, `hertz_force`,
`restitution_force`, called by the laws' `force` and by the contact kernels); `kernel()`
gives a law's code and parameters for mechlib.elements.contact.kernels. Every law's elastic part is
k x^n (`elastic_force`), with the potential k x^(n+1) / (n+1) (`potential`, J; the energy
request's `elastic` column); the rest of the force, (F - k x^n), is the damping part.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.core.smooth import compiled_step, step

__all__ = [
    "HERTZ",
    "IMPACT",
    "MIN_APPROACH_SPEED",
    "RATE_RATIO_CAP",
    "RESTITUTION",
    "HertzLaw",
    "ImpactLaw",
    "PowerLaw",
    "RestitutionLaw",
    "hertz_force",
    "hertz_stiffness",
    "impact_force",
    "restitution_force",
    "step",
]

IMPACT, HERTZ, RESTITUTION = 0, 1, 2
"""Law codes of the compiled kernels."""

MIN_APPROACH_SPEED = 1.0e-3
"""m/s: floor of the stored approach speed (a contact that starts at rest would otherwise
divide by zero in the hysteresis damping factor)."""

RATE_RATIO_CAP = 10.0
"""|xd / xd(-)| beyond this (no impact reaches it: |xd| <= xd(-) in a free impact) is held
there, so that a wild Newton iterate cannot make the damping term explode."""


@njit(**KERNEL)
def _rate_ratio(xd: float, approach: float) -> float:
    ratio = xd / max(approach, MIN_APPROACH_SPEED)
    return min(max(ratio, -RATE_RATIO_CAP), RATE_RATIO_CAP)


@njit(**KERNEL)
def impact_force(
    k: float, exponent: float, damping: float, depth: float, x: float, xd: float, start: float
) -> float:
    """`ImpactLaw` force (N): the damping ramps in from penetration `start` (0, or where an
    event switched the element on while penetrating) to `start` + `depth`."""
    if x <= 0.0:
        return 0.0
    c = compiled_step(x, start, 0.0, start + depth, damping) if damping != 0.0 else 0.0
    return max(k * x**exponent + c * xd, 0.0)


@njit(**KERNEL)
def hertz_force(
    k: float, exponent: float, restitution: float, x: float, xd: float, approach: float
) -> float:
    """`HertzLaw` force (N); restitution NaN: purely elastic."""
    if x <= 0.0:
        return 0.0
    elastic = k * x**exponent
    if math.isnan(restitution):
        return elastic
    e = restitution
    return max(elastic * (1.0 + 0.75 * (1.0 - e * e) * _rate_ratio(xd, approach)), 0.0)


@njit(**KERNEL)
def restitution_force(
    restitution: float, k: float, exponent: float, x: float, xd: float, approach: float
) -> float:
    """`RestitutionLaw` force (N)."""
    if x <= 0.0:
        return 0.0
    e = restitution
    factor = 8.0 * (1.0 - e) / (5.0 * e)
    return max(k * x**exponent * (1.0 + factor * _rate_ratio(xd, approach)), 0.0)


class PowerLaw:
    """The elastic part k x^n of a law with `stiffness` k (N/m^n) and `exponent` n, and its
    potential (the integral of that force over the penetration)."""

    stiffness: float
    exponent: float

    def elastic_force(self, x: float) -> float:
        """k x^n (N) at penetration x (m; 0 apart)."""
        return self.stiffness * x**self.exponent if x > 0.0 else 0.0

    def potential(self, x: float, cap: float = math.inf) -> float:
        """Elastic energy (J) at penetration x (m): k x^(n+1) / (n+1), and beyond `cap` (m,
        where the contact kernels hold the force at k cap^n) that plus k cap^n (x - cap)."""
        if x <= 0.0:
            return 0.0
        k, n = self.stiffness, self.exponent
        held = min(x, cap)
        return k * held ** (n + 1.0) / (n + 1.0) + k * held**n * (x - held)


def hertz_stiffness(E1: float, nu1: float, E2: float, nu2: float, radius: float) -> float:
    """K (N/m^1.5) of two elastic bodies (seed 004 eqs. 3.4-3.5):
    K = 4 / (3 pi (h1 + h2)) * sqrt(R), h = (1 - nu^2) / (pi E), R the effective radius (m)
    (R1 R2 / (R1 + R2) outside, R1 R2 / (R2 - R1) for a ball in a socket)."""
    h1 = (1.0 - nu1 * nu1) / (math.pi * E1)
    h2 = (1.0 - nu2 * nu2) / (math.pi * E2)
    return 4.0 / (3.0 * math.pi * (h1 + h2)) * math.sqrt(radius)


@dataclass(frozen=True)
class ImpactLaw(PowerLaw):
    """F = k x^e + step(x, 0, 0, depth, c_max) * xd, never negative (seed 000 sec. 2.2.5).

    stiffness k (N/m^e), exponent e (-), damping c_max (N*s/m) reached at `depth` (m)."""

    stiffness: float
    exponent: float = 1.5
    damping: float = 0.0
    depth: float = 1.0e-4
    remembers = False

    def force(self, x: float, xd: float, approach: float = 0.0, start: float = 0.0) -> float:
        """F (N) at penetration x (m), its rate xd (m/s); the damping ramps in from `start`."""
        values = (self.stiffness, self.exponent, self.damping, self.depth, x, xd, start)
        return impact_force(*map(float, values))

    def kernel(self) -> tuple[int, np.ndarray]:
        """(IMPACT, [k, e, c_max, depth, ramp start]); the last entry is the element's to set
        (`Contact.start_from`)."""
        params = [self.stiffness, self.exponent, self.damping, self.depth, 0.0]
        return IMPACT, np.array(params, float)


@dataclass(frozen=True)
class HertzLaw(PowerLaw):
    """F = K x^n (1 + 3 (1 - e^2) / 4 * xd / xd(-)), never negative: Hertz with the
    Lankarani-Nikravesh hysteresis damping mu = 3 K (1 - e^2) / (4 xd(-)) (seed 004
    eqs. 3.6-3.8); xd(-) the approach speed at the start of the contact (m/s). K (N/m^n),
    n (-), restitution e (-); without e the contact is purely elastic."""

    stiffness: float
    exponent: float = 1.5
    restitution: float | None = None
    remembers = True

    def force(self, x: float, xd: float, approach: float = 0.0) -> float:
        e = math.nan if self.restitution is None else self.restitution
        return hertz_force(*map(float, (self.stiffness, self.exponent, e, x, xd, approach)))

    def kernel(self) -> tuple[int, np.ndarray]:
        e = math.nan if self.restitution is None else self.restitution
        return HERTZ, np.array([self.stiffness, self.exponent, e], float)


@dataclass(frozen=True)
class RestitutionLaw(PowerLaw):
    """A penalty force with the damping that gives restitution e, valid for low e too
    (Flores et al. 2011): F = k x^n (1 + 8 (1 - e) / (5 e) * xd / xd(-)), never negative.

    stiffness k (N/m^n, the penalty), exponent n (-), restitution e (0 < e <= 1)."""

    restitution: float
    stiffness: float = 1.0e8
    exponent: float = 1.5
    remembers = True

    def force(self, x: float, xd: float, approach: float = 0.0) -> float:
        return restitution_force(
            *map(float, (self.restitution, self.stiffness, self.exponent, x, xd, approach))
        )

    def kernel(self) -> tuple[int, np.ndarray]:
        return RESTITUTION, np.array([self.restitution, self.stiffness, self.exponent], float)
