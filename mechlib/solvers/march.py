"""The one loop of the analyses in time: a stepper marched to the output times, with events.

Kinematic, quasi-static and dynamic (generalized-alpha, Radau) analyses are steppers
(mechlib.solvers.contract); `march` drives them all:

    state = init(start); record it; arm the events
    for each output time t_out after start:
        until t_out is reached:
            check the step limit (analysis.max_steps, accepted and rejected steps)
            result = step(state, t_out)       (rejected: the stepper retries shorter)
            an armed event fired within the step: locate it on re-solved steps, settle
                and record the state there, carry out its actions, restart (or stop)
            else: accept the new state, re-arm the events
        record the state at t_out, report progress

A dense stepper (`analysis.output: dense`) instead steps towards the end at its own step
sizes and records a row at each output time within each accepted step (`dense_row`, from
the step's two ends: mechlib.solvers.dense), and the rows before an event within its step.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Literal

import numpy as np

from mechlib.core.outcome import SolverFailure, SolverStats, Status
from mechlib.model.analysis import Trajectory, row_times
from mechlib.solvers.contract import DenseStepper, State, Stepper, StepResult, StepUnresolved
from mechlib.solvers.dense_states import StateEnd, state_end, states_between
from mechlib.solvers.events import EventMonitor, fire, first_events

__all__ = ["accepted", "check_step_limit", "march"]


def march(
    stepper: Stepper,
    q0,
    qd0,
    trajectory: Trajectory,
    *,
    progress: Callable[[float, float], None] | None = None,
    events=(),
    event_log: list | None = None,
) -> Status:
    """Fill `trajectory` at the output times of `stepper.spec` and at the events (logged
    in `event_log`); SUCCESSFUL, or EVENT_STOP when an event stopped the run. A failure
    raises SolverFailure and leaves what was recorded."""
    spec, stats = stepper.spec, stepper.stats
    monitor = EventMonitor(events)
    trajectory.at_rest = stepper.at_rest
    s = stepper.init(spec.start, q0, qd0)
    stepper.record(trajectory, s)
    monitor.arm(s.t, stepper.view(s))
    if isinstance(stepper, DenseStepper) and stepper.dense:
        return _march_dense(stepper, s, trajectory, monitor, progress, event_log)
    outputs = row_times(spec)
    i = 0
    while i < len(outputs):
        if not monitor.armed:  # steps in compiled calls, where the stepper has them
            s, i = stepper.run_compiled(s, outputs, i, trajectory, progress)
            if i == len(outputs):
                break
        t_out = outputs[i]
        if t_out - s.t > 1e-12 * max(1.0, abs(t_out)):  # one step in Python
            check_step_limit(spec, stats, s.t)
            new = accepted(stepper.step(s, t_out), s.t)
            if new is None:
                continue
            after = (
                _events(stepper, monitor, s, new, trajectory, event_log) if monitor.armed else None
            )
            if after is Status.EVENT_STOP:
                return Status.EVENT_STOP
            if after is None:
                after = stepper.accept(new)
                if monitor.armed:
                    monitor.arm(after.t, stepper.view(after))
            s = after
        if t_out - s.t <= 1e-12 * max(1.0, abs(t_out)):
            stepper.record(trajectory, s)
            i += 1
            if progress:
                progress(s.t, spec.end)
    return Status.SUCCESSFUL


def _march_dense(
    stepper: DenseStepper,
    s: State,
    trajectory: Trajectory,
    monitor: EventMonitor,
    progress: Callable[[float, float], None] | None,
    log: list | None,
) -> Status:
    """`march` for a dense stepper: steps towards the end, rows at the output times
    within each accepted step (and before an event, within its step)."""
    spec, system = stepper.spec, stepper.system
    rows = _Rows(stepper, trajectory, row_times(spec), progress)
    while spec.end - s.t > 1e-12 * max(1.0, abs(spec.end)):
        if not monitor.armed:  # steps in compiled calls, where the stepper has them
            s, rows.next = stepper.run_compiled(s, rows.times, rows.next, trajectory, progress)
            if spec.end - s.t <= 1e-12 * max(1.0, abs(spec.end)):
                break
        check_step_limit(spec, stepper.stats, s.t)
        z0 = state_end(system.states)  # the element states and rates at the step's start
        new = accepted(stepper.step(s, spec.end), s.t)
        if new is None:
            continue
        after = None
        if monitor.armed:
            after = _events(
                stepper, monitor, s, new, trajectory, log, functools.partial(rows.before, s, z0)
            )
        if after is Status.EVENT_STOP:
            return Status.EVENT_STOP
        if after is None:
            # the rows within the step first, with the model the step was solved with: a
            # joint friction sticking or letting go at `new` changes it (the restart)
            stepper.settle(new)
            rows.upto(s, new, z0, True)
            after = stepper.switch(new)
            if monitor.armed:
                monitor.arm(after.t, stepper.view(after))
        elif after is not s:
            rows.at_event(after)
        s = after
    return Status.SUCCESSFUL


class _Rows:
    """The output times still to record, recorded from dense steps."""

    def __init__(self, stepper: DenseStepper, trajectory: Trajectory, times, progress):
        self.stepper, self.trajectory, self.progress = stepper, trajectory, progress
        self.times, self.next = times, 0

    def _due(self, t: float, inclusive: bool) -> bool:
        if self.next >= len(self.times):
            return False
        return self._is_due(self.times[self.next], t, inclusive)

    @staticmethod
    def _is_due(time: float, t: float, inclusive: bool) -> bool:
        """The output time `time` (s) lies before t (s) (or at it, `inclusive`)."""
        gap = time - t
        tiny = 1e-12 * max(1.0, abs(t))
        return gap <= tiny if inclusive else gap < -tiny

    def upto(self, start: State, end: State, z0: StateEnd | None, inclusive: bool) -> None:
        """Record the output times up to end.t (inclusive or not) within start -> end: in
        one block where the stepper gives one (`dense_block`), the rest row by row; z0 the
        element states and their rates at start (None without), those at end the accepted
        ones now (mechlib.solvers.dense_states)."""
        z1 = state_end(self.stepper.system.states) if z0 is not None else None
        due = self._last_due(end.t, inclusive)
        if due > self.next:
            self._block(start, end, z0, due)
        while self._due(end.t, inclusive):
            t = float(self.times[self.next])
            states = None
            if z0 is not None and z1 is not None:
                h = end.t - start.t
                states = states_between(z0, z1, h, (t - start.t) / h)
            self._record(self.stepper.dense_row(start, end, t, states))

    def _last_due(self, t: float, inclusive: bool) -> int:
        """The index after the last output time due by t (s) (`_is_due`): found by
        bisection, then checked against the rule itself at its ends."""
        tiny = 1e-12 * max(1.0, abs(t))
        edge = t + tiny if inclusive else t - tiny
        due = max(
            self.next, int(np.searchsorted(self.times, edge, "right" if inclusive else "left"))
        )
        while due > self.next and not self._is_due(self.times[due - 1], t, inclusive):
            due -= 1
        while due < len(self.times) and self._is_due(self.times[due], t, inclusive):
            due += 1
        return due

    def _block(self, start: State, end: State, z0: StateEnd | None, due: int) -> None:
        """The rows up to output index `due` from the stepper's `dense_block`, if any."""
        times = self.times[self.next : due]
        block = self.stepper.dense_block(start, end, times, z0)
        if block is None or not block.rows:
            return
        system, n = self.stepper.system, block.rows
        self.trajectory.extend(
            times[:n], block.states, system.nq, system.snapshot(), (), np.zeros((n, 0)),
            block.element_states,
        )  # fmt: skip
        self.next += n
        if self.progress:
            self.progress(float(times[n - 1]), self.stepper.spec.end)

    def before(self, start: State, z0: StateEnd | None, event: State) -> None:
        """Record the output times before an event's instant within start -> event."""
        self.upto(start, event, z0, False)

    def at_event(self, state: State) -> None:
        """An output time at the event's instant gets the state the run goes on from."""
        if self._due(state.t, True):
            self._record(state)

    def _record(self, state: State) -> None:
        self.stepper.record(self.trajectory, state)
        self.next += 1
        if self.progress:
            self.progress(state.t, self.stepper.spec.end)


