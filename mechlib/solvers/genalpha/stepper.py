"""Generalized-alpha as a stepper (mechlib.solvers.contract): step-size control on the error
estimate, stick/slip location of joint friction, restarts, and the step-collapse watch
around `mechlib.solvers.genalpha.integrator.Integrator`.

The step size is chosen by mechlib.solvers.genalpha.rules: a rejected step shrinks it, an
accepted one grows it as far as the error estimate allows, up to a ceiling after a Newton
failure (rules.step_size); at each change the
pseudo-acceleration and the integrator's own velocity are carried to the new step
(rules.carried), because generalized-alpha's `a` and its velocity's constraint violation are
tied to the step they were made with. Outputs carry consistent velocities, accelerations and
reactions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechlib.core.outcome import SolverFailure, SolverStats, Status
from mechlib.model.analysis import Dynamic
from mechlib.solvers.consistent import consistent_state
from mechlib.solvers.contract import DenseStepper, State, StepResult, StepUnresolved
from mechlib.solvers.dense import HermiteRows, first_step, step_bound
from mechlib.solvers.dense_states import state_end
from mechlib.solvers.genalpha import rules
from mechlib.solvers.genalpha.integrator import Integrator
from mechlib.solvers.genalpha.kernels import Scales
from mechlib.solvers.genalpha.modal_run import ModalRun
from mechlib.solvers.genalpha.run import StepRun
from mechlib.solvers.runaway import StepCollapse, fell_to, snapshot, stall, step_floor
from mechlib.solvers.stick import slip_stop, switch_sticking
from mechlib.system.system import System

__all__ = ["GeneralizedAlphaStepper"]


@dataclass(kw_only=True)
class _AlphaState(State):
    """An accepted state with its consistent (qd, qdd, lam), which outputs and the error
    estimate use, and the integrator's own values it continues from: raw_qd, raw_qdd, the
    pseudo-acceleration a, raw_lam."""

    raw_qd: np.ndarray
    raw_qdd: np.ndarray
    a: np.ndarray
    raw_lam: np.ndarray


def _alpha(state: State) -> _AlphaState:
    """`state` as this stepper's own: every state it is handed is one it made."""
    assert isinstance(state, _AlphaState), "a generalized-alpha stepper's own state"
    return state


def _state(t: float, new) -> _AlphaState:
    """A state from Integrator.step's (q, qd, qdd, a, lam, consistent (qd, qdd, lam))."""
    q, qd, qdd, a, lam, (c_qd, c_qdd, c_lam) = new
    return _AlphaState(t, q, c_qd, c_qdd, c_lam, raw_qd=qd, raw_qdd=qdd, a=a, raw_lam=lam)


