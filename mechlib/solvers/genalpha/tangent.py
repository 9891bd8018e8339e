"""The differenced part of generalized-alpha's iteration matrix: K = -dQ/dq and
C = -dQ/dqd of the applied forces by forward differences, column by column, each column
leaving out the elements and modal bodies it cannot change and the exactly zero columns not
evaluated at all (mechlib.system.fd_columns.ColumnSkips)."""

from __future__ import annotations

import numpy as np

from mechlib.core.differences import fd_step
from mechlib.system.fd_columns import ColumnSkips
from mechlib.system.system import System

__all__ = ["differenced_tangent"]


def differenced_tangent(
    system: System, k, skips: ColumnSkips, lam: np.ndarray, jac: np.ndarray, h: float
) -> tuple[np.ndarray, np.ndarray]:
    """(K, C) (nq, nq) at state k and multipliers `lam` (joint friction is loaded by them;
    `jac` their phi_q), the columns as `skips` says. Element states (mechlib.elements.states)
    are re-advanced over the step h (s) at each perturbed state: the tangent then holds their
    response to q and qd (the oil columns of a hydraulic actuator are a stiffness only
    through its pressures)."""
    sys = system
    q, qd = sys.state_of(k)
    states = sys.states
    trial = states.trial.copy()

    def forces(kp, skip, jac_p=None):
        if states.drive_forces:
            states.trial = trial.copy()
            states.advance(sys.view(kp), h)
        return sys.forces(kp, skip=skip, lam=lam, jac=jac_p)

    base: dict[frozenset[int], np.ndarray] = {}
    stiffness, damping = np.empty((sys.nq, sys.nq)), np.empty((sys.nq, sys.nq))
    try:
        for j in range(sys.nq):
            body = skips.body(j)
            if skips.inert(body):  # exactly zero (ColumnSkips.inert): not evaluated
                stiffness[:, j] = damping[:, j] = 0.0
                continue
            skip = skips.skip(body)
            if skip not in base:  # bodies that leave out the same elements share it
                base[skip] = sys.forces(k, skip=skip, lam=lam, jac=jac)
            dq = np.zeros(sys.nq)
            dq[j] = eps = fd_step(q[j])
            stiffness[:, j] = -(forces(sys.kin(q + dq, qd, k.t), skip) - base[skip]) / eps
            dq[j] = eps = fd_step(qd[j])
            damping[:, j] = -(forces(sys.kin(q, qd + dq, k.t), skip, jac) - base[skip]) / eps
    finally:
        states.trial = trial
    return stiffness, damping
