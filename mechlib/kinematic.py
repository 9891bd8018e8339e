"""Kinematic analysis: motions fix every degree of freedom.

Positions by Newton on phi(q, t) = 0, velocities from phi_q qd = nu, accelerations from
phi_q qdd = gamma, and reactions from the equations of motion with inertia:
phi_q^T lam = Q(lam) - M qdd (Newton when joint friction makes Q depend on lam).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from mechlib.analysis import Kinematic, Trajectory, check_step_limit, output_times
from mechlib.assembly import solve_positions
from mechlib.events import EventMonitor, fire, first_events
from mechlib.linalg import factor, singular_failure, solve_factored
from mechlib.reaction_loads import solve_reaction_loaded
from mechlib.solution import SolverFailure, SolverStats
from mechlib.system import System

__all__ = ["run_kinematic", "kinematic_state"]

_MAX_SUBDIVISIONS = 10


def kinematic_state(system: System, q_guess: np.ndarray, t: float, stats: SolverStats,
                    *, inertia: bool = True):
    """(q, qd, qdd, lam) at time t from a position guess; raises SolverFailure by name."""
    q, its = solve_positions(system, q_guess, t)
    stats.newton_iterations += its
    k = system.kin(q, None, t)
    system.commit(k)
    jac = system.phi_q(k)
    lu = factor(jac) if jac.shape[0] == jac.shape[1] else None
    if lu is None:
        raise singular_failure(system, jac, t, "kinematic analysis failed")
    qd = solve_factored(lu, system.nu(k))
    k = system.kin(q, qd, t)
    qdd = solve_factored(lu, system.gamma(k))
    inertial = system.mass(k) @ qdd if inertia else 0.0
    def loads(lam):
        return system.forces(k, inertia=inertia, lam=lam, jac=jac) - inertial
    if not system.reaction_dependent:
        return q, qd, qdd, solve_factored(lu, loads(None), transpose=True)
    lam = solve_reaction_loaded(system, k, jac.T, loads, slice(0, jac.shape[0]), jac=jac)
    if lam is None:
        raise singular_failure(system, jac, t, "kinematic analysis failed")
    return q, qd, qdd, lam


def run_kinematic(system: System, spec: Kinematic, q0: np.ndarray, qd0: np.ndarray,
                  trajectory: Trajectory, stats: SolverStats,
                  progress: Callable[[float, float], None] | None = None,
                  events=(), event_log: list | None = None) -> None:
    """Fill `trajectory` at the output times (and at the events, located between them and
    logged in `event_log`); SolverFailure leaves what was computed."""
    monitor = EventMonitor(events)
    state = (q0, qd0, np.zeros_like(q0))
    t_prev = spec.start
    for t in output_times(spec.start, spec.end, spec.step):
        check_step_limit(spec, stats, t_prev)
        new, lam = _advance(system, state, t_prev, t, stats)
        while monitor.armed and t > t_prev:
            hit = first_events(monitor, t_prev, t, _view(system, t, new, lam),
                               lambda tt: _view(system, tt,
                                                *_advance(system, state, t_prev, tt, stats)))
            if hit is None:
                break
            t_e, fired = hit
            at, lam_e = _advance(system, state, t_prev, t_e, stats)
            trajectory.record(t_e, *at, lam_e)
            if fire(system, monitor, fired, system.kin(at[0], at[1], t_e), event_log):
                return
            at, lam_e = _advance(system, at, t_e, t_e, stats)  # the changed model at t_e
            monitor.arm(t_e, _view(system, t_e, at, lam_e))
            state, t_prev = at, t_e
            new, lam = _advance(system, state, t_prev, t, stats)
        state = new
        trajectory.record(t, *state, lam)
        if monitor.armed:
            monitor.arm(t, _view(system, t, state, lam))
        stats.steps += 1
        t_prev = t
        if progress:
            progress(t, spec.end)


def _view(system: System, t: float, state, lam: np.ndarray):
    q, qd, _ = state
    return system.view(system.kin(q, qd, t), lam)


def _advance(system: System, state, t0: float, t1: float, stats: SolverStats, depth: int = 0):
    """State at t1 from the state at t0; a step Newton cannot take is halved (10 times at
    most), since the position guess extrapolates Euler parameters linearly."""
    q, qd, qdd = state
    h = t1 - t0
    try:
        q1, qd1, qdd1, lam = kinematic_state(system, q + h * qd + 0.5 * h * h * qdd, t1, stats)
        return (q1, qd1, qdd1), lam
    except SolverFailure:
        if depth >= _MAX_SUBDIVISIONS or h <= 0.0:
            raise
    stats.rejected_steps += 1
    mid = 0.5 * (t0 + t1)
    half, _ = _advance(system, state, t0, mid, stats, depth + 1)
    return _advance(system, half, mid, t1, stats, depth + 1)
