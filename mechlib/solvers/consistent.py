"""Consistent states: velocities on the constraints, accelerations and reactions from the
equations of motion at a given (q, qd). Used by both integrators (generalized-alpha at its
start, restarts and step-size changes; Radau at every output time) and by the exact stick
of joint friction.
"""

from __future__ import annotations

import numpy as np

from mechlib.linalg.factor import singular_failure, solve_factored
from mechlib.solvers.augmented import augmented_accelerations
from mechlib.system.reaction_loads import accelerations_and_reactions
from mechlib.system.saddle import rigid_saddle_factors
from mechlib.system.system import System

__all__ = ["consistent_accelerations", "consistent_state"]


def consistent_state(system: System, q, qd, t: float, *, project: bool = True):
    """(qd, qdd, lam): with `project`, qd projected onto phi_q qd = nu (mass-weighted);
    then qdd and lam from [[M, phi_q^T], [phi_q, 0]] [qdd; lam] = [Q(lam); gamma]: the
    reactions of the equations of motion at that state, free of integrator transients,
    with the joint friction they load (`mechlib.system.reaction_loads`)."""
    k = system.kin(q, qd, t)
    jac = system.phi_q(k)
    lu = rigid_saddle_factors(system, k)
    if lu is None:  # a singular position: the bounded augmented-Lagrangian solution
        return _at_singular(system, k, jac, qd, t)
    drift = system.nu(k) - jac @ qd
    if project and np.abs(drift).max(initial=0.0) > 0.0:
        qd = qd + solve_factored(lu, np.concatenate([np.zeros(system.nq), drift]))[: system.nq]
        k = system.kin(q, qd, t)
    sol = accelerations_and_reactions(system, k, jac, lu)
    if sol is None:
        raise singular_failure(system, jac, t, "dynamic analysis failed")
    return qd, sol[: system.nq], sol[system.nq :]


def _at_singular(system: System, k, jac: np.ndarray, qd, t: float):
    """(qd, qdd, lam) where the saddle matrix is singular (mechlib.solvers.augmented): qd as
    given, the accelerations bounded."""
    sol = augmented_accelerations(system, k, jac, system.gamma(k))
    if sol is None:
        raise singular_failure(system, jac, t, "dynamic analysis failed")
    return qd, sol[0], sol[1]


def consistent_accelerations(system: System, q, qd, t: float):
    """(qdd, lam) at the state (q, qd) without touching qd (see `consistent_state`)."""
    _, qdd, lam = consistent_state(system, q, qd, t, project=False)
    return qdd, lam
