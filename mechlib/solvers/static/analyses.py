"""Static and quasi-static analyses: equilibria with inertia ignored
(mechlib.solvers.static.equilibrium).

Quasi-static continues along the motions' time functions: each equilibrium starts from the
linear extrapolation in time of the last two and on the last one's stiffness, and an interval
Newton cannot take is subdivided.
Static solves one instant: the quasi-static stepper's first state.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechlib.core.outcome import SolverFailure, SolverStats, Status
from mechlib.model.analysis import Static, Trajectory
from mechlib.solvers.assembly import solve_rates
from mechlib.solvers.contract import State, Stepper, StepResult
from mechlib.solvers.static.equilibrium import Tangent, equilibrium
from mechlib.system.system import System

__all__ = ["QuasiStaticStepper", "equilibrium", "run_static"]

_MAX_SUBDIVISIONS = 10


@dataclass(kw_only=True)
class _Equilibrium(State):
    """An equilibrium, the one before it (its extrapolation's start: q_prev at t_prev, s)
    and the stiffness its Newton ended with (None: none differenced)."""

    q_prev: np.ndarray
    t_prev: float
    stiffness: np.ndarray | None = None


def _equilibrium(state: State) -> _Equilibrium:
    """`state` as this stepper's own: every state it is handed is one it made."""
    assert isinstance(state, _Equilibrium), "a quasi-static stepper's own state"
    return state


class QuasiStaticStepper(Stepper):
    """Equilibria at the output times; a failed interval is retried in up to 2^10 sub-steps
    (rejected steps). Velocities and accelerations are those the motions prescribe
    (minimum-norm); an equilibrium is recorded before it is committed, so that its outputs
    see the slip anchors the solver measured from (the previous equilibrium). Each state
    keeps the stiffness its Newton ended with, and a step from it starts on that stiffness
    (mechlib.solvers.static.equilibrium.Tangent) and from the extrapolation of the state and the
    one before:
    a step depends on its start state and end time only, so the trial times of an event's
    location can be solved in any order."""

    at_rest = True

    def init(self, t: float, q0: np.ndarray, qd0: np.ndarray | None) -> State:
        # the start has no multipliers yet (None: equilibrium starts them from the loads)
        tangent = Tangent()
        q, lam = self._subdivided(q0, q0, None, t, t, self._mark(q0, t), tangent)
        return self.settle(self._state(q, lam, t, q0, t, tangent))

    def step(self, state: State, t_out: float) -> StepResult:
        return StepResult(self._solve(_equilibrium(state), t_out), None, Status.SUCCESSFUL)

    def resolve(self, state: State, t: float) -> State:
        return self._solve(_equilibrium(state), t)

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
        """The equilibrium of the changed model: its multipliers restart from the loads, its
        stiffness is differenced afresh."""
        tangent = Tangent()
        q, lam = equilibrium(self.system, state.q, None, state.t, self.stats, tangent=tangent)
        return self._state(q, lam, state.t, q, state.t, tangent)

    def _solve(self, start: _Equilibrium, t1: float) -> State:
        """The equilibrium at t1 continued from `start`: on a copy of its stiffness, from the
        guess extrapolated linearly in time from it and the equilibrium before it."""
        q, q_prev, t0, t_prev = start.q, start.q_prev, start.t, start.t_prev
        guess = q + (t1 - t0) / (t0 - t_prev) * (q - q_prev) if t1 > t0 > t_prev else q
        tangent = Tangent(start.stiffness)
        q1, lam = self._subdivided(q, guess, start.lam, t0, t1, start.elements, tangent)
        return self._state(q1, lam, t1, q, t0, tangent)

    def _state(self, q, lam, t: float, q_prev, t_prev: float, tangent: Tangent) -> State:
        """The equilibrium (q, lam) at t as a state, after q_prev at t_prev, with the
        stiffness its Newton ended with."""
        qd, qdd = solve_rates(self.system, q, t)
        mark, stiffness = self._mark(q, t), tangent.stiffness
        return _Equilibrium(
            t, q, qd, qdd, lam, mark, q_prev=q_prev, t_prev=t_prev, stiffness=stiffness
        )

    def _subdivided(
        self, q, guess, lam, t0: float, t1: float, marks, tangent: Tangent, depth: int = 0
    ):
        """(q, lam) at t1 from the equilibrium (q, lam) at t0 (element states `marks`), Newton
        from `guess`; where it fails, the interval in two halves, recursively."""
        system = self.system
        if system.states:
            system.states.resume(marks)
        try:
            return equilibrium(
                system, guess, lam, t1, self.stats, states_step=t1 - t0, tangent=tangent
            )
        except SolverFailure:
            if depth >= _MAX_SUBDIVISIONS or t1 <= t0:
                raise
        self.stats.rejected_steps += 1
        mid = 0.5 * (t0 + t1)
        q_mid, lam_mid = self._subdivided(q, q, lam, t0, mid, marks, tangent, depth + 1)
        system.commit(system.kin(q_mid, None, mid))
        mark = self._mark(q_mid, mid)
        return self._subdivided(q_mid, q_mid, lam_mid, mid, t1, mark, tangent, depth + 1)

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
