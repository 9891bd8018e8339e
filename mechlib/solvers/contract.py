"""The integrator contract: what every analysis in time gives the one loop (mechlib.solvers.march).

After scipy's `OdeSolver` and diffrax's `step -> (state, error, status)`: an analysis is a
`Stepper` with `init` (the state at the start) and `step` (one step towards an output time,
returning a `StepResult`: the new state, its error estimate and a `Status`), plus what the
loop needs around a step: `resolve` (the step re-solved to end earlier: event location),
`accept` and `settle` (a state becomes the last accepted one), `restart` (after an event
changed the model), `view` and `record`. A run that cannot go on raises `SolverFailure`
carrying a `Status`; `Solution.result` carries the run's status next to its message.

Work counters (`SolverStats`): each stepper counts its accepted and rejected steps and its
Newton iterations; factorisations and Jacobian evaluations are counted where they happen
(mechlib.core.work), so every analysis fills them alike.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mechlib.core.outcome import SolverFailure, SolverStats, Status

if TYPE_CHECKING:
    from mechlib.kinematics.view import StateView
    from mechlib.model.analysis import Trajectory
    from mechlib.system.system import System

__all__ = ["DenseStepper", "State", "StepResult", "StepUnresolved", "Stepper"]


@dataclass
class State:
    """A state of the mechanism at time t (s) as outputs read it: positions q, velocities
    qd, accelerations qdd, multipliers lam; `elements`: the element states there (a
    `mechlib.elements.states` mark, None without element states or where the stepper keeps them);
    `snapshot`: the system's snapshot to record it with (None: taken when recorded).
    Steppers add what they continue from."""

    t: float
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    lam: np.ndarray
    elements: tuple | None = None
    snapshot: dict | None = None


@dataclass(frozen=True)
class StepResult:
    """What `Stepper.step` returns: the new state (None when rejected), the scaled local
    error estimate (accepted when <= 1; inf when Newton failed; None for analyses without
    one: each kinematic or quasi-static row is solved on its own, Radau keeps SciPy's),
    and the status (SUCCESSFUL or STEP_REJECTED)."""

    state: State | None
    error: float | None
    status: Status


class StepUnresolved(Exception):
    """A step re-solved to end at `t` (s) that the stepper could not take."""

    def __init__(self, t: float):
        super().__init__(t)
        self.t = t


class Stepper(ABC):
    """An analysis in time, stepped by `mechlib.solvers.march.march`.

    Steps land on the output times: `step(state, t_out)` never goes past `t_out`. A failure
    that ends the run raises SolverFailure (with its Status); a step the stepper retries
    smaller returns Status.STEP_REJECTED. Element states (mechlib.elements.states) advance with the
    mechanism: trial values along a step, accepted by `settle`.
    """

    at_rest = False  # its states are equilibria (Trajectory.at_rest)
    dense = False  # steps at their own size; rows from `dense_row` (DenseStepper)

    def __init__(self, system: System, spec, stats: SolverStats):
        self.system, self.spec, self.stats = system, spec, stats

    @abstractmethod
    def init(self, t: float, q0: np.ndarray, qd0: np.ndarray) -> State:
        """The accepted state at the start t (s) from the assembled q0, qd0."""

    @abstractmethod
    def step(self, state: State, t_out: float) -> StepResult:
        """One step from `state` towards the output time t_out (s)."""

    @abstractmethod
    def resolve(self, state: State, t: float) -> State:
        """The step from `state` re-solved to end at t (s), for locating an event; raises
        StepUnresolved (or SolverFailure) when it cannot be taken."""

    @abstractmethod
    def settle(self, state: State) -> State:
        """`state` becomes the last accepted state (element memories and states, counters)."""

    @abstractmethod
    def restart(self, state: State) -> State:
        """The state to go on from after an event changed the model at `state`."""

    def run_compiled(
        self,
        state: State,
        outputs: np.ndarray,
        i: int,
        trajectory: Trajectory,
        progress: Callable[[float, float], None] | None,
    ) -> tuple[State, int]:
        """Steps taken in compiled calls from `state` towards the output times outputs[i:]
        (with `dense`, towards the end), their rows recorded in `trajectory`: (the state
        reached, accepted and settled; the index of the next output time). `march` calls it
        while no event is armed and steps in Python from where it stops. By default none."""
        return state, i

    def accept(self, state: State) -> State:
        """Settle a step's state; a stepper that switches the model there (joint friction
        sticking) returns the state it restarts from."""
        self.settle(state)
        return self.switch(state)

    def switch(self, state: State) -> State:
        """After `settle`: the state to go on from once the model is switched at the
        settled `state` (joint friction sticking or letting go: a restart), else `state`.
        Rows within the step that ended at `state` are recorded before, with the model
        the step was solved with."""
        return state

    def unresolved(
        self, state: State, new: State, failure: StepUnresolved, events: Callable[[], str]
    ) -> None:
        """Locating the events `events()` (their names) within the step state -> new failed
        at `failure.t`: reject the step (the next one is shorter) or raise SolverFailure.
        By default a failure."""
        raise SolverFailure(
            f"{self.spec.name} analysis failed at t = {state.t:.6g} s locating event {events()}",
            time=state.t,
            status=Status.NEWTON_FAILED,
        )

    def view(self, state: State) -> StateView:
        """The state view of `state` (for event conditions)."""
        return self.system.view(self.system.kin(state.q, state.qd, state.t), state.lam)

    def record(self, trajectory: Trajectory, state: State) -> None:
        trajectory.record(state.t, state.q, state.qd, state.qdd, state.lam, snapshot=state.snapshot)


class DenseStepper(Stepper):
    """A stepper that can give rows between its step ends: with `dense` set it steps at
    its own size and `march` takes the output rows from `dense_row` (mechlib.solvers.dense)."""

    @abstractmethod
    def dense_row(self, start: State, end: State, t: float, states) -> State:
        """The row at t (s) within the accepted step start -> end; `states`: the element
        states interpolated there (None without)."""

    def dense_block(self, start: State, end: State, times: np.ndarray, z0):
        """The rows at `times` (s) within the accepted step start -> end in one call, the
        element states interpolated from z0 (their values and rates at start: mechlib.
        solvers.dense_states.state_end; None without) to the accepted ones
        (mechlib.solvers.dense.RowBlock: perhaps fewer rows than asked), or None: `march`
        then takes them from `dense_row` one by one."""
        return None
