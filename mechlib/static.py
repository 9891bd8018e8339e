"""Static and quasi-static analyses: equilibrium with inertia ignored.

Unknowns (q, lam); the balance R = [phi_q^T lam - Q(q, t); phi(q, t)] and its
forward-difference stiffness are in mechlib.balance. Newton with backtracking on the residual
norm; where Newton's matrix is singular, pseudo-transient continuation (mechlib.continuation)
first. Quasi-static continues along the motions' time functions and subdivides the step when
Newton struggles.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from mechlib.analysis import QuasiStatic, Static, Trajectory, check_step_limit, output_times
from mechlib.assembly import solve_accelerations, solve_positions, solve_velocities
from mechlib.events import EventMonitor, fire, first_events
from mechlib.balance import Balance
from mechlib.continuation import settle
from mechlib.linalg import augmented, factor, singular_failure, solve_factored
from mechlib.solution import SolverFailure, SolverStats
from mechlib.system import System

__all__ = ["equilibrium", "run_static", "run_quasi_static"]

_MAX_NEWTON = 40
_MAX_SUBDIVISIONS = 10


def equilibrium(system: System, q: np.ndarray, lam: np.ndarray | None, t: float,
                stats: SolverStats, tol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
    """(q, lam) in static equilibrium at t from a guess; SolverFailure if none is found.

    Newton first; where its matrix is singular (a contact at zero penetration or open has
    no stiffness: a body not yet resting on its support), pseudo-transient continuation
    (mechlib.continuation) brings the bodies to rest, and Newton finishes from there."""
    q, its = solve_positions(system, q, t)
    stats.newton_iterations += its
    if lam is None or len(lam) != len(system.labels):
        # multipliers balancing the loads at the guess (least squares): the constraint
        # forces then carry their geometric stiffness (a hanging pendulum) from the start
        k = system.kin(q, None, t)
        lam, *_ = np.linalg.lstsq(system.phi_q(k).T, system.forces(k, inertia=False),
                                  rcond=None)
    balance = Balance(system, t, q)
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


def _newton(balance: Balance, q: np.ndarray, lam: np.ndarray, stats: SolverStats,
            tol: float) -> tuple[np.ndarray, np.ndarray]:
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
    raise SolverFailure(f"static equilibrium did not converge at t = {t:.6g} s: no equilibrium "
                        "near the previous position (a load beyond what the mechanism can "
                        "hold, or an unloaded free degree of freedom)", time=t, where=where)


def _record(system: System, trajectory: Trajectory, q, lam, t: float) -> None:
    """Record an equilibrium, then accept it; recorded before: its outputs see the slip
    anchors the solver measured from (the previous equilibrium)."""
    k = system.kin(q, None, t)
    qd = solve_velocities(system, k)
    qdd = solve_accelerations(system, system.kin(q, qd, t))
    trajectory.record(t, q, qd, qdd, lam)
    system.commit(k)


def run_static(system: System, spec: Static, q0: np.ndarray, trajectory: Trajectory,
               stats: SolverStats, progress: Callable | None = None) -> None:
    trajectory.at_rest = True
    q, lam = equilibrium(system, q0, None, spec.time, stats)
    stats.steps += 1
    _record(system, trajectory, q, lam, spec.time)


def run_quasi_static(system: System, spec: QuasiStatic, q0: np.ndarray,
                     trajectory: Trajectory, stats: SolverStats,
                     progress: Callable | None = None, events=(),
                     event_log: list | None = None) -> None:
    """Equilibria at the output times (and at the events, located between them and logged
    in `event_log`); a failed step is retried in up to 2^10 sub-steps."""
    monitor = EventMonitor(events)
    trajectory.at_rest = True
    q, lam, t_prev = q0, None, spec.start
    q_prev = q0
    for t in output_times(spec.start, spec.end, spec.step):
        check_step_limit(spec, stats, t_prev)
        q_new, lam_new = _continue(system, q, q_prev, lam, t_prev, t, stats)
        while monitor.armed and t > t_prev:
            hit = first_events(monitor, t_prev, t, _view(system, q_new, lam_new, t),
                               lambda tt: _view(system, *_continue(system, q, q, lam, t_prev,
                                                                   tt, stats), tt))
            if hit is None:
                break
            t_e, fired = hit
            q_e, lam_e = _continue(system, q, q, lam, t_prev, t_e, stats)
            _record(system, trajectory, q_e, lam_e, t_e)
            if fire(system, monitor, fired, system.kin(q_e, None, t_e), event_log):
                return
            # the changed model has other multipliers: they restart from the loads
            q_e, lam_e = equilibrium(system, q_e, None, t_e, stats)
            monitor.arm(t_e, _view(system, q_e, lam_e, t_e))
            q_prev, q, lam, t_prev = q_e, q_e, lam_e, t_e
            q_new, lam_new = _continue(system, q, q_prev, lam, t_prev, t, stats)
        q_prev, q, lam = q, q_new, lam_new
        _record(system, trajectory, q, lam, t)
        if monitor.armed:
            monitor.arm(t, _view(system, q, lam, t))
        stats.steps += 1
        t_prev = t
        if progress:
            progress(t, spec.end)


def _view(system: System, q: np.ndarray, lam: np.ndarray, t: float):
    """The state view of an equilibrium (velocities from the motions)."""
    k = system.kin(q, None, t)
    return system.view(system.kin(q, solve_velocities(system, k), t), lam)


def _continue(system, q, q_prev, lam, t0: float, t1: float, stats: SolverStats, depth: int = 0):
    guess = 2.0 * q - q_prev if depth == 0 and t1 > t0 else q
    try:
        return equilibrium(system, guess, lam, t1, stats)
    except SolverFailure:
        if depth >= _MAX_SUBDIVISIONS or t1 <= t0:
            raise
        stats.rejected_steps += 1
        mid = 0.5 * (t0 + t1)
        q_mid, lam_mid = _continue(system, q, q, lam, t0, mid, stats, depth + 1)
        system.commit(system.kin(q_mid, None, mid))
        return _continue(system, q_mid, q, lam_mid, mid, t1, stats, depth + 1)
