"""Static and quasi-static analyses: equilibria with inertia ignored (mechlib.equilibrium).

Quasi-static continues along the motions' time functions: each equilibrium starts from the
linear extrapolation of the last two, and an interval Newton cannot take is subdivided.
Static solves one instant: the quasi-static stepper's first state.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechlib.analysis import Static, Trajectory
from mechlib.assembly import solve_accelerations, solve_velocities
from mechlib.contract import State, Status, Stepper, StepResult
from mechlib.equilibrium import Tangent, equilibrium
from mechlib.solution import SolverFailure, SolverStats
from mechlib.system import System

__all__ = ["QuasiStaticStepper", "equilibrium", "run_static"]

_MAX_SUBDIVISIONS = 10


@dataclass(kw_only=True)
class _Equilibrium(State):
    """An equilibrium, and the one before it (its extrapolation's start)."""

    q_prev: np.ndarray


def _equilibrium(state: State) -> _Equilibrium:
    """`state` as this stepper's own: every state it is handed is one it made."""
    assert isinstance(state, _Equilibrium), "a quasi-static stepper's own state"
    return state


class QuasiStaticStepper(Stepper):
    """Equilibria at the output times; a failed interval is retried in up to 2^10 sub-steps
    (rejected steps). Velocities and accelerations are those the motions prescribe
    (minimum-norm); an equilibrium is recorded before it is committed, so that its outputs
    see the slip anchors the solver measured from (the previous equilibrium). The stiffness
    is reused from equilibrium to equilibrium while Newton converges on it
    (mechlib.equilibrium.Tangent)."""

    at_rest = True

    def __init__(self, system: System, spec, stats: SolverStats):
        super().__init__(system, spec, stats)
        self.tangent = Tangent()  # the last stiffness, reused while Newton converges on it

    def init(self, t: float, q0: np.ndarray, qd0: np.ndarray | None) -> State:
        # the start has no multipliers yet (None: equilibrium starts them from the loads)
        q, lam = self._continue(q0, q0, None, t, t, self._mark(q0, t))
        return self.settle(self._state(q, lam, t, q0))

    def step(self, state: State, t_out: float) -> StepResult:
        return StepResult(
            self._solve(state, t_out, _equilibrium(state).q_prev), None, Status.SUCCESSFUL
        )

    def resolve(self, state: State, t: float) -> State:
        kept, self.tangent = self.tangent, Tangent()  # locating an event: no stiffness
        try:  # carried in from another time, as each trial time is solved afresh
            return self._solve(state, t, state.q)
        finally:
            self.tangent = kept

    def settle(self, state: State) -> State:
        system = self.system
        self.stats.steps += 1
        if system.states:
            assert state.elements is not None, "marked by _state when there are states"
            system.states.resume(state.elements)
        state.snapshot = system.snapshot()
        system.commit(system.kin(state.q, None, state.t))
        return state

    def restart(self, state: State) -> State:
        """The equilibrium of the changed model: its multipliers restart from the loads."""
        q, lam = equilibrium(self.system, state.q, None, state.t, self.stats)
        return self._state(q, lam, state.t, q)

    def _solve(self, state: State, t1: float, q_prev: np.ndarray) -> State:
        """The equilibrium at t1 continued from `state`, extrapolated from q_prev."""
        q, lam = self._continue(state.q, q_prev, state.lam, state.t, t1, state.elements)
        return self._state(q, lam, t1, state.q)

    def _state(self, q: np.ndarray, lam: np.ndarray, t: float, q_prev: np.ndarray) -> State:
        k = self.system.kin(q, None, t)
        qd = solve_velocities(self.system, k)
        qdd = solve_accelerations(self.system, self.system.kin(q, qd, t))
        return _Equilibrium(t, q, qd, qdd, lam, self._mark(q, t), q_prev=q_prev)

    def _continue(self, q, q_prev, lam, t0: float, t1: float, marks, depth: int = 0):
        """(q, lam) at t1 from the equilibrium (q, lam) at t0 (element states `marks`)."""
        system = self.system
        if system.states:
            system.states.resume(marks)
        guess = 2.0 * q - q_prev if depth == 0 and t1 > t0 else q
        try:
            return equilibrium(
                system, guess, lam, t1, self.stats, states_step=t1 - t0, tangent=self.tangent
            )
        except SolverFailure:
            if depth >= _MAX_SUBDIVISIONS or t1 <= t0:
                raise
        self.stats.rejected_steps += 1
        mid = 0.5 * (t0 + t1)
        q_mid, lam_mid = self._continue(q, q, lam, t0, mid, marks, depth + 1)
        system.commit(system.kin(q_mid, None, mid))
        return self._continue(q_mid, q, lam_mid, mid, t1, self._mark(q_mid, mid), depth + 1)

    def _mark(self, q: np.ndarray, t: float):
        """The element states' mark at the equilibrium q (at rest, as its forces)."""
        if not self.system.states:
            return None
        return self.system.states.mark(self.system.view(self.system.kin(q, None, t)))


def run_static(
    system: System, spec: Static, q0: np.ndarray, trajectory: Trajectory, stats: SolverStats
) -> None:
    """One equilibrium at spec.time: the quasi-static stepper's first state. Element states
    keep their initial values (one instant: no time to integrate them over)."""
    stepper = QuasiStaticStepper(system, spec, stats)
    trajectory.at_rest = True
    stepper.record(trajectory, stepper.init(spec.time, q0, None))
