"""The static balance of a system at time t: residual, tangent stiffness and their norms.

Unknowns (q, lam); residual R = [phi_q^T lam - Q(q, t); phi(q, t)] (N, then the constraint
units); stiffness K_T = d(phi_q^T lam - Q)/dq by forward differences (the tested fallback of
DESIGN.md). Shared by Newton (mechlib.solvers.static.analyses) and pseudo-transient continuation
(mechlib.solvers.static.continuation).
"""

from __future__ import annotations

import weakref

import numpy as np

from mechlib.core.differences import FD_STEP
from mechlib.core.work import count
from mechlib.system.fd_columns import ColumnSkips, JacobianClasses
from mechlib.system.system import System

__all__ = ["FD_STEP", "Balance"]

"""Forward-difference step of the stiffness, relative to max(1, |q_j|)."""

# per system: the Jacobian classes of its current equations (by their labels)
_CLASSES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


class Balance:
    """R(q, lam) and K_T(q, lam) of `system` at time `t` (s). `scale` (N): the force that
    the force residual is judged against: the larger of the total weight (|g| taken at
    least 1 m/s^2), the largest applied generalised force at `q0`, and 1 N.
    `states_step` (s): the time over which element states (mechlib.elements.states) advance from
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
        self._classes = _jacobian_classes(system)
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
        mechlib.system.fd_columns), which it cannot change; the rest is evaluated as a whole, but
        for the frictionless primitive contacts, which add their own tangent
        (Contact.tangent). The constraint Jacobian at a column's perturbed q is the base one
        with the rows of the body's equations taken from an evaluation shared by bodies
        that no equation joins (mechlib.system.fd_columns.JacobianClasses): the same matrix, from
        (for the door) 21 evaluations instead of 105."""
        system, t, nq = self.system, self.t, self.system.nq
        count(jacobian_evaluations=1)
        out = np.empty((nq, nq))
        k0 = system.kin(q, None, t)
        jac0 = system.phi_q(k0)
        reaction0 = jac0.T @ lam
        steps = FD_STEP * np.maximum(1.0, np.abs(q))
        classes = self._classes
        shared = None if classes is None else self._shared_jacobians(classes, q, steps)
        work = jac0.copy()
        base: dict[frozenset[int], np.ndarray] = {}
        for j in range(nq):
            body = self._skips.body(j)
            skip = self._skips.skip(body)
            if skip not in base:  # bodies that leave out the same elements share it
                base[skip] = reaction0 - system.forces(k0, inertia=False, lam=lam, skip=skip)
            dq = np.zeros(nq)
            dq[j] = steps[j]
            k = system.kin(q + dq, None, t)
            if classes is None or shared is None or body < 0:
                jac = system.phi_q(k)
            else:  # the base Jacobian but the rows of the body's equations, as evaluated at k
                rows = classes.rows[body]
                work[rows] = shared[body][j % system.per_body][rows]
                jac = work
            out[:, j] = (
                jac.T @ lam - system.forces(k, inertia=False, lam=lam, skip=skip) - base[skip]
            ) / dq[j]
            if jac is work:
                work[rows] = jac0[rows]
        if self._compiled:
            view, damping = system.view(k0, lam), np.zeros_like(out)  # at rest: unused
            for element in self._compiled:
                if element.active:
                    element.tangent(view, out, damping)
        return out

    def _shared_jacobians(
        self, classes: JacobianClasses, q: np.ndarray, steps: np.ndarray
    ) -> dict[int, list[np.ndarray]]:
        """{body: [phi_q at q + the steps of coordinate c of every body of the body's
        class, for each c]}."""
        system, per_body = self.system, self.system.per_body
        found: dict[int, list[np.ndarray]] = {}
        for bodies in classes.classes:
            jacobians = []
            for c in range(per_body):
                dq = np.zeros(system.nq)
                for b in bodies:
                    dq[per_body * b + c] = steps[per_body * b + c]
                jacobians.append(system.phi_q(system.kin(q + dq, None, self.t)))
            found.update(dict.fromkeys(bodies, jacobians))
        return found

    def size(self, res: np.ndarray) -> float:
        """Euclidean norm of R with the forces divided by `scale` (-)."""
        w = np.ones_like(res)
        w[: self.system.nq] = self.scale
        return float(np.linalg.norm(res / w))

    def balanced(self, res: np.ndarray, tol: float) -> bool:
        """Forces below tol * scale and constraints below tol."""
        nq = self.system.nq
        return bool(
            np.abs(res[:nq]).max(initial=0) < tol * self.scale
            and np.abs(res[nq:]).max(initial=0) < tol
        )

    def converged(self, res: np.ndarray, step: np.ndarray, tol: float) -> bool:
        """Balanced (above) and the position step below 1e-8."""
        return self.balanced(res, tol) and bool(
            np.abs(step[: self.system.nq]).max(initial=0) < 1e-8
        )


def _jacobian_classes(system: System) -> JacobianClasses | None:
    """JacobianClasses.of(system), found once per set of equations (an event may add or
    drop some)."""
    key = tuple(system.labels)
    cached = _CLASSES.get(system)
    if cached is None or cached[0] != key:
        cached = (key, JacobianClasses.of(system))
        _CLASSES[system] = cached
    return cached[1]
