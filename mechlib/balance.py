"""The static balance of a system at time t: residual, tangent stiffness and their norms.

Unknowns (q, lam); residual R = [phi_q^T lam - Q(q, t); phi(q, t)] (N, then the constraint
units); stiffness K_T = d(phi_q^T lam - Q)/dq by forward differences (the tested fallback of
DESIGN.md). Shared by Newton (mechlib.static) and pseudo-transient continuation
(mechlib.continuation).
"""

from __future__ import annotations

import numpy as np

from mechlib.fd_columns import ColumnSkips
from mechlib.system import System
from mechlib.work import count

__all__ = ["FD_STEP", "Balance"]

FD_STEP = 1e-7
"""Forward-difference step of the stiffness, relative to max(1, |q_j|)."""


class Balance:
    """R(q, lam) and K_T(q, lam) of `system` at time `t` (s). `scale` (N): the force that
    the force residual is judged against: the larger of the total weight (|g| taken at
    least 1 m/s^2), the largest applied generalised force at `q0`, and 1 N.
    `states_step` (s): the time over which element states (mechlib.states) advance from
    their accepted values to each iterate (0: they keep them)."""

    def __init__(self, system: System, t: float, q0: np.ndarray, states_step: float = 0.0):
        self.system, self.t = system, t
        self.states_step = states_step if system.states else 0.0
        # frictionless primitive contacts differentiate themselves (compiled, increments
        # sized for contact: a steel Hertz deflection is below FD_STEP); a static friction
        # force comes from the slip anchors, which only the differences below see
        self._compiled = [
            e for e in system.elements if getattr(e, "has_tangent", False) and e.friction is None
        ]
        self._skips = ColumnSkips(system, {id(e) for e in self._compiled})
        weight = abs(system.total_mass) * max(float(np.linalg.norm(system.gravity)), 1.0)
        applied = system.forces(system.kin(q0, None, t), inertia=False)
        self.scale = max(weight, np.abs(applied).max(initial=0.0), 1.0)

    def residual(self, q: np.ndarray, lam: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(R (nq + m,), phi_q (m, nq)) at (q, lam)."""
        system = self.system
        k = system.kin(q, None, self.t)
        if self.states_step > 0.0:  # at rest, as the forces are evaluated
            system.states.advance(system.view(k), self.states_step)
        jac = system.phi_q(k)
        force = jac.T @ lam - system.forces(k, inertia=False, lam=lam)
        return np.concatenate([force, system.phi(k)]), jac

    def stiffness(self, q: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """d(phi_q^T lam - Q)/dq by forward differences, (nq, nq). A column of body b leaves
        out the elements whose forces depend on other bodies only (`state_bodies`,
        mechlib.fd_columns), which it cannot change; the rest is evaluated as a whole, but
        for the frictionless primitive contacts, which add their own tangent
        (Contact.tangent)."""
        system, t = self.system, self.t
        count(jacobian_evaluations=1)
        out = np.empty((system.nq, system.nq))
        k0 = system.kin(q, None, t)
        reaction0 = system.phi_q(k0).T @ lam
        base: dict[frozenset[int], np.ndarray] = {}
        for j in range(system.nq):
            body = self._skips.body(j)
            skip = self._skips.skip(body)
            if skip not in base:  # bodies that leave out the same elements share it
                base[skip] = reaction0 - system.forces(k0, inertia=False, lam=lam, skip=skip)
            dq = np.zeros(system.nq)
            dq[j] = FD_STEP * max(1.0, abs(q[j]))
            k = system.kin(q + dq, None, t)
            out[:, j] = (
                system.phi_q(k).T @ lam
                - system.forces(k, inertia=False, lam=lam, skip=skip)
                - base[skip]
            ) / dq[j]
        if self._compiled:
            view, damping = system.view(k0, lam), np.zeros_like(out)  # at rest: unused
            for element in self._compiled:
                if element.active:
                    element.tangent(view, out, damping)
        return out

    def size(self, res: np.ndarray) -> float:
        """Euclidean norm of R with the forces divided by `scale` (-)."""
        w = np.ones_like(res)
        w[: self.system.nq] = self.scale
        return float(np.linalg.norm(res / w))

    def converged(self, res: np.ndarray, step: np.ndarray, tol: float) -> bool:
        """Forces below tol * scale, constraints below tol, position step below 1e-8."""
        nq = self.system.nq
        return bool(
            np.abs(res[:nq]).max(initial=0) < tol * self.scale
            and np.abs(res[nq:]).max(initial=0) < tol
            and np.abs(step[:nq]).max(initial=0) < 1e-8
        )
