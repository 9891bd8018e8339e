"""Friction coefficient of a contact as a continuous function of the sliding speed.

The coefficient rises smoothly from 0 at rest (no jump: the integrator's Jacobian sees a
steep but finite slope, so stick-slip does not chatter) to `mu_static` at `v_static` and
settles at `mu_dynamic` from `v_dynamic` on. Friction force = mu(|v_t|) * F_N, opposite the
tangential relative velocity v_t. The formulas are compiled (numba: `stribeck`, `coulomb`)
for the contact kernels; `kernel()` gives a law's code and parameters.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.core.smooth import compiled_step as step

__all__ = [
    "COULOMB",
    "NO_FRICTION",
    "STRIBECK",
    "CoulombFriction",
    "StribeckFriction",
    "coulomb",
    "stribeck",
]

NO_FRICTION, STRIBECK, COULOMB = 0, 1, 2
"""Friction codes of the compiled kernels."""


@njit(**KERNEL)
def stribeck(
    mu_static: float, mu_dynamic: float, v_static: float, v_dynamic: float, viscous: float, v: float
) -> float:
    """`StribeckFriction` coefficient at sliding speed v (m/s)."""
    top = mu_static - viscous * v_static
    if v <= v_static:
        return step(v, -v_static, -top, v_static, top) + viscous * v
    return step(v, v_static, top, v_dynamic, mu_dynamic - viscous * v_dynamic) + viscous * v


@njit(**KERNEL)
def coulomb(mu_dynamic: float, v_static: float, v: float) -> float:
    """`CoulombFriction` coefficient at sliding speed v (m/s)."""
    return mu_dynamic * step(v, -v_static, -1.0, v_static, 1.0)


@dataclass(frozen=True)
class StribeckFriction:
    """Step-function Stribeck law of seed 004 eq. 3.9 (with its viscous term mu_v):

    mu = step(v, -v_st, -(mu_st - mu_v v_st), v_st, mu_st - mu_v v_st) + mu_v v for v <= v_st
    mu = step(v, v_st, mu_st - mu_v v_st, v_dyn, mu_dyn - mu_v v_dyn) + mu_v v above;
    speeds v in m/s, mu_v in s/m, coefficients dimensionless."""

    mu_static: float
    mu_dynamic: float
    v_static: float = 1.0e-3
    v_dynamic: float = 1.0e-2
    viscous: float = 0.0

    def coefficient(self, v: float) -> float:
        return stribeck(
            *map(
                float,
                (self.mu_static, self.mu_dynamic, self.v_static, self.v_dynamic, self.viscous, v),
            )
        )

    def kernel(self) -> tuple[int, np.ndarray]:
        return STRIBECK, np.array(
            [self.mu_static, self.mu_dynamic, self.v_static, self.v_dynamic, self.viscous], float
        )


@dataclass(frozen=True)
class CoulombFriction:
    """mu = mu_dynamic * step(v, -v_static, -1, v_static, 1): Coulomb friction regularised
    below `v_static` (m/s; slope 1.5 mu / v_static at rest), constant above."""

    mu_dynamic: float
    v_static: float = 1.0e-3

    def coefficient(self, v: float) -> float:
        return coulomb(float(self.mu_dynamic), float(self.v_static), float(v))

    def kernel(self) -> tuple[int, np.ndarray]:
        return COULOMB, np.array([self.mu_dynamic, self.v_static], float)