class GeneralizedAlphaStepper(DenseStepper):
    """Error-controlled generalized-alpha steps landing on the output times."""

    def __init__(self, system: System, spec: Dynamic, stats: SolverStats):
        super().__init__(system, spec, stats)
        self.integ = Integrator(system, spec, stats)
        self.rows = HermiteRows(system, compiled=spec.compiled != "python")
        self.dense = spec.dense and not spec.fixed_step
        self.max_step = step_bound(system, spec)  # dense: the problem's scales, not `step`
        if self.dense:
            self.h = first_step(system, spec)
        else:
            span = spec.end - spec.start
            self.h = (
                self.max_step
                if spec.fixed_step
                else min(self.max_step, rules.FIRST_STEP * span or 1e-3)
            )
        # joint frictions that can stick: without any, no slip stops to look for
        self.sticking = any(getattr(e, "can_stick", False) for e in system.elements)
        self.h_min = step_floor(spec.end)
        self.h_used = 0.0
        self.ceiling = math.inf  # the steps' ceiling after a Newton failure (s; rules.step_size)
        self.grid = spec.grid  # step ends to follow instead of the error control (or None)
        self.split = False  # the grid's step from here failed Newton: to its middle first
        self.collapse = StepCollapse(spec.name, spec.end, spec.max_steps)
        runs = spec.compiled == "runs"
        self.whole_run = (
            StepRun(self)
            if runs and StepRun.eligible(self)
            else ModalRun(self)
            if runs and ModalRun.eligible(self)
            else None
        )

    def run_compiled(self, state: State, outputs: np.ndarray, i: int, trajectory, progress):
        """The steps and rows `run_steps` takes in compiled calls from `state` towards
        outputs[i:] (mechlib.solvers.genalpha.run), where the analysis and the system allow
        them now."""
        if self.whole_run is None:
            return state, i
        return self.whole_run.run(_alpha(state), outputs, i, trajectory, progress)

    def init(self, t: float, q0: np.ndarray, qd0: np.ndarray) -> State:
        self.integ.scales = Scales(self.system, q0, self.spec.tolerance)
        s = self._restart(t, q0.copy(), qd0.copy())
        return self.restart(s) if self._switched(s) else s

    def restart(self, state: State) -> State:
        return self._restart(state.t, state.q, _alpha(state).raw_qd)

    def _restart(self, t: float, q: np.ndarray, qd: np.ndarray) -> _AlphaState:
        """Consistent accelerations (and velocities: a latch engaging is a plastic impact,
        the mass-weighted projection) at t; the pseudo-acceleration starts from them."""
        if self.system.states:
            self.system.states.start(self.system.view(self.system.kin(q, qd, t)))
        qd, qdd, lam = consistent_state(self.system, q, qd, t)
        self.integ.lu, self.integ.eta = None, 1.0
        return _AlphaState(t, q, qd, qdd, lam, raw_qd=qd, raw_qdd=qdd, a=qdd.copy(), raw_lam=lam)

    def step(self, state: State, t_out: float) -> StepResult:
        """One step towards t_out, shortened to where a sliding joint friction stops."""
        s = _alpha(state)
        new, err = self._attempt(s, t_out)
        if new is None:
            return StepResult(None, err, Status.STEP_REJECTED)
        return StepResult(self._stop_slips(s, new), err, Status.SUCCESSFUL)

    def _attempt(self, s: _AlphaState, t_out: float) -> tuple[_AlphaState | None, float]:
        """One step towards t_out and its error; None when rejected (the step size is then
        reduced)."""
        spec = self.spec
        gap = t_out - s.t
        h_try = self.trial_step(s.t, gap)
        if self.h_used and abs(h_try / self.h_used - 1.0) > 1e-9:
            s.raw_qd, s.a = rules.carried(s.qd, s.raw_qd, s.raw_qdd, s.a, h_try / self.h_used)
        self.h_used = h_try
        new = self.integ.step(s.t, h_try, s.q, s.raw_qd, s.raw_qdd, s.a, s.raw_lam, s.qdd)
        if new is None:
            self.system.states.reject()
            self.newton_failed(s, h_try)
            return None, math.inf
        err = 0.0 if spec.fixed_step or self.grid else self._error(h_try, new[0], s.qdd, new[5][1])
        if err > 1.0:
            self.system.states.reject()
            h, self.ceiling = rules.step_size(h_try, err, self.h, self.max_step, True, self.ceiling)
            self._shrink(s, h)
            return None, err
        self.split = False
        if not spec.fixed_step:
            self.h, self.ceiling = rules.step_size(
                h_try, err, self.h, self.max_step, True, self.ceiling
            )
        return _state(s.t + h_try, new), err

    def trial_step(self, t: float, gap: float) -> float:
        """The step (s) from t towards a time `gap` s ahead: along the grid where one is
        given (rules.on_grid), else of the step size, landing on the output times unless
        the output is dense (rules.towards, rules.substep)."""
        if self.grid is not None:
            ends, middles, _ = self.grid.covering(t)
            return rules.on_grid(t, gap, ends, middles, self.split)
        return rules.towards(gap, self.h) if self.dense else rules.substep(gap, self.h)

    def newton_failed(self, s: State, h: float, doing: str = "") -> None:
        """The step h (s) from s that Newton could not take (`doing`: while locating an
        event): rejected, the next a quarter as long (rules.step_size); along a grid,
        split (`_split`); a fixed step fails the run."""
        if self.grid is not None:
            self._split(s, h, doing)
            return
        if self.spec.fixed_step:
            raise _newton_failure(self.system, s.t, h, doing)
        self.stats.rejected_steps += 1
        h, self.ceiling = rules.step_size(h, math.inf, self.h, self.max_step, False, self.ceiling)
        self._shrink(s, h, counted=True)

    def _split(self, s: State, h: float, doing: str) -> None:
        """The grid's step h (s) from s failed Newton: split into the two steps it merges
        (counted as a rejected step); one that cannot be split (a single step, or its
        middle's), or a split more than the grid allows, fails the run."""
        grid = self.grid
        assert grid is not None, "a grid's step"
        ends, middles, _ = grid.covering(s.t)
        whole = rules.on_grid(s.t, math.inf, ends, middles, False)
        halved = rules.on_grid(s.t, math.inf, ends, middles, True)
        if self.split or halved >= whole:
            raise _newton_failure(self.system, s.t, h, doing)
        if not grid.allows_split(self.stats.rejected_steps):
            raise _too_many_splits(s.t, grid.most_splits or 0)
        self.split = True
        self.stats.rejected_steps += 1

    def _error(self, h: float, q1: np.ndarray, acc0: np.ndarray, acc1: np.ndarray) -> float:
        """The scaled local error of a step h (s): of the positions and, where the
        mechanism has them, of its element states (each weighed by its own scale)."""
        err = self.integ.error(h, q1, acc0, acc1)
        states = self.system.states
        estimate = states.local_error(h) if states else None
        if estimate is None:
            return err
        assert self.integ.scales is not None, "set by init"
        return max(err, self.integ.scales.state_error(estimate, states.trial))

    def _shrink(self, s: State, h: float, *, counted: bool = False) -> None:
        """A rejected step from s (`counted` already): retry with step h (s); below h_min
        the run stalls (its message names the joints of a singular position there)."""
        if not counted:
            self.stats.rejected_steps += 1
        self.h = h
        if self.h < self.h_min:  # a singular matrix says more than "no convergence"
            why = self.integ.singular or _newton_failure(self.system, s.t, self.h)
            raise stall(self.system, self.spec.name, s.t, s.q, fell_to(self.h, self.h_min), why)

    def settle(self, state: State) -> State:
        """Count the step, take its element states and memories, watch the step size."""
        system = self.system
        self.stats.steps += 1
        self.stats.step_ends.append(state.t)
        assert self.integ.scales is not None, "set by init"
        self.integ.scales.update(state.qdd)
        k = system.kin(state.q, _alpha(state).raw_qd, state.t)
        if system.states:
            system.states.accept(system.view(k))
        system.commit(k)
        self.collapse.watch(
            self.stats.steps + self.stats.rejected_steps,
            state.t,
            self.h_used,
            lambda: snapshot(system, self.view(state), state.qd),
        )
        return state

    def switch(self, state: State) -> State:
        """Stick or free joint frictions at the settled `state` (a switch restarts)."""
        return self.restart(state) if self._switched(_alpha(state)) else state

    def dense_row(self, start: State, end: State, t: float, states) -> State:
        """The row at t within start -> end: the quintic Hermite interpolant of both ends'
        (q, qd, qdd) (`end`'s own at its time), projected (mechlib.solvers.dense): every row's
        accelerations and reactions are those of the equations of motion at its state."""
        return self.rows.row(start, end, t, states)

    def dense_block(self, start: State, end: State, times: np.ndarray, z0):
        """The rows at `times` within start -> end from one compiled call where the system
        allows it (mechlib.solvers.dense.HermiteRows.block), else None."""
        return self.rows.block(start, end, times, z0, state_end(self.system.states))

    def _switched(self, s: _AlphaState) -> bool:
        if not self.sticking:
            return False
        return switch_sticking(self.system, s.q, s.raw_qd, s.t, self.view(s), consistent_state)

    def resolve(self, state: State, t: float) -> State:
        """The step from `state` re-solved to end at t (s); StepUnresolved when Newton
        fails."""
        return self._resolve(_alpha(state), t)

    def _resolve(self, s: _AlphaState, t: float) -> _AlphaState:
        """`resolve` on this stepper's own state (its own velocity and pseudo-acceleration
        carried to the shorter step)."""
        h = t - s.t
        raw_qd, a = s.raw_qd, s.a
        if self.h_used:
            raw_qd, a = rules.carried(s.qd, raw_qd, s.raw_qdd, a, h / self.h_used)
        new = self.integ.step(s.t, h, s.q, raw_qd, s.raw_qdd, a, s.raw_lam, s.qdd)
        if new is None:
            raise StepUnresolved(t)
        return _state(t, new)

    def _stop_slips(self, s: _AlphaState, new: _AlphaState) -> _AlphaState:
        """`new`, or the state at the first instant within the step where a sliding joint
        friction stops (its slip rate passes through zero: it may stick there) or a held
        one's effort passes its capacity (it lets go there)."""
        sys = self.system
        if not self.sticking:
            return new
        try:
            t = slip_stop(
                sys,
                s.t,
                new.t,
                self.view(s),
                self.view(new),
                lambda tt: self.view(self._resolve(s, tt)),
            )
            if t is None:
                return new
            if t < new.t:
                stopped = self._resolve(s, t)
                self.h_used = t - s.t  # the step its pseudo-acceleration was made for
                return stopped
        except (StepUnresolved, SolverFailure):  # a shorter step Newton cannot take: keep new
            pass
        # the re-solved steps moved the element states' trial values: back to new's
        return self._resolve(s, new.t) if sys.states else new

    def unresolved(self, state: State, new: State, failure: StepUnresolved, events) -> None:
        """A load that jumps where an event condition's zero lies (a preloaded wire going
        taut) defeats Newton on steps ending just past it; shorter steps resolve it, as for
        any step Newton cannot take: the step is rejected, the next a quarter as long."""
        self.system.states.reject()
        doing = f"locating event {events()}"
        if self.spec.fixed_step:
            raise _newton_failure(self.system, state.t, failure.t - state.t, doing)
        self.newton_failed(state, new.t - state.t, doing)


def _too_many_splits(t: float, most: int) -> SolverFailure:
    return SolverFailure(
        f"dynamic analysis stopped at t = {t:.6g} s: Newton could not take a step of the "
        f"prescribed grid after {most} splits of its steps into two (the most the grid "
        "allows)",
        time=t,
        status=Status.NEWTON_FAILED,
    )


def _newton_failure(system: System, t: float, h: float, doing: str = "") -> SolverFailure:
    while_ = f" {doing}" if doing else ""
    return SolverFailure(
        f"dynamic analysis failed at t = {t:.6g} s{while_}: Newton iterations "
        f"did not converge even with a step of {h:.3g} s (an impact or a "
        "stiffness too large for the step, a toggle position, or a load "
        "discontinuity)",
        time=t,
        status=Status.NEWTON_FAILED,
    )
