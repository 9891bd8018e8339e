"""Friction coefficient of a contact as a continuous function of the sliding speed.

The coefficient rises smoothly from 0 at rest (no jump: the integrator's Jacobian sees a
steep but finite slope, so stick-slip does not chatter) to `mu_static` at `v_static` and
settles at `mu_dynamic` from `v_dynamic` on. Friction force = mu(|v_t|) * F_N, opposite the
tangential relative velocity v_t.
"""
from __future__ import annotations

from dataclasses import dataclass

from mechlib.contact.laws import step

__all__ = ["StribeckFriction", "CoulombFriction"]


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
        mv, vs, vd = self.viscous, self.v_static, self.v_dynamic
        top = self.mu_static - mv * vs
        if v <= vs:
            return step(v, -vs, -top, vs, top) + mv * v
        return step(v, vs, top, vd, self.mu_dynamic - mv * vd) + mv * v


@dataclass(frozen=True)
class CoulombFriction:
    """mu = mu_dynamic * step(v, -v_static, -1, v_static, 1): Coulomb friction regularised
    below `v_static` (m/s; slope 1.5 mu / v_static at rest), constant above."""

    mu_dynamic: float
    v_static: float = 1.0e-3

    def coefficient(self, v: float) -> float:
        return self.mu_dynamic * step(v, -self.v_static, -1.0, self.v_static, 1.0)
