"""Static and quasi-static analyses: equilibrium with inertia ignored.

Unknowns (q, lam); residual R = [phi_q^T lam - Q(q, t); phi(q, t)]; Newton with the
stiffness d(phi_q^T lam - Q)/dq by central-free forward differences (the tested fallback of
DESIGN.md) and backtracking on the residual norm. Quasi-static continues along the motions'
time functions and subdivides the step when Newton struggles.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from mechlib.analysis import QuasiStatic, Static, Trajectory, check_step_limit, output_times
from mechlib.assembly import solve_accelerations, solve_positions, solve_velocities
from mechlib.events import EventMonitor, fire, first_events
from mechlib.linalg import augmented, factor, singular_failure, solve_factored
from mechlib.solution import SolverFailure, SolverStats
from mechlib.system import System

__all__ = ["equilibrium", "run_static", "run_quasi_static"]

_MAX_NEWTON = 40
_MAX_SUBDIVISIONS = 10
_FD_STEP = 1e-7


def _residual(system: System, q: np.ndarray, lam: np.ndarray, t: float):
    k = system.kin(q, None, t)
    jac = system.phi_q(k)
    force = jac.T @ lam - system.forces(k, inertia=False, lam=lam)
    return np.concatenate([force, system.phi(k)]), jac, force


def _stiffness(system: System, q: np.ndarray, lam: np.ndarray, t: float,
               force: np.ndarray) -> np.ndarray:
    """d(phi_q^T lam - Q)/dq by forward differences, (nq, nq). A column of body b leaves
    out the elements joining two other bodies (contacts, seals: `body_pair`), whose forces
    it cannot change; the rest is evaluated as a whole."""
    out = np.empty((system.nq, system.nq))
    skips = _elsewhere(system)
    k0 = system.kin(q, None, t)
    reaction0 = system.phi_q(k0).T @ lam
    base: dict[int, np.ndarray] = {}
    for j in range(system.nq):
        body = j // 7
        if body not in base:
            base[body] = reaction0 - system.forces(k0, inertia=False, lam=lam,
                                                   skip=skips[body])
        dq = np.zeros(system.nq)
        dq[j] = _FD_STEP * max(1.0, abs(q[j]))
        k = system.kin(q + dq, None, t)
        out[:, j] = (system.phi_q(k).T @ lam
                     - system.forces(k, inertia=False, lam=lam, skip=skips[body])
                     - base[body]) / dq[j]
    return out


def _elsewhere(system: System) -> dict[int, set[int]]:
    """Per moving body: ids of the two-body elements that do not involve it."""
    pairs = [(id(e), e.body_pair()) for e in system.elements if hasattr(e, "body_pair")]
    return {b: {i for i, pair in pairs if b not in pair} for b in range(system.nb)}


def _scales(system: System, force: np.ndarray) -> float:
    weight = float(np.abs(system.masses).sum() * max(np.linalg.norm(system.gravity), 1.0))
    return max(weight, np.abs(force).max(initial=0.0), 1.0)


def equilibrium(system: System, q: np.ndarray, lam: np.ndarray | None, t: float,
                stats: SolverStats, tol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
    """(q, lam) in static equilibrium at t from a guess; SolverFailure if Newton fails."""
    q, its = solve_positions(system, q, t)
    stats.newton_iterations += its
    m = len(system.labels)
    if lam is None or len(lam) != m:
        # multipliers balancing the loads at the guess (least squares): the constraint
        # forces then carry their geometric stiffness (a hanging pendulum) from the start
        k = system.kin(q, None, t)
        lam, *_ = np.linalg.lstsq(system.phi_q(k).T, system.forces(k, inertia=False),
                                  rcond=None)
    res, jac, force = _residual(system, q, lam, t)
    scale = _scales(system, system.forces(system.kin(q, None, t), inertia=False))
    for _ in range(_MAX_NEWTON):
        stats.newton_iterations += 1
        lu = factor(augmented(_stiffness(system, q, lam, t, force), jac))
        if lu is None:
            raise singular_failure(system, jac, t, "static equilibrium failed")
        step = solve_factored(lu, -res)
        norm0, alpha = np.linalg.norm(res / _weights(res, system.nq, scale)), 1.0
        while True:
            q_new, lam_new = q + alpha * step[:system.nq], lam + alpha * step[system.nq:]
            res_new, jac_new, force_new = _residual(system, q_new, lam_new, t)
            if np.linalg.norm(res_new / _weights(res, system.nq, scale)) < norm0 or alpha < 1e-3:
                break
            alpha *= 0.5
        q, lam, res, jac, force = q_new, lam_new, res_new, jac_new, force_new
        if (np.abs(res[:system.nq]).max(initial=0) < tol * scale
                and np.abs(res[system.nq:]).max(initial=0) < tol
                and np.abs(step[:system.nq]).max(initial=0) < 1e-8):
            return q, lam
    worst = int(np.argmax(np.abs(res[system.nq:]))) if m else 0
    where = (system.labels[worst],) if m else ()
    raise SolverFailure(f"static equilibrium did not converge at t = {t:.6g} s: no equilibrium "
                        "near the previous position (a load beyond what the mechanism can "
                        "hold, or an unloaded free degree of freedom)", time=t, where=where)


def _weights(res: np.ndarray, nq: int, scale: float) -> np.ndarray:
    w = np.ones_like(res)
    w[:nq] = scale
    return w


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
