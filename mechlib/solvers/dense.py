"""Dense output (`analysis.output: dense`): output rows between the integrator's own steps.

The integrator steps at the size its error control chooses, from a first step and up to a
largest step set by the problem's own scales (or `analysis.max_step`), whatever the output
interval; each output time within an accepted step gets a row from the step's two ends:

- positions and velocities by the quintic Hermite interpolant of (q, qd, qdd) at both
  ends (generalized-alpha), or by the integrator's own dense output (Radau);
- the positions then projected onto the position constraints, the velocities onto the
  velocity constraints (mass-weighted), and the accelerations and multipliers solved from
  the equations of motion there (`consistent_state`): the row's reactions are those of the
  equations of motion at the row's state, as at a step's end;
- element states (mechlib.elements.states) by the cubic Hermite interpolant of their values
  and rates at the step's ends (mechlib.solvers.dense_states: error O(h^4), where a straight
  line between the values missed each crest by up to h^2 / 8 of its curvature).

Events still end a step where they happen, and their rows are recorded as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechlib.core.work import count
from mechlib.solvers.assembly import MAX_NEWTON, POSITION_TOLERANCE, REUSE_BELOW, solve_positions
from mechlib.solvers.consistent import consistent_state
from mechlib.solvers.contract import State
from mechlib.solvers.dense_compiled import (
    DONE,
    interpolated,
    project_loaded_row,
    project_loaded_rows,
    small_enough,
)
from mechlib.solvers.dense_states import StateEnd, advanced
from mechlib.system.system import System

__all__ = [
    "PROJECTION",
    "HermiteRows",
    "RowBlock",
    "first_step",
    "hermite",
    "natural_time",
    "projected_row",
    "step_bound",
]

_FIRST_FRACTION = 1e-6  # of the natural time: the start acceleration may be left at once
# the position Newton's exact step below which a compiled row takes it as converged (m, or
# rad/Euler parameter: q's own units; mechlib.solvers.dense_compiled._positions)
ONE_STEP = 1e-9
# mechlib.solvers.dense_compiled.project_row's parameters: solve_positions' tolerance, its
# Jacobian reuse step and iterations, and `ONE_STEP`
PROJECTION = np.array([POSITION_TOLERANCE, REUSE_BELOW, MAX_NEWTON, ONE_STEP], dtype=float)


def natural_time(system: System) -> float:
    """The mechanism's own time scale (s): sqrt(size / gravity), gravity floored at
    1 m/s^2 (a mechanism without gravity: sqrt of its size in metres)."""
    g = max(float(np.linalg.norm(system.gravity)), 1.0)
    return math.sqrt(max(system.length, 1e-6) / g)


def largest_step(system: System, spec) -> float:
    """`analysis.max_step` when given, else the natural time (s): not the span, so that
    a longer run takes the same steps over the shorter one's time."""
    if spec.max_step:
        return float(spec.max_step)
    return natural_time(system)


def step_bound(system: System, spec) -> float:
    """The largest step a dynamic run may take (s): with dense output and error control
    `largest_step`; else `analysis.max_step`, at most the output interval (the steps end
    on the output times), the output interval when not given."""
    if spec.dense and not spec.fixed_step:
        return largest_step(system, spec)
    return float(min(spec.max_step or spec.step, spec.step))


def first_step(system: System, spec) -> float:
    """A small fraction of the natural time, at most the largest step (s)."""
    return min(largest_step(system, spec), _FIRST_FRACTION * natural_time(system))


def hermite(t0: float, t1: float, a: tuple, b: tuple, t: float) -> tuple:
    """(q, qd) at t from the quintic Hermite interpolant of a = (q, qd, qdd) at t0 and
    b = (q, qd, qdd) at t1: exact for quintic motions, error O(h^6) in q."""
    return interpolated(np.stack((*a, *b)), t1 - t0, (t - t0) / (t1 - t0))


@dataclass(frozen=True)
class RowBlock:
    """Rows of one step from one compiled call: how many, their (q, qd, qdd, lam) stacked
    (rows, 3 nq + m) and their element states (rows, nz; None without states)."""

    rows: int
    states: np.ndarray
    element_states: np.ndarray | None