def _events(
    stepper: Stepper,
    monitor: EventMonitor,
    s: State,
    new: State,
    trajectory: Trajectory,
    log: list | None,
    before: Callable[[State], None] | None = None,
) -> State | Literal[Status.EVENT_STOP] | None:
    """If events fire during the step s -> new: the state at the first one, settled and
    recorded (after `before(it)`: a dense march's rows within the step), the actions done,
    restarted (EVENT_STOP when an action stops the run); else None. When a re-solved step
    of the location cannot be taken the stepper rejects the step (or fails): `s` is
    returned, to step again from."""
    try:
        hit = first_events(
            monitor, s.t, new.t, stepper.view(new), lambda t: stepper.view(stepper.resolve(s, t))
        )
        if hit is None:
            return None
        t_e, fired = hit
        at = stepper.resolve(s, t_e)
    except StepUnresolved as failure:
        stepper.unresolved(
            s,
            new,
            failure,
            lambda: ", ".join(f"'{e.name}'" for e in monitor.crossed(new.t, stepper.view(new))),
        )
        return s
    at = stepper.settle(at)
    if before is not None:
        before(at)
    stepper.record(trajectory, at)
    trajectory.event_rows.append(len(trajectory) - 1)
    system = stepper.system
    if fire(system, monitor, fired, system.kin(at.q, at.qd, t_e), log):
        return Status.EVENT_STOP
    at = stepper.restart(at)
    monitor.arm(at.t, stepper.view(at))
    return at


def accepted(result: StepResult, t: float) -> State | None:
    """The state of a step to go on from, by its status and error estimate: None for a
    rejected step (the stepper retries shorter); a status that is neither ends the run
    (SolverFailure with that status, from time t, s). A step reported successful with an
    error estimate above 1 breaks the contract: the stepper's error control is wrong."""
    if result.status is Status.STEP_REJECTED:
        return None
    if result.status is not Status.SUCCESSFUL or result.state is None:
        raise SolverFailure(
            f"step from t = {t:.6g} s: {result.status.message}", time=t, status=result.status
        )
    if result.error is not None and not result.error <= 1.0:
        raise SolverFailure(
            f"step from t = {t:.6g} s accepted with a local error estimate of {result.error:.3g} "
            "(above 1): the integrator's step-size control is at fault",
            time=t,
            status=Status.INTEGRATOR_FAILED,
        )
    return result.state


def check_step_limit(spec, stats: SolverStats, t: float) -> None:
    """Raise SolverFailure (MAX_STEPS_REACHED) once the run at time t (s) has used its
    `max_steps` (accepted and rejected steps)."""
    taken = stats.steps + stats.rejected_steps
    if taken >= spec.max_steps:
        raise SolverFailure(
            f"{spec.name} analysis stopped at t = {t:.6g} s of {spec.end:g} s: the limit of "
            f"{spec.max_steps} steps (analysis.max_steps, accepted and rejected) is reached; "
            "raise analysis.max_steps if the run is sound, or look for what keeps the steps "
            "small",
            time=t,
            status=Status.MAX_STEPS_REACHED,
        )
