"""Second, independent integrator for cross-checks: scipy's Radau IIA (order 5) on the
index-1 form with Baumgarte terms, projected onto the position and velocity constraints
at every output time (the integration restarts from the projected state).

    [[M, phi_q^T], [phi_q, 0]] [qdd; lam] = [Q; gamma - 2 w (phi_q qd - nu) - w^2 phi]
"""
from __future__ import annotations

from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

from mechlib.analysis import Dynamic, Trajectory, check_step_limit, output_times
from mechlib.assembly import solve_positions
from mechlib.genalpha import consistent_accelerations
from mechlib.linalg import singular_failure
from mechlib.reaction_loads import accelerations_and_reactions
from mechlib.solution import SolverFailure, SolverStats
from mechlib.system import System

__all__ = ["run_radau"]

_BAUMGARTE = 20.0  # rad/s: constraint drift decays within a few 1/20 s between projections


def _rhs(system: System):
    nq = system.nq

    def f(t: float, y: np.ndarray) -> np.ndarray:
        q, qd = y[:nq], y[nq:]
        k = system.kin(q, qd, t)
        jac = system.phi_q(k)
        drift = jac @ qd - system.nu(k)
        g = system.gamma(k) - 2.0 * _BAUMGARTE * drift - _BAUMGARTE ** 2 * system.phi(k)
        sol = accelerations_and_reactions(system, k, jac, gamma=g)
        if sol is None:
            raise singular_failure(system, jac, t, "dynamic analysis (radau) failed")
        return np.concatenate([qd, sol[:nq]])
    return f


def _project(system: System, q: np.ndarray, qd: np.ndarray, t: float):
    q, _ = solve_positions(system, q, t)
    k = system.kin(q, None, t)
    jac = system.phi_q(k)
    fix, *_ = np.linalg.lstsq(jac, system.nu(k) - jac @ qd, rcond=None)
    return q, qd + fix


def run_radau(system: System, spec: Dynamic, q0, qd0, trajectory: Trajectory,
              stats: SolverStats, progress: Callable | None = None) -> None:
    """Integrate output interval by output interval with projection in between."""
    nq = system.nq
    f = _rhs(system)
    q, qd = q0.copy(), qd0.copy()
    times = output_times(spec.start, spec.end, spec.step)
    qdd, lam = consistent_accelerations(system, q, qd, times[0])
    trajectory.record(times[0], q, qd, qdd, lam)
    atol = np.r_[np.full(nq, spec.tolerance * 1e-2), np.full(nq, spec.tolerance * 1e-1)]
    for t0, t1 in zip(times[:-1], times[1:]):
        check_step_limit(spec, stats, t0)
        sol = solve_ivp(f, (t0, t1), np.concatenate([q, qd]), method="Radau",
                        rtol=spec.tolerance, atol=atol, max_step=spec.max_step or np.inf)
        stats.steps += max(len(sol.t) - 1, 0)
        stats.newton_iterations += sol.nfev
        if not sol.success:
            raise SolverFailure(f"dynamic analysis (radau) failed at t = {sol.t[-1]:.6g} s: "
                                f"{sol.message}", time=float(sol.t[-1]))
        q, qd = _project(system, sol.y[:nq, -1], sol.y[nq:, -1], t1)
        system.commit(system.kin(q, None, t1))
        qdd, lam = consistent_accelerations(system, q, qd, t1)
        trajectory.record(t1, q, qd, qdd, lam)
        if progress:
            progress(t1, spec.end)
