"""Static equilibrium: Newton on (q, lam), with inertia ignored.

Unknowns (q, lam); the balance R = [phi_q^T lam - Q(q, t); phi(q, t)] and its
forward-difference stiffness are in mechlib.balance. Newton with backtracking on the residual
norm; where Newton's matrix is singular, pseudo-transient continuation (mechlib.continuation)
first. Used by the static and quasi-static analyses (mechlib.static) and by modes.
"""

from __future__ import annotations

import numpy as np

from mechlib.assembly import solve_positions
from mechlib.balance import Balance
from mechlib.continuation import settle
from mechlib.contract import Status
from mechlib.linalg import augmented, factor, singular_failure, solve_factored
from mechlib.solution import SolverFailure, SolverStats
from mechlib.system import System
from mechlib.work import count

__all__ = ["equilibrium"]

_MAX_NEWTON = 40


def equilibrium(
    system: System,
    q: np.ndarray,
    lam: np.ndarray | None,
    t: float,
    stats: SolverStats,
    tol: float = 1e-10,
    *,
    states_step: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """(q, lam) in static equilibrium at t from a guess; SolverFailure if none is found.

    Newton first; where its matrix is singular (a contact at zero penetration or open has
    no stiffness: a body not yet resting on its support), pseudo-transient continuation
    (mechlib.continuation) brings the bodies to rest, and Newton finishes from there.
    Element states advance over `states_step` (s) with every iterate (mechlib.balance)."""
    q, its = solve_positions(system, q, t)
    stats.newton_iterations += its
    if lam is None or len(lam) != len(system.labels):
        # multipliers balancing the loads at the guess (least squares): the constraint
        # forces then carry their geometric stiffness (a hanging pendulum) from the start
        k = system.kin(q, None, t)
        count(factorizations=1)
        lam, *_ = np.linalg.lstsq(system.phi_q(k).T, system.forces(k, inertia=False), rcond=None)
    balance = Balance(system, t, q, states_step)
    try:
        return _newton(balance, q, lam, stats, tol)
    except _Singular:
        q, lam = settle(balance, q, lam, stats)
    try:
        return _newton(balance, q, lam, stats, tol)
    except _Singular as singular:
        raise singular_failure(system, singular.jac, t, "static equilibrium failed") from None


class _Singular(Exception):
    """Newton's matrix is singular at an iterate with constraint Jacobian `jac`."""

    def __init__(self, jac: np.ndarray):
        super().__init__("singular static matrix")
        self.jac = jac


def _newton(
    balance: Balance, q: np.ndarray, lam: np.ndarray, stats: SolverStats, tol: float
) -> tuple[np.ndarray, np.ndarray]:
    """Newton on (q, lam), each step halved (down to 1/1000) until the weighted residual
    decreases; _Singular when the matrix is, SolverFailure after _MAX_NEWTON iterations."""
    system, t, nq = balance.system, balance.t, balance.system.nq
    res, jac = balance.residual(q, lam)
    for _ in range(_MAX_NEWTON):
        stats.newton_iterations += 1
        lu = factor(augmented(balance.stiffness(q, lam), jac))
        if lu is None:
            raise _Singular(jac)
        step = solve_factored(lu, -res)
        norm0, alpha = balance.size(res), 1.0
        while True:
            q_new, lam_new = q + alpha * step[:nq], lam + alpha * step[nq:]
            res_new, jac_new = balance.residual(q_new, lam_new)
            if balance.size(res_new) < norm0 or alpha < 1e-3:
                break
            alpha *= 0.5
        q, lam, res, jac = q_new, lam_new, res_new, jac_new
        if balance.converged(res, step, tol):
            return q, lam
    m = len(system.labels)
    worst = int(np.argmax(np.abs(res[nq:]))) if m else 0
    where = (system.labels[worst],) if m else ()
    raise SolverFailure(
        f"static equilibrium did not converge at t = {t:.6g} s: no equilibrium "
        "near the previous position (a load beyond what the mechanism can "
        "hold, or an unloaded free degree of freedom)",
        time=t,
        where=where,
        status=Status.NEWTON_FAILED,
    )