class HermiteRows:
    """Rows within generalized-alpha's accepted steps: the quintic Hermite interpolant of
    both ends' (q, qd, qdd), projected (`projected_row`); a row at a step's end takes the
    end's own (q, qd). The ends are stacked once per step for the compiled rows (`compiled`
    False: every row projected in Python)."""

    def __init__(self, system: System, compiled: bool = True):
        self.system, self.compiled = system, compiled
        self._step: tuple[State, State, np.ndarray] | None = None
        self._functions: tuple[object, bool] | None = None  # (coordinate block, timed)

    def _timed(self, rows) -> bool:
        """Whether the coordinate equations `rows` (System.coordinate_rows) hold a function
        of time (found again only when an event changes them)."""
        if self._functions is None or self._functions[0] is not rows:
            timed = any(rows.equations[i].function is not None for i in rows.linear)
            self._functions = (rows, timed)
        return self._functions[1]

    def row(self, start: State, end: State, t: float, states) -> State:
        """The row at t (s) within start -> end, with the element states `states`."""
        s = 1.0 if abs(t - end.t) <= 1e-12 * max(1.0, abs(t)) else (t - start.t) / (end.t - start.t)
        step = self._step
        if step is None or step[0] is not start or step[1] is not end:
            ends = np.stack((start.q, start.qd, start.qdd, end.q, end.qd, end.qdd))
            step = self._step = (start, end, ends)
        return _projected(self.system, t, step[2], end.t - start.t, s, states, self.compiled)

    def block(
        self, start: State, end: State, times: np.ndarray, z0: StateEnd | None, z1: StateEnd | None
    ) -> RowBlock | None:
        """The rows at `times` (s) within start -> end, the element states interpolated
        between their values and rates z0 and z1 (mechlib.solvers.dense_states; None
        without), in one compiled call (dense_compiled.project_loaded_rows: each row as
        `row` gives it); None where the system does not allow it (`_compiled_row`'s
        conditions, a time function in its equations, or states without rates at both
        ends). The block may hold fewer rows than asked (the kernel gave one back: `row`
        takes it)."""
        system = self.system
        arrays = system.packed_constraints()
        if not self.compiled or arrays is None or not small_enough(system):
            return None
        elements = row_elements(system)
        if elements is None or self._timed(system.coordinate_rows()):
            return None
        ends_z = _state_ends(z0, z1)
        if ends_z is None:
            return None
        nq, m, n = system.nq, system.active.size, len(times)
        ends = np.stack((start.q, start.qd, start.qdd, end.q, end.qd, end.qdd))
        out, zs = np.empty((n, 3 * nq + m)), np.empty((n, ends_z.shape[1]))
        ints, floats = arrays.packed()
        done, fresh = project_loaded_rows(
            ends, start.t, end.t, np.asarray(times, dtype=float), ints, floats,
            arrays.functions(float(times[0])), arrays.references(), arrays.bodies(), PROJECTION,
            ends_z, elements, out, zs,
        )  # fmt: skip
        count(factorizations=fresh + done, jacobian_evaluations=fresh)
        return RowBlock(done, out[:done], zs[:done] if ends_z.shape[1] else None)


def _state_ends(z0: StateEnd | None, z1: StateEnd | None) -> np.ndarray | None:
    """The element states' (z0, f0, z1, f1) stacked (4, nz) for the compiled rows ((4, 0)
    without states), or None where an end has no rates (`states_between` then interpolates
    them linearly, row by row)."""
    if z0 is None or z1 is None:
        return np.zeros((4, 0))
    (v0, f0), (v1, f1) = z0, z1
    if f0 is None or f1 is None or not advanced(z0, z1):
        return None
    return np.stack((v0, f0, v1, f1))


def row_elements(system: System) -> tuple | None:
    """The packed force elements' `args` for the compiled rows (System.compiled_forces,
    their references refreshed), or None where the Python rows take them: an element with
    no compiled form, or a joint friction (its law reads the reactions and the slip history
    the rows solve for)."""
    elements = system.compiled_forces()
    if elements is None or elements.frictions:
        return None
    elements.refresh(system)
    return elements.args


def projected_row(system: System, t: float, q, qd, states: np.ndarray | None) -> State:
    """The row at t from interpolated (q, qd) and element states: q onto the position
    constraints, qd onto the velocity ones, qdd and lam from the equations of motion; its
    snapshot carries the interpolated element states. The system's element states are
    left as they were."""
    ends = np.zeros((6, system.nq))
    ends[3], ends[4] = q, qd
    return _projected(system, t, ends, 1.0, 1.0, states)


def _projected(
    system: System, t: float, ends: np.ndarray, h: float, s: float, states, compiled: bool = True
) -> State:
    """`projected_row` of the interpolant of `ends` at the fraction s of the step h (s), in
    one compiled call where `compiled` and the system allow it."""
    snapshot = system.snapshot()
    if states is not None:
        snapshot["states"] = states.copy()
    row = _compiled_row(system, t, ends, h, s, states) if compiled else None
    if row is not None:
        q, qd, qdd, lam = row
        return State(t, q, qd, qdd, lam, snapshot=snapshot)
    q, qd = interpolated(ends, h, s)
    kept = system.states.trial
    if states is not None:
        system.states.trial = states
    try:
        q, _ = solve_positions(system, q, t)
        qd, qdd, lam = consistent_state(system, q, qd, t)
    finally:
        system.states.trial = kept
    return State(t, q, qd, qdd, lam, snapshot=snapshot)


def _compiled_row(
    system: System, t: float, ends: np.ndarray, h: float, s: float, states=None
) -> tuple[np.ndarray, ...] | None:
    """(q, qd, qdd, lam) of `_projected` from one compiled call (mechlib.solvers.dense_compiled)
    for a small packed system whose active elements are packed ones (`row_elements`), at
    element states `states`; None where the Python
    path must take the row (a larger system, another element, or the kernel gave up:
    near a toggle, no convergence)."""
    arrays = system.packed_constraints()
    if arrays is None or not small_enough(system):
        return None
    elements = row_elements(system)
    if elements is None:
        return None
    z = system.states.trial if states is None else states
    nq, m = system.nq, system.active.size
    out = np.empty(3 * nq + m)
    ints, floats = arrays.packed()
    status, fresh = project_loaded_row(
        ends, h, s, ints, floats, arrays.functions(t), arrays.references(), arrays.bodies(),
        PROJECTION, z, elements, out,
    )  # fmt: skip
    count(factorizations=fresh, jacobian_evaluations=fresh)
    if status != DONE:
        return None
    count(factorizations=1)  # the saddle matrix's, as consistent_state counts it
    return out[:nq], out[nq : 2 * nq], out[2 * nq : 3 * nq], out[3 * nq :]
