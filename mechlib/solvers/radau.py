"""Second, independent integrator for cross-checks: scipy's Radau IIA (order 5) on the
index-1 form with Baumgarte terms, projected onto the position and velocity constraints
at every output time (the integration restarts from the projected state).

    [[M, phi_q^T], [phi_q, 0]] [qdd; lam] = [Q; gamma - 2 w (phi_q qd - nu) - w^2 phi]

As a stepper (mechlib.solvers.contract) one step is one output interval, integrated by scipy's
own steps; it does not locate events (`solve` refuses them). With dense output
(`analysis.output: dense`) one scipy solver runs over the whole analysis instead, one of
its steps per stepper step (largest step: mechlib.solvers.dense.largest_step), and each row is its
dense output at the output time, projected; the integration never restarts, the
Baumgarte terms hold its drift. Its work is counted from
scipy's counters (Jacobian evaluations `njev`, LU factorisations `nlu`) and from the calls
of the right-hand side: each Newton iteration evaluates it at the three stages of the
trial step, so the stage calls give the iterations and the trial step sizes (a new size
within one scipy step is a rejected step).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import Radau

from mechlib.core.outcome import SolverFailure, Status
from mechlib.core.work import count
from mechlib.linalg.factor import singular_failure
from mechlib.solvers.assembly import solve_positions
from mechlib.solvers.augmented import augmented_accelerations
from mechlib.solvers.consistent import consistent_accelerations
from mechlib.solvers.contract import DenseStepper, State, StepResult
from mechlib.solvers.dense import largest_step, projected_row
from mechlib.solvers.march import check_step_limit
from mechlib.solvers.runaway import fell_to, stall, step_floor
from mechlib.system.system import System

__all__ = ["RadauStepper"]

_BAUMGARTE = 20.0  # rad/s: constraint drift decays within a few 1/20 s between projections


def _rhs(system: System):
    nq = system.nq

    def f(t: float, y: np.ndarray) -> np.ndarray:
        q, qd = y[:nq], y[nq:]
        k = system.kin(q, qd, t)
        jac = system.phi_q(k)
        drift = jac @ qd - system.nu(k)
        g = system.gamma(k) - 2.0 * _BAUMGARTE * drift - _BAUMGARTE**2 * system.phi(k)
        sol = augmented_accelerations(system, k, jac, g)
        if sol is None:
            raise singular_failure(system, jac, t, "dynamic analysis (radau) failed")
        return np.concatenate([qd, sol[0]])

    return f


class _Logged:
    """The right-hand side, with the times of the calls outside Jacobian evaluations."""

    def __init__(self, f):
        self.f, self.times, self.in_jacobian = f, [], False

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        if not self.in_jacobian:
            self.times.append(t)
        return self.f(t, y)

    def jacobian(self, inner):
        def jac(*args):
            self.in_jacobian = True
            try:
                return inner(*args)
            finally:
                self.in_jacobian = False

        return jac


class RadauStepper(DenseStepper):
    """scipy Radau from one output time to the next, projected there."""

    def __init__(self, system: System, spec, stats):
        super().__init__(system, spec, stats)
        self.rhs = _Logged(_rhs(system))
        nq = system.nq
        self.atol = np.r_[np.full(nq, spec.tolerance * 1e-2), np.full(nq, spec.tolerance * 1e-1)]
        self.dense = spec.dense and not spec.fixed_step
        self.solver: Radau | None = None  # dense: the one solver of the whole run
        self.counted = (0, 0)  # dense: its factorisations and Jacobians counted so far

    def init(self, t: float, q0: np.ndarray, qd0: np.ndarray) -> State:
        q, qd = q0.copy(), qd0.copy()
        return State(t, q, qd, *consistent_accelerations(self.system, q, qd, t))

    def _solver(self, state: State, t_end: float, max_step: float) -> Radau:
        solver = Radau(
            self.rhs,
            float(state.t),
            np.concatenate([state.q, state.qd]),
            float(t_end),
            rtol=self.spec.tolerance,
            atol=self.atol,
            max_step=max_step,
        )
        solver.jac = self.rhs.jacobian(solver.jac)
        return solver

    def step(self, state: State, t_out: float) -> StepResult:
        if self.dense:
            return self._dense_step(state)
        nq, system = self.system.nq, self.system
        solver = self._solver(state, t_out, self.spec.max_step or np.inf)
        floor = step_floor(self.spec.end)
        while solver.status == "running":
            check_step_limit(self.spec, self.stats, float(solver.t))
            self._scipy_step(solver)
            if solver.status == "running" and solver.h_abs < floor:
                solver.status = "failed"
        count(factorizations=solver.nlu, jacobian_evaluations=solver.njev)
        if solver.status == "failed":  # scipy's step fell below its own floor: a stall
            y = solver.y[:nq]
            why = f"scipy: {self.message}" if self.message else ""
            how = fell_to(solver.h_abs, floor)
            raise stall(system, self.spec.name, float(solver.t), y, how, why)
        try:
            q, qd, its = _project(system, solver.y[:nq], solver.y[nq:], t_out)
        except SolverFailure as failure:  # no position on the constraints at t_out
            how = f"no position on the constraints at t = {t_out:.6g} s"
            raise stall(system, self.spec.name, state.t, state.q, how, failure) from None
        self.stats.newton_iterations += its
        system.commit(system.kin(q, None, t_out))
        qdd, lam = consistent_accelerations(system, q, qd, t_out)
        return StepResult(State(t_out, q, qd, qdd, lam), None, Status.SUCCESSFUL)

    def _dense_step(self, state: State) -> StepResult:
        """One scipy step of the run's one solver; its end unprojected (rows project)."""
        nq = self.system.nq
        if self.solver is None:
            self.solver = self._solver(state, self.spec.end, largest_step(self.system, self.spec))
        solver = self.solver
        self._scipy_step(solver)
        nlu, njev = self.counted
        count(factorizations=solver.nlu - nlu, jacobian_evaluations=solver.njev - njev)
        self.counted = (solver.nlu, solver.njev)
        floor = step_floor(self.spec.end)
        if solver.status == "failed" or (solver.status == "running" and solver.h_abs < floor):
            why = f"scipy: {self.message}" if self.message else ""
            how = fell_to(solver.h_abs, floor)
            raise stall(self.system, self.spec.name, float(solver.t), solver.y[:nq], how, why)
        y = solver.y
        return StepResult(
            State(float(solver.t), y[:nq], y[nq:], state.qdd, state.lam), None, Status.SUCCESSFUL
        )

    def dense_row(self, start: State, end: State, t: float, states) -> State:
        """The row at t: the solver's dense output over its last step, projected."""
        assert self.solver is not None, "made by the first dense step"
        nq = self.system.nq
        y = self.solver.y if t == end.t else self.solver.dense_output()(t)
        row = projected_row(self.system, t, y[:nq], y[nq:], states)
        self.system.commit(self.system.kin(row.q, None, t))
        return row

    def _scipy_step(self, solver) -> None:
        """One scipy step, its stage calls counted: three per Newton iteration; the last
        call of an accepted step is the derivative at its end; calls at the step's start
        re-evaluate the error estimate."""
        t0 = solver.t
        self.rhs.times = []
        self.message = solver.step()
        stages = [t for t in self.rhs.times if t != t0]
        accepted = solver.status != "failed"
        if accepted:
            stages = stages[:-1]
            self.stats.steps += 1
        self.stats.newton_iterations += len(stages) // 3
        sizes = [t for i, t in enumerate(stages) if i % 3 == 2]
        trials = sum(1 for i, h in enumerate(sizes) if i == 0 or h != sizes[i - 1])
        self.stats.rejected_steps += max(trials - 1, 0) if accepted else trials

    def resolve(self, state: State, t: float) -> State:
        raise SolverFailure("the radau integrator does not locate events", time=t)

    def settle(self, state: State) -> State:
        return state  # scipy's steps were counted as taken; committed when projected

    def restart(self, state: State) -> State:
        raise SolverFailure("the radau integrator does not restart after events", time=state.t)


def _project(system: System, q: np.ndarray, qd: np.ndarray, t: float):
    """(q, qd, Newton iterations) projected onto the position and velocity constraints."""
    q, its = solve_positions(system, q, t)
    k = system.kin(q, None, t)
    jac = system.phi_q(k)
    count(factorizations=1)
    fix, *_ = np.linalg.lstsq(jac, system.nu(k) - jac @ qd, rcond=None)
    return q, qd + fix, its
