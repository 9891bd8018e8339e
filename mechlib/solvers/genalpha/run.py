"""Runs of generalized-alpha steps in one compiled call.

For a rigid system with no element states but those of `valve` actuators with a constant
command (mechlib.solvers.genalpha.run_states) or a clearance joint's wear work, no force
element without a compiled form, no stuck joint friction and no time function in its
equations (a free mechanism under gravity, with springs, dampers, sliding joint friction and
primitive contacts: the bench models, a free deployment phase; a ram driven by its
servo-actuator; a ball rattling in its socket), `run_steps` takes accepted steps one after
another, landing on the output times (`output: steps`) or towards the end (dense output), as
`GeneralizedAlphaStepper.step`, `accept` and `march` do them -- the step size from the error
estimate, the Newton iterations (mechlib.solvers.genalpha.compiled.newton), the error
estimate, the acceleration scales, the angles' unwrapping, the contacts' memories committed
(mechlib.elements.contact.memory, before the step's rows, as `march` settles a step before
its rows), the rows at the output times (a step's own state, or dense rows interpolated and
projected by mechlib.solvers.dense_compiled.project_row) -- without returning to Python
between steps.

Before a step that needs a new factorisation of the iteration matrix (a stale one, or a step
size more than 25 % away from the factored one) it factors [[M, phi_q^T], [phi_q, 0]] at the
step's predicted state, as the Python step does, with the kernel the Python path uses
(mechlib.linalg.flat_lu.refactor: dense or band LU). For SuperLU's factors, or a matrix the kernel
finds singular, it returns REFACTOR: `StepRun` factors it in Python (or fails the step as
the Python step does) and calls it again for that step. At a new step size it carries the
integrator's velocity and pseudo-acceleration to it as the Python step does (rules.carried;
ctrl[RESTARTED] tells `StepRun` that the state it hands back has them). It stops, leaving the
state where it was (but for those two), before any step that needs what only the Python
stepper does: a step below the step floor, Newton stalling on a matrix it cannot refresh (one
made for an earlier step, or for this one with the differenced tangent kept, is refreshed at
Newton's iterate and the iteration goes on, as the Python step does: `_refreshed`), the step
limit, a step the step-collapse watch must see (`_watched`: where a window opens or may
close), a dense row the compiled projection gives back; and before recording a non-finite
row.
`march` then takes one step in Python and calls it again: the same steps, iterations and
results as the Python loop to round-off (tests/mechlib/test_genalpha_run.py,
tests/mechlib/contact/test_contact_runs.py).
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.core.outcome import SolverFailure
from mechlib.core.work import count
from mechlib.elements.compiled_forces import (
    CompiledForces,
    advance_states,
    any_elements,
    element_tangent,
    slip_rates,
    slipping_on,
    update_references,
)
from mechlib.elements.contact import group as contact_group
from mechlib.elements.contact.group import commit_contacts, contacts_tangent
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics.coordinates import AngleMeasure
from mechlib.linalg.flat_lu import SUPERLU, refactor
from mechlib.solvers.dense import PROJECTION
from mechlib.solvers.dense_compiled import (
    DONE,
    project_worked_row,
    row_work,
    small_enough,
)
from mechlib.solvers.finite import all_finite
from mechlib.solvers.genalpha import kernels as gk
from mechlib.solvers.genalpha import rules
from mechlib.solvers.genalpha.call_rows import FED_ROWS, FED_SECONDS, CallRows
from mechlib.solvers.genalpha.compiled import CONVERGED, rigid_work, worked_newton
from mechlib.solvers.genalpha.run_states import (
    RunStates,
    accept_states,
    end_rates,
    interpolate_states,
    record_states,
    states_error,
    trial_start,
)
from mechlib.solvers.runaway import COLLAPSE_STEPS
from mechlib.system.saddle import coupled_pattern, saddle_values

__all__ = ["FAILED", "REFACTOR", "STOPPED", "StepRun", "run_steps"]

_NO_GRID = np.zeros((2, 0))  # `run_steps`'s grid where the steps follow the error control

STOPPED = 1  # the run stopped before a step (or a row) that Python must take
REFACTOR = 2  # stopped before a step that needs a new iteration matrix (ctrl[NEXT_H]: its h)
FAILED = 3  # Newton stalled on the step after a new iteration matrix: the step fails

# slots of the control array `ctrl` (in: settings; in/out: the stepper's state)
T, H, H_USED, LU_H, ETA, STALE = 0, 1, 2, 3, 4, 5
MAX_STEP, END, MAX_STEPS, TOL, ERROR_CONSTANT = 6, 7, 8, 9, 10
ALPHA_M, ALPHA_F, BETA, GAMMA, DENSE = 11, 12, 13, 14, 15
FRESH, NEXT_H = 16, 17  # in: the matrix is new for the next step; out: that step's h
REFACTORED = 18  # out: the iteration matrices factored in the call
RESTARTED = 19  # out: velocity and pseudo-acceleration carried to a new step size (H_USED: h)
H_MIN = 20  # in: the run's step floor (s)
RETANGENT = 21  # in/out: a slow step's next matrix takes a new tangent (rules.retangents)
TRIED = 22  # in: the matrix new for the next step (FRESH) was refactored for slowness
CEILING = 23  # in/out: the steps' ceiling after a Newton failure (s; rules.step_size)
GRID = 24  # in: the steps follow `grid` (rules.on_grid), no error test
SPLIT = 25  # in/out: the grid's step from here failed Newton: to its middle first
# in: the matrix new for the next step (FRESH) took a new differenced tangent, or the
# system has none (Integrator.stiff False): Newton stalling on it fails the step
RENEWED = 26
STIFF = 27  # in: 1.0 where the iteration matrix holds a tangent (Integrator.stiff)
WATCH = 28  # in: the step-collapse watch's open window: its first step count (-1: none)
# in: how far dense steps go in this call (s): END, or the last end of a grid still growing
# (mechlib.model.step_feed); END stays the analysis's for the step-collapse watch's pace
REACH = 29
CTRL_SIZE = 30
# the constants of the step-size control and of Newton are not in `ctrl`: the kernels call
# the rules of mechlib.solvers.genalpha.rules, as the Python stepper does
# slots of the counters `counts` (in/out): steps, Newton iterations, the dense rows' work
STEPS, REJECTED, ITERATIONS, ROW_JACOBIANS, ROW_FACTORS = 0, 1, 2, 3, 4


@njit(**KERNEL)
def _reached(t_out, t):
    return t_out - t <= 1e-12 * max(1.0, abs(t_out))


@njit(**KERNEL)
def run_steps(
    own, own_lam, cons, cons_lam, ctrl, counts, outs, first, ints, floats, functions, body,
    fi, ff, layout, q_abs, a_ref, angles, refs_all, block_angles, projection, rows_t,
    rows_state, rows_refs, most_steps, elements, rest, rates, states, tangent, kept, grid,
    steps_t,
):  # fmt: skip
    """Accepted steps from the state (`own` (4, nq): q, qd, qdd, a of the integrator,
    `own_lam` its multipliers; `cons` (2, nq): the consistent qd, qdd, `cons_lam` the
    consistent multipliers), in place, recording the rows at the output times outs[first:]
    (rows_t, rows_state: q, qd, qdd, lam stacked, rows_refs: the angles' references): with
    ctrl[DENSE], steps towards the end and rows projected within each step
    (mechlib.solvers.dense_compiled, `projection` its parameters), else steps landing on each
    output time and the rows their states. At most len(rows_t) rows and `most_steps`
    steps. The iteration matrix's factors (fi, ff: mechlib.linalg.flat_lu) are refactored in
    place when the saddle pattern's `layout` (its kind, rows, columns, and the flat
    layout's places, rows and columns; kind -1: none) fits them. `angles` = (ai, aj, au, av)
    of every angle measure, `refs_all` their references (in place), `block_angles` the
    indices of the constraint rows' angles among them. `elements`: the packed force elements
    (mechlib.elements.compiled_forces; their tangent enters the iteration matrix: the
    contacts' own, the differenced tangent of `rest` = (the elements but the contacts,
    the columns they act on)), `rates` (n, 2) their frictions' slip rates (rad/s) at the
    last two accepted states (in place); it stops before a step in which a friction may
    stick. The contacts' memories are committed on each accepted state, in place in
    `elements` (mechlib.elements.contact.group.commit_contacts), the time and approach
    speeds of each accepted step kept in `kept` (contact_group.history). `states`: the
    element states (mechlib.solvers.genalpha.run_states: accepted, trial, rates, history,
    error weights, the rows' states), advanced in each step's Newton iterations and
    tangent, tested by the step's error, their rates at its end evaluated once (for the rows
    and the next step), accepted with it, interpolated into the rows (cubic Hermite).
    `tangent` (2, nq, nq): the elements' (K, C) of the last refactor (in place; NaN: none
    yet), kept from call to call as the Python stepper keeps its tangent. `grid` (2, n):
    with ctrl[GRID], the step ends to follow and their middles (mechlib.model.step_grid;
    no error test); `steps_t` (most_steps,): out, the accepted steps' end times (s).
    Returns (0, STOPPED, REFACTOR or FAILED; next output index, rows written)."""
    nq = own.shape[1]
    m = own_lam.shape[0]
    dense = ctrl[DENSE] != 0.0
    refs = refs_all[block_angles]  # the constraint rows' angles' references (a copy)
    new_refs, new_block = refs_all.copy(), refs.copy()
    true = np.empty(3 * nq + m)
    ends = np.empty((6, nq))
    params = np.empty(5)
    params[2], params[3], params[4] = ctrl[TOL], ctrl[ALPHA_M], ctrl[ALPHA_F]
    kind, prow, pcol, place, brow, bcol = layout
    values = np.empty(prow.shape[0])
    slips = np.empty(rates.shape[0])  # the frictions' slip rates at a state
    work = rigid_work(ints, floats, nq)  # Newton's arrays, made once for the call's steps
    # and the dense rows' (empty without dense rows: a large system's rows never come here)
    rows_nq, rows_m = (nq, m) if dense else (0, 0)
    row_arrays = row_work(ints, floats, body, rows_nq, rows_m)
    i, written, taken = first, 0, 0
    while True:
        t = ctrl[T]
        row = _row_at(dense, i, written, t, ctrl, outs, own, cons, cons_lam, refs_all, rows_t,
                      rows_state, rows_refs)  # fmt: skip
        if row == _WRITTEN:
            record_states(states, written)
            written += 1
            i += 1
            continue
        if row != _STEP:  # done (0), or a row Python must look at
            return STOPPED * (row != _FULL), i, written
        target = ctrl[REACH] if dense else outs[i]
        limit = _limits(counts, ctrl, taken, most_steps)
        if limit >= 0:
            return limit, i, written
        h_try = _trial_step(t, target - t, ctrl, dense, grid)
        _carried(h_try, ctrl, own, cons)  # GeneralizedAlphaStepper._attempt
        if _watched(counts, ctrl, t, h_try):
            return STOPPED, i, written  # the step-collapse watch
        fresh = ctrl[FRESH] != 0.0
        ctrl[FRESH] = 0.0
        t_new = t + h_try
        due = _rows_due(outs, i, t_new, dense)  # rows within the step
        if written + due > rows_t.shape[0]:
            return (STOPPED if written == 0 else 0), i, written
        am, af, beta, gamma = ctrl[ALPHA_M], ctrl[ALPHA_F], ctrl[BETA], ctrl[GAMMA]
        q1, qd1, qdd1 = gk.predict(own[0], own[1], own[2], own[3], h_try, am, beta, gamma)
        trial_start(states)
        # refactored for slowness with the tangent kept (Integrator.step's `tried`)
        tried = fresh and ctrl[TRIED] != 0.0
        renewed = fresh and ctrl[RENEWED] != 0.0  # Integrator._compiled_step's `refreshed`
        if _matrix_due(ctrl, h_try, fresh):
            # [[M, phi_q^T], [phi_q, 0]] at the predicted state (Integrator._iteration_matrix)
            stale = ctrl[STALE] != 0.0
            retangent = stale and ctrl[RETANGENT] != 0.0
            if not _refactored(q1, qd1, own_lam, h_try, ctrl, kind, ints, floats,
                               functions, refs, body, prow, pcol, values, place, brow, bcol,
                               fi, ff, elements, rest, tangent, states,
                               retangent):  # fmt: skip
                ctrl[NEXT_H] = h_try  # StepRun factors it (or finds it singular)
                return REFACTOR, i, written
            counts[ROW_JACOBIANS] += 1
            counts[ROW_FACTORS] += 1
            ctrl[LU_H], ctrl[STALE], ctrl[H_USED] = h_try, 0.0, h_try
            ctrl[REFACTORED] += 1.0
            fresh, tried = True, stale and not retangent
            renewed = retangent or ctrl[STIFF] == 0.0
        params[0] = (1.0 - am) / (h_try * h_try * beta * (1.0 - af))
        params[1] = gamma / (h_try * beta)
        lam1 = own_lam.copy()
        status, it, _, eta, done = worked_newton(
            q1, qd1, qdd1, lam1, work, functions, refs, body, fi, ff, q_abs, a_ref, params, 0,
            math.inf, ctrl[ETA], own[2], own[3], true, h_try, states[0], states[2], states[1],
            elements,
        )  # fmt: skip
        if status != CONVERGED:  # a converged step hands its ~40 arguments to no call
            status, it, eta, done, renewed, tried = _refreshed(
                status, it, eta, done, renewed, tried, q1, qd1, qdd1, lam1, own, true, h_try,
                ctrl, counts, params, kind, ints, floats, work, functions, refs, body, prow,
                pcol, values, place, brow, bcol, fi, ff, q_abs, a_ref, elements, rest, tangent,
                states,
            )  # fmt: skip
        if status != CONVERGED:
            return _newton_stopped(ctrl, counts, renewed, done, h_try, status), i, written
        new_qdd = true[nq : 2 * nq]
        err = _step_error(ctrl, h_try, cons, new_qdd, q_abs, q1, states)
        if err > 1.0:  # rejected: the step shrunk as the Python stepper shrinks it
            if not _rejected(ctrl, counts, h_try, err, eta, it, tried, done):
                return STOPPED, i, written  # below the step floor: Python's stall
            continue
        if not _slipping(own[0], cons[0], q1, qd1, true[:nq], rates, slips, elements):
            return STOPPED, i, written  # a friction may stop: Python locates it, may hold it
        # the angles unwrapped at the new state (settle), which the step's rows read
        _unwrapped(q1, nq // 7, angles, refs_all, block_angles, new_refs, new_block)
        ends[0], ends[1], ends[2] = own[0], cons[0], cons[1]
        ends[3], ends[4], ends[5] = q1, true[:nq], new_qdd
        end_rates(q1, qd1, elements, states)
        # the contacts' memories first: the Python stepper settles a step before its rows
        saved = _committed(q1, qd1, t_new, elements, kept, taken, due)
        fresh_rows = _dense_rows(
            ends, t, t_new, outs[i : i + due], written, row_arrays, functions, new_block,
            new_refs, body, projection, rows_t, rows_state, rows_refs, elements, states,
        )  # fmt: skip
        if fresh_rows < 0:  # the Python stepper takes this step and its rows
            _uncommitted(elements, saved)
            return STOPPED, i, written
        # accepted (GeneralizedAlphaStepper._attempt, then settle)
        counts[ITERATIONS] += done
        counts[ROW_JACOBIANS] += fresh_rows
        counts[ROW_FACTORS] += fresh_rows + due
        _accept_control(ctrl, h_try, err, eta, it, tried)
        _take(own, own_lam, cons, cons_lam, q1, qd1, qdd1, lam1, true, a_ref)
        accept_states(h_try, states)
        steps_t[taken] = ctrl[T]
        ctrl[SPLIT] = 0.0
        counts[STEPS] += 1
        taken += 1
        refs_all[:] = new_refs
        refs[:] = new_block
        _after_step(rates, slips, elements, refs_all)
        written += due
        i += due


@njit(**KERNEL)
def _step_error(ctrl, h, cons, new_qdd, q_abs, q1, states):
    """The scaled local error of the step h (s) (gk.error_norm of the coordinates, then the
    element states': run_states.states_error); 0 along a grid (ctrl[GRID]: no error test)."""
    if ctrl[GRID] != 0.0:
        return 0.0
    err = gk.error_norm(ctrl[ERROR_CONSTANT] * h * h, cons[1], new_qdd, q_abs, ctrl[TOL], q1)
    return states_error(err, h, states, ctrl[TOL])


_STEP, _WRITTEN, _FULL, _NOT_FINITE = 0, 1, 2, 3  # what `_output_row` found


@njit(**KERNEL)
def _row_at(
    dense, i, written, t, ctrl, outs, own, cons, cons_lam, refs_all, rows_t, rows_state, rows_refs
):  # fmt: skip
    """What to do at t (s): dense output steps on until ctrl[REACH] (_FULL there, else
    _STEP); steps landing on the output times record a row there (`_output_row`)."""
    if dense:
        return _FULL if _reached(ctrl[REACH], t) else _STEP
    return _output_row(
        i, written, t, outs, own, cons, cons_lam, refs_all, rows_t, rows_state, rows_refs
    )


@njit(**KERNEL)
def _rejected(ctrl, counts, h_try, err, eta, iterations, tried, done):
    """A step h_try (s) whose error err exceeds 1, rejected as GeneralizedAlphaStepper.
    _attempt and _shrink reject it (the Newton rate carried on, a fresh matrix after slow
    convergence, the step shrunk by the error's law, counted); False, nothing changed,
    where the new step would fall below the run's floor (ctrl[H_MIN]: Python then fails
    the run)."""
    h, ceiling = rules.step_size(h_try, err, ctrl[H], ctrl[MAX_STEP], True, ctrl[CEILING])
    if h < ctrl[H_MIN]:
        return False
    ctrl[ETA] = rules.carried_rate(eta)
    _converged_in(ctrl, iterations, tried)
    ctrl[H], ctrl[H_USED], ctrl[CEILING] = h, h_try, ceiling
    counts[REJECTED] += 1
    counts[ITERATIONS] += done
    return True


@njit(**KERNEL)
def _output_row(i, written, t, outs, own, cons, cons_lam, refs_all, rows_t, rows_state, rows_refs):
    """Steps landing on the output times: at t (s) the state's row when t is outs[i] and
    there is room (_WRITTEN); _STEP where a step is to be taken towards outs[i]; _FULL when
    no output time or no row is left; _NOT_FINITE for a state Python must look at."""
    if i == outs.shape[0]:
        return _FULL
    if not _reached(outs[i], t):
        return _STEP
    if written == rows_t.shape[0]:
        return _FULL
    if not all_finite(own[0], cons[0], cons[1], cons_lam):
        return _NOT_FINITE
    _write_row(written, t, own[0], cons, cons_lam, refs_all, rows_t, rows_state, rows_refs)
    return _WRITTEN


@njit(**KERNEL)
def _rows_due(outs, i, t_new, dense):
    """How many output times from outs[i] lie within a dense step ending at t_new (s);
    none for a step landing on an output time (its row is recorded at its end)."""
    due = 0
    while (
        dense and i + due < outs.shape[0] and outs[i + due] - t_new <= 1e-12 * max(1.0, abs(t_new))
    ):
        due += 1
    return due


@njit(**KERNEL)
def _matrix_due(ctrl, h, fresh):
    """The step h (s) needs the iteration matrix factored anew (rules.refactors): not when
    it was factored for this step (`fresh`)."""
    return not fresh and (ctrl[STALE] != 0.0 or rules.refactors(h, ctrl[LU_H]))


@njit(**KERNEL)
def _limits(counts, ctrl, taken, most_steps):
    """-1 while a step may be taken; 0 after the call's `most_steps`; STOPPED at the
    analysis's step limit (Python's message)."""
    if taken == most_steps:
        return 0
    if counts[STEPS] + counts[REJECTED] >= ctrl[MAX_STEPS]:
        return STOPPED
    return -1


@njit(**KERNEL)
def _watched(counts, ctrl, t, h):
    """The step h (s) from t (s) is one the step-collapse watch must see
    (mechlib.solvers.runaway.StepCollapse.watch, in Python after each accepted step): with
    no window open, a step at whose pace the run would pass analysis.max_steps (the watch
    opens one); with a window open (ctrl[WATCH]), a step that may close it (COLLAPSE_STEPS
    from its start). Within a window the watch does nothing: the steps go on here."""
    taken = counts[STEPS] + counts[REJECTED]
    if ctrl[WATCH] < 0.0:
        return taken + (ctrl[END] - t) / h > ctrl[MAX_STEPS]
    return taken + 1 - ctrl[WATCH] >= COLLAPSE_STEPS


@njit(**KERNEL)
def _trial_step(t, interval, ctrl, dense, grid):
    """The step (s) from t towards a time `interval` s ahead: along the grid with
    ctrl[GRID], else with step size ctrl[H] (GeneralizedAlphaStepper.trial_step)."""
    if ctrl[GRID] != 0.0:
        return rules.on_grid(t, interval, grid[0], grid[1], ctrl[SPLIT] != 0.0)
    h = ctrl[H]
    return rules.towards(interval, h) if dense else rules.substep(interval, h)


@njit(**KERNEL)
def _new_size(ctrl, h):
    """The step h (s) is a new step size: the pseudo-acceleration restarts."""
    return ctrl[H_USED] != 0.0 and abs(h / ctrl[H_USED] - 1.0) > 1e-9


_SINGULAR = -1  # `_refreshed`: the iteration matrix is singular at Newton's iterate


@njit(**KERNEL)
def _refreshed(
    status, it, eta, done, renewed, tried, q1, qd1, qdd1, lam1, own, true, h, ctrl, counts,
    params, kind, ints, floats, work, functions, refs, body, prow, pcol, values, place, brow,
    bcol, fi, ff, q_abs, a_ref, elements, rest, tangent, states,
):  # fmt: skip
    """Newton stalled on the step h (s) with an iteration matrix made for an earlier step,
    or for this one with the differenced tangent kept (not `renewed`): refreshed at the
    iterate, its tangent anew, Newton goes on from there (Integrator._compiled_step), in
    this call. Returns (status, it, eta, done, renewed, tried) as they are after it (as
    given where Newton converged, the matrix was renewed, or the layout does not fit the
    factors: Python then takes the step); status _SINGULAR where the refreshed matrix is
    singular."""
    if status == CONVERGED or renewed or fi[0] != kind:
        return status, it, eta, done, renewed, tried
    if not _refactored(q1, qd1, lam1, h, ctrl, kind, ints, floats, functions, refs, body,
                       prow, pcol, values, place, brow, bcol, fi, ff, elements, rest,
                       tangent, states, True):  # fmt: skip
        return _SINGULAR, it, eta, done, renewed, tried
    counts[ROW_JACOBIANS] += 1
    counts[ROW_FACTORS] += 1
    ctrl[LU_H], ctrl[STALE], ctrl[H_USED] = h, 0.0, h
    ctrl[REFACTORED] += 1.0
    status, it, _, eta, more = worked_newton(
        q1, qd1, qdd1, lam1, work, functions, refs, body, fi, ff, q_abs, a_ref, params, 0,
        math.inf, eta, own[2], own[3], true, h, states[0], states[2], states[1], elements,
    )  # fmt: skip
    return status, it, eta, done + more, True, False


@njit(**KERNEL)
def _newton_stopped(ctrl, counts, renewed, done, h, status):
    """Newton stopped on the step h (s): on a matrix not `renewed` STOPPED (Python
    refreshes it, as it would: where the kernel cannot, `_refreshed`); on a renewed one
    FAILED (the step fails), its iterations counted; REFACTOR where the refreshed matrix is singular
    (StepRun factors one for the step in Python, or fails it)."""
    if status == _SINGULAR:
        ctrl[NEXT_H] = h
        return REFACTOR
    if not renewed:
        return STOPPED
    counts[ITERATIONS] += done
    ctrl[NEXT_H] = h
    return FAILED


@njit(**KERNEL)
def _unwrapped(q1, nb, angles, refs_all, block_angles, new_refs, new_block):
    """The angle measures' references at q1 (nb rigid bodies first in it: `new_refs`, from
    `refs_all`), and those of the constraint rows' angles among them (`new_block`)."""
    ai, aj, au, av = angles
    x, _ = ca.state_arrays(q1, q1, nb)
    new_refs[:] = refs_all
    ca.angle_values(x, ai, aj, au, av, new_refs)
    for j in range(block_angles.shape[0]):
        new_block[j] = new_refs[block_angles[j]]


@njit(**KERNEL)
def _converged_in(ctrl, iterations, tried):
    """A step converged in `iterations` on a matrix refactored for the last step's slowness
    with the tangent kept (`tried`) or not: after slow convergence the next matrix is
    stale, its tangent new as rules.retangents says (Integrator.converged_in; the whole
    runs serve rigid systems, which keep their tangent first: rules.keeps_tangent)."""
    slow = rules.slow(iterations)
    ctrl[STALE] = 1.0 if slow else 0.0
    ctrl[RETANGENT] = 1.0 if slow and rules.retangents(tried) else 0.0


@njit(**KERNEL)
def _accept_control(ctrl, h_try, err, eta, iterations, tried):
    """The control after an accepted step h_try (s) with error err on a matrix `tried`
    (`_converged_in`): the Newton rate carried on, a fresh matrix after slow convergence,
    the next step size (rules), the time."""
    ctrl[ETA] = rules.carried_rate(eta)
    _converged_in(ctrl, iterations, tried)
    ctrl[H], ctrl[CEILING] = rules.step_size(
        h_try, err, ctrl[H], ctrl[MAX_STEP], True, ctrl[CEILING]
    )
    ctrl[H_USED] = h_try
    ctrl[T] += h_try


@njit(**KERNEL)
def _write_row(k, t, q, cons, cons_lam, refs_all, rows_t, rows_state, rows_refs):
    """Row k: time t (s), the state (q, the consistent qd, qdd, lam) and the references."""
    nq = q.shape[0]
    rows_t[k] = t
    rows_state[k, :nq] = q
    rows_state[k, nq : 2 * nq] = cons[0]
    rows_state[k, 2 * nq : 3 * nq] = cons[1]
    rows_state[k, 3 * nq :] = cons_lam
    rows_refs[k] = refs_all


@njit(**KERNEL)
def _dense_rows(
    ends, t, t_new, times, first, work, functions, block_refs, refs, body, projection,
    rows_t, rows_state, rows_refs, elements, states,
):  # fmt: skip
    """The rows at `times` within the step t -> t_new (s), projected from the step's `ends`
    (mechlib.solvers.dense_compiled, with the packed `elements` at the rows' element
    states, interpolated into `states`' rows: run_states.interpolate_states, cubic Hermite
    from both ends' values and rates) into rows
    first, first + 1, ...: the fresh Jacobians they took, or -1 where a row is given back
    to Python. `work`: dense_compiled.row_work's arrays, made once for the call's steps."""
    span = t_new - t
    fresh_rows = 0
    for k in range(times.shape[0]):
        t_row = times[k]
        at_end = abs(t_row - t_new) <= 1e-12 * max(1.0, abs(t_row))
        w = (t_row - t) / span
        s = 1.0 if at_end else w
        z = interpolate_states(states, span, w, first + k)
        status, fresh = project_worked_row(
            ends, span, s, work, functions, block_refs, body, projection, z, elements,
            rows_state[first + k],
        )  # fmt: skip
        if status != DONE:
            return -1
        fresh_rows += fresh
        rows_t[first + k] = t_row
        rows_refs[first + k] = refs
    return fresh_rows


@njit(**KERNEL)
def _refactored(
    q1, qd1, lam, h, ctrl, kind, ints, floats, functions, refs, body, prow, pcol, values, place,
    brow, bcol, fi, ff, elements, rest, tangent, states, retangent,
):  # fmt: skip
    """The iteration matrix [[M + (gamma' C + K) / beta', phi_q^T], [phi_q, 0]] of the step
    h (s) at (q1, qd1) refactored in place into (fi, ff) when the pattern's layout fits them
    (`kind`); K, C the packed elements' tangent (mechlib.elements.compiled_forces; none
    without elements): the differenced tangent of `rest` (the elements but the contacts,
    over their columns), kept in `tangent` and differenced anew, as the Python path does,
    only where asked (`retangent`: after a stall, or a slow step as rules.retangents says)
    or none is kept yet, with the element `states`' trial values advanced at (q1, qd1)
    first (Integrator._compiled_step); plus the contacts' own tangent at (q1, qd1) each
    time (Integrator._iteration_matrix). False where the layout does not fit, or the
    kernel finds the matrix singular (StepRun then factors it in Python)."""
    if fi[0] != kind:
        return False
    nq = q1.shape[0]
    x, _ = ca.state_arrays(q1, q1, nq // 7)
    saddle_values(x, ints, floats, functions, refs, body, prow, pcol, values)
    rest_elements, columns = rest
    contacts = elements[12].shape[0] > 0
    if columns.shape[0] or contacts:
        if retangent or math.isnan(tangent[0, 0, 0]):
            _differenced(q1, qd1, lam, h, ints, floats, functions, refs, body, rest_elements,
                         columns, tangent, states)  # fmt: skip
        am, af, beta = ctrl[ALPHA_M], ctrl[ALPHA_F], ctrl[BETA]
        bp = (1.0 - am) / (h * h * beta * (1.0 - af))
        gp = ctrl[GAMMA] / (h * beta)
        stiffness, damping = _with_contacts(q1, qd1, elements, tangent)
        for e in range(prow.shape[0]):
            r, c = prow[e], pcol[e]
            if r < nq and c < nq:
                values[e] += (gp * damping[r, c] + stiffness[r, c]) / bp
    return refactor(values, place, brow, bcol, fi, ff)


@njit(**KERNEL)
def _committed(q1, qd1, t, elements, kept, step, due):
    """The accepted state (q1, qd1 raw) at t (s) committed into the packed contacts
    (contact_group.commit_contacts, Contact.commit's rule), the step's approach speeds
    kept in row `step` of `kept`. Returns what a step with rows (`due`) may have to undo
    (`_uncommitted`): the approach speeds, memories and anchors before."""
    ints, moving, anchor, memory = elements[12], elements[16], elements[17], elements[18]
    n = ints.shape[0] if due else 0
    saved = (moving[:n, 0].copy(), memory[:n].copy(), anchor[:n].copy())
    if ints.shape[0]:
        x, xd = ca.state_arrays(q1, qd1, q1.shape[0] // 7)
        commit_contacts(x, xd, t, ints, elements[13], moving, anchor, memory, kept, step)
    return saved


@njit(**KERNEL)
def _uncommitted(elements, saved):
    """The contacts' memories as `_committed` found them (its step given back)."""
    approaches, memories, anchors = saved
    n = approaches.shape[0]
    elements[16][:n, 0] = approaches
    elements[18][:n] = memories
    elements[17][:n] = anchors


@njit(**KERNEL)
def _with_contacts(q1, qd1, elements, tangent):
    """(K, C): the kept differenced tangent, plus the packed contacts' own at (q1, qd1)
    (copies then) as Integrator._iteration_matrix adds them."""
    if not elements[12].shape[0]:
        return tangent[0], tangent[1]
    stiffness, damping = tangent[0].copy(), tangent[1].copy()
    nb = q1.shape[0] // 7
    x, xd = ca.state_arrays(q1, qd1, nb)
    contacts_tangent(x, xd, elements[12], elements[13], elements[14], elements[15], elements[16],
                     nb, stiffness, damping)  # fmt: skip
    return stiffness, damping


@njit(**KERNEL)
def _differenced(
    q1, qd1, lam, h, ints, floats, functions, refs, body, elements, columns, tangent, states
):  # fmt: skip
    """tangent = (K, C) of the packed elements at (q1, qd1) with multipliers `lam`
    (mechlib.elements.compiled_forces.element_tangent, over `columns`; zero without any),
    their element states (`states`) advanced over the step h (s) at (q1, qd1) and anew at
    each moved state."""
    nq = q1.shape[0]
    if not columns.shape[0]:  # every column inert (mechlib.system.fd_columns.ColumnSkips)
        tangent[:] = 0.0
        return
    nb = nq // 7
    _, masses, _, inertia = ca.body_terms(body, nb)
    x, xd = ca.state_arrays(q1, qd1, nb)
    nall = ca.row_count(ints)
    full, rows = np.empty(nall), np.zeros((nall, nq + 7))
    active, _ = ca.constraint_rows(x, ints, floats, functions, refs, full, rows)
    z0, trial, f0 = states[0], states[1], states[2]
    if trial.shape[0]:
        advance_states(x, xd, z0, f0, h, elements, trial)
    moved = (z0, f0, h, np.empty(trial.shape[0]))
    element_tangent(q1, qd1, trial, elements, columns, masses, inertia, rows, active, lam,
                    tangent[0], tangent[1], moved)  # fmt: skip


@njit(**KERNEL)
def _slipping(q0, qd0, q1, qd1, qd1_true, rates, slips, elements):
    """Every packed friction slides on through the step (q0, qd0) -> (q1, qd1 raw,
    qd1_true consistent) (mechlib.elements.compiled_forces.slipping_on, against the rate of
    the last accepted state too): nothing for mechlib.solvers.stick to locate or hold.
    `slips` (out): the raw slip rates at the step's end."""
    if not slips.shape[0]:
        return True
    before, after = np.empty(slips.shape[0]), np.empty(slips.shape[0])
    slip_rates(q0, qd0, elements, before)
    slip_rates(q1, qd1_true, elements, after)
    if not slipping_on(before, after, elements):
        return False
    slip_rates(q1, qd1, elements, slips)
    return slipping_on(rates[:, 1], slips, elements) and slipping_on(after, slips, elements)


@njit(**KERNEL)
def _after_step(rates, slips, elements, refs_all):
    """An accepted step: the frictions' slip rates (raw, as JointFriction.commit keeps
    them: `slips`, found by `_slipping`) shifted into `rates`, their impending directions
    cleared (they slide above v_threshold), the angle elements' references unwrapped."""
    varying = elements[7]
    for i in range(slips.shape[0]):
        rates[i, 0], rates[i, 1] = rates[i, 1], slips[i]
        varying[i, 3] = 0.0
    if any_elements(elements):
        update_references(elements, refs_all)


@njit(**KERNEL)
def _take(own, own_lam, cons, cons_lam, q1, qd1, qdd1, lam1, true, a_ref):
    """The accepted step's state becomes the one to go on from: the integrator's own (q,
    qd, qdd, a, lam) and the consistent (qd, qdd, lam); the acceleration scales raised."""
    nq, m = own.shape[1], own_lam.shape[0]
    own[0], own[1], own[2] = q1, qd1, qdd1
    own[3] = true[2 * nq + m :]
    own_lam[:] = lam1
    cons[0], cons[1] = true[:nq], true[nq : 2 * nq]
    cons_lam[:] = true[2 * nq : 2 * nq + m]
    for j in range(nq):
        a_ref[j] = max(a_ref[j], abs(cons[1][j]))


@njit(**KERNEL)
def _carried(h, ctrl, own, cons):
    """At a new step size h (s) the integrator's velocity own[1] and pseudo-acceleration
    own[3] carried to it from the consistent velocity cons[0] and the integrator's
    acceleration own[2] (rules.carried), noted in ctrl."""
    if not _new_size(ctrl, h):
        return
    own[1], own[3] = rules.carried(cons[0], own[1], own[2], own[3], h / ctrl[H_USED])
    ctrl[H_USED], ctrl[RESTARTED] = h, 1.0


class StepRun:
    """`run_steps` for a generalized-alpha stepper in `march`: whether the system allows it
    now, the stepper's state in and out, the rows recorded."""

    MOST_CALLS = 1024  # kernel calls of one `run` (a chunk of rows or a factorisation each)

    def __init__(self, stepper):
        self.stepper = stepper
        system = stepper.system
        # system.angle_measures' order: the angle measures in the order of system.measures
        self.angle_keys = [k for k, m in system.measures.items() if isinstance(m, AngleMeasure)]
        self._angle_args: tuple | None = None
        self._block: tuple | None = None  # (coordinate block, its angles' indices)
        self._patterns: dict[tuple, object] = {}  # the coupled saddle patterns, by columns
        # the elements' tangent (K, C) the calls keep, and the Python stepper's tangent it
        # was made beside (a new one there: this one is made anew too)
        self._tangent: tuple[np.ndarray, object, object] | None = None
        self.elements: CompiledForces | None = None  # packed for the run (`_ready`)
        self.states = RunStates(system)  # the element states, in and out of each call
        # the rows of each call (mechlib.solvers.genalpha.call_rows), fewer where a
        # companion follows the run's steps beside it
        self._feed = getattr(stepper.spec, "feed", None)
        self.calls = CallRows(FED_ROWS, FED_SECONDS) if self._feed else CallRows()
        # the matrix `_refactor` made was refactored for slowness with the tangent kept; it
        # took a new differenced tangent (or the system has none)
        self._tried = self._renewed = False
        self._grid = _NO_GRID  # the step ends the steps follow and their middles (`_grid_at`)
        self._grid_of: object = None  # the grid's ends it was stacked from

    @staticmethod
    def eligible(stepper) -> bool:
        """A stepper whose runs may be compiled at all (more is checked at each run)."""
        return (
            not stepper.spec.fixed_step
            and stepper.integ.arrays is not None
            and RunStates.servable(stepper.system)
        )

    def _ready(self, t: float) -> bool:
        """Whether a run may start at t (s) now; the elements packed, their values
        refreshed (the actuators' held demands)."""
        system = self.stepper.system
        if self.stepper.integ.lu is None:
            return False
        self.elements = self.stepper.integ.elements(t)
        if self.elements is None or not contact_group.runnable(self.elements.contacts):
            # an element with no compiled form, or a stuck friction; a contact without its
            # own tangent, or whose commit would move an impact law's ramp
            return False
        if self.stepper.dense and not (small_enough(system) and not self.elements.frictions):
            # its rows' dense Schur complement would cost more than Python's; the compiled
            # rows' projection knows no joint friction (its load reads the reactions)
            return False
        block = system.coordinate_rows()  # no function of time (a hold's value is constant)
        functions = (block.equations[i].function for i in block.linear)
        return all(f is None or getattr(f, "constant", False) for f in functions)

    def run(self, s, outputs: np.ndarray, i: int, trajectory, progress) -> tuple:
        """From state s, the steps and rows towards outputs[i:] that `run_steps` takes,
        the iteration matrices it asks for factored here as the Python step factors them
        (at the step's predicted state); returns (the state reached, the index of the next
        output time)."""
        if not self._ready(s.t):
            return s, i
        fresh, calls = False, 0
        while calls < self.MOST_CALLS:
            end = self._grid_at(s.t)
            s, i, status, h_next, fresh = self._call(
                s, outputs, i, trajectory, progress, fresh, end
            )
            # a call that reached the end of a grid still growing waits for more, uncounted
            calls += status != 0 or end == self.stepper.spec.end or not _reached(end, s.t)
            if status == FAILED:
                self._fail(s, h_next)
                return s, i
            if status == REFACTOR:
                fresh = self._refactor(s, h_next)
                if not fresh:
                    return s, i
            elif status == STOPPED or i == len(outputs):  # else a chunk done: the next
                return s, i
        return s, i

    def _grid_at(self, t: float) -> float:
        """How far (s) a call from t (s) may step: the analysis's end, or the last end of a
        grid made as its run is solved (mechlib.model.step_feed), whose arrays it then
        takes (waiting for an end after t)."""
        grid, end = self.stepper.grid, self.stepper.spec.end
        if grid is None:
            return end
        ends, middles, reach = grid.covering(t)
        if self._grid_of is not ends:
            self._grid, self._grid_of = np.stack([ends, middles]), ends
        return min(end, reach)

    def _refactor(self, s, h: float) -> bool:
        """The iteration matrix of the step h (s) from s factored at its predicted state
        (GeneralizedAlphaStepper._attempt, Integrator._compiled_step); False when it is
        singular (the step then fails as there)."""
        stepper, system = self.stepper, self.stepper.system
        integ = stepper.integ
        stepper.h_used = h
        _, _, q1, qd1, _, lam1, t1, fresh = integ._predicted(
            s.t, h, s.q, s.raw_qd, s.raw_qdd, s.a, s.raw_lam, s.qdd
        )
        self._tried = integ.refactor and not fresh  # as Integrator._compiled_step's
        self._renewed = fresh or not integ.stiff
        k = system.kin(q1, qd1, t1)
        if system.states:  # the tangent's base at the iterate's states, as in `step`
            system.states.advance(system.view(k), h)
        try:
            integ._iteration_matrix(k, h, fresh, lam1)
        except SolverFailure as failure:  # singular here: the step fails, a smaller one next
            integ.singular = failure
            self._fail(s, h)
            return False
        return True

    def _fail(self, s, h: float) -> None:
        """The step h (s) from s failed with a new iteration matrix: as the Python stepper
        (Integrator.step returning None, then GeneralizedAlphaStepper._attempt) -- the
        matrix dropped, the step rejected, the next a quarter as long (below the step
        floor: the stall's SolverFailure)."""
        stepper = self.stepper
        stepper.integ.drop()
        stepper.h_used = h
        stepper.newton_failed(s, h)

    def _call(
        self, s, outputs: np.ndarray, i: int, trajectory, progress, fresh: bool, end: float
    ) -> tuple:
        """One `run_steps` call from s (`fresh`: the matrix was factored for its first
        step) towards `end` (s): (the state reached, the next output index, the status,
        ctrl[NEXT_H], whether the matrix is still new for the next step: the call ended
        before taking it)."""
        stepper, system = self.stepper, self.stepper.system
        integ, stats, spec = stepper.integ, stepper.stats, stepper.spec
        arrays, scales, c = integ.arrays, integ.scales, integ.c
        nq = system.nq
        own = np.stack([s.q, s.raw_qd, s.raw_qdd, s.a])
        own_lam = np.array(s.raw_lam, dtype=float)
        cons = np.stack([s.qd, s.qdd])
        cons_lam = np.array(s.lam, dtype=float)
        ctrl = np.empty(CTRL_SIZE)
        ctrl[[T, H, H_USED, LU_H, ETA, STALE, FRESH]] = (
            s.t,
            stepper.h,
            stepper.h_used,
            integ.lu_h,
            integ.eta,
            float(integ.stale),
            float(fresh),
        )
        ctrl[[MAX_STEP, END, MAX_STEPS, TOL, ERROR_CONSTANT]] = (
            stepper.max_step,
            spec.end,
            spec.max_steps,
            scales.tol,
            c.error_constant,
        )
        ctrl[[ALPHA_M, ALPHA_F, BETA, GAMMA]] = c.alpha_m, c.alpha_f, c.beta, c.gamma
        ctrl[DENSE] = float(stepper.dense)
        ctrl[H_MIN] = stepper.h_min
        ctrl[REACH] = end
        ctrl[CEILING] = stepper.ceiling
        ctrl[GRID], ctrl[SPLIT] = float(stepper.grid is not None), float(stepper.split)
        ctrl[RETANGENT], ctrl[TRIED] = float(integ.retangent), float(fresh and self._tried)
        ctrl[RENEWED], ctrl[STIFF] = float(fresh and self._renewed), float(integ.stiff)
        window = stepper.collapse.since
        ctrl[WATCH] = -1.0 if window is None else float(window.taken)
        ctrl[REFACTORED] = ctrl[RESTARTED] = 0.0
        counts = np.array([stats.steps, stats.rejected_steps, 0, 0, 0], dtype=np.int64)
        ints, floats = arrays.packed()
        fi, ff, layout = self._factors()
        if self._angle_args is None:
            self._angle_args = ca.measure_args([m.sine_cosine for m in system.angle_measures], 4)
        refs_all = np.array([m.reference for m in system.angle_measures], dtype=float)
        block_angles = self._block_angles(system.coordinate_rows())
        rows = min(self.calls.rows(3 * nq + own_lam.size), len(outputs) - i)
        rows_t, rows_refs = np.empty(rows), np.empty((rows, len(refs_all)))
        rows_state = np.empty((rows, 3 * nq + own_lam.size))
        steps_t = np.empty(10 * rows)  # the accepted steps' end times
        elements = self.elements
        assert elements is not None, "packed by _ready"
        rates = elements.start_rates()
        states = self.states.pack(scales.z_abs, rows)
        kept = contact_group.history(10 * rows, len(elements.contacts))
        status, i_next, written = run_steps(
            own, own_lam, cons, cons_lam, ctrl, counts, outputs, i, ints, floats,
            arrays.functions(s.t), arrays.bodies(), fi, ff, layout, scales.q_abs, scales.a_ref,
            self._angle_args, refs_all, block_angles, PROJECTION, rows_t, rows_state, rows_refs,
            10 * rows, elements.args, (elements.rest, elements.rest_columns), rates, states,
            self._kept_tangent(nq), kept, self._grid, steps_t,
        )  # fmt: skip
        self.calls.done(written)
        count(
            factorizations=int(counts[ROW_FACTORS]), jacobian_evaluations=int(counts[ROW_JACOBIANS])
        )
        if ctrl[REFACTORED]:  # as StepRun._refactor leaves them
            integ.adopt(fi, ff, float(ctrl[LU_H]))
            integ.stale, stepper.h_used = bool(ctrl[STALE]), float(ctrl[H_USED])
            integ.retangent = bool(ctrl[RETANGENT])
        taken = int(counts[STEPS]) - stats.steps
        rejected = int(counts[REJECTED]) - stats.rejected_steps
        elements.read_back(rates, taken, kept)
        self.states.unpack(states, taken > 0)
        stats.steps, stats.rejected_steps = int(counts[STEPS]), int(counts[REJECTED])
        if self._feed is not None:  # counted before the ends are handed on
            self._feed.compiled_steps += taken
            if not self._feed.followed:
                self.calls.relax()
        stats.step_ends.extend(steps_t[:taken].tolist())
        stepper.split = bool(ctrl[SPLIT])
        stats.newton_iterations += int(counts[ITERATIONS])
        for m, value in zip(system.angle_measures, refs_all):
            m.reference = float(value)
        if taken or rejected or ctrl[RESTARTED]:  # moved, shrunk, or carried to a new h
            stepper.h, stepper.h_used = float(ctrl[H]), float(ctrl[H_USED])
            stepper.ceiling = float(ctrl[CEILING])
            integ.eta, integ.stale = float(ctrl[ETA]), bool(ctrl[STALE])
            integ.retangent = bool(ctrl[RETANGENT])
            s = type(s)(
                float(ctrl[T]), own[0], cons[0], cons[1], cons_lam,
                raw_qd=own[1], raw_qdd=own[2], a=own[3], raw_lam=own_lam,
            )  # fmt: skip
        self._record(
            trajectory, rows_t[:written], rows_state[:written], rows_refs[:written],
            states[-1][:written] if system.states else None,
        )  # fmt: skip
        if written and progress:
            progress(float(rows_t[written - 1]), spec.end)
        return s, i_next, status, float(ctrl[NEXT_H]), bool(ctrl[FRESH])

    def _kept_tangent(self, nq: int) -> np.ndarray:
        """The elements' tangent (2, nq, nq) the calls share: NaN (made at the next
        refactor) at first, after the Python stepper made a tangent of its own, and for
        elements packed anew."""
        made, packed = self.stepper.integ.tangent, self.elements
        kept = self._tangent
        if kept is None or kept[1] is not made or kept[2] is not packed:
            self._tangent = kept = (np.full((2, nq, nq), np.nan), made, packed)
        return kept[0]

    def _factors(self) -> tuple[np.ndarray, np.ndarray, tuple]:
        """The iteration matrix's flat factors for the call (copies where the kernel may
        refactor in them: the stepper's own stay as they are until the call returns) and
        the saddle pattern's layout for `run_steps` (kind -1 where it does not fit them)."""
        fi, ff = self.stepper.integ._factor_data()
        pattern = self._pattern()
        layout = pattern.layout
        if fi[0] == SUPERLU or layout is None or layout.ints[0] != fi[0] or len(ff) != layout.size:
            return fi, ff, (-1, *self._NO_LAYOUT)
        return fi.copy(), ff.copy(), (fi[0], pattern.rows, pattern.cols, *layout.kernel_args())

    def _pattern(self):
        """The saddle pattern of the iteration matrix: the system's, with the blocks the
        elements' tangent couples (their `columns`) added (found once per columns)."""
        system = self.stepper.system
        coupled = np.zeros(0, np.int64) if self.elements is None else self.elements.columns
        if not coupled.size:
            return system.saddle_pattern()
        key = tuple(coupled)
        if key not in self._patterns:
            self._patterns[key] = coupled_pattern(system, coupled)
        return self._patterns[key]

    _NO_LAYOUT = tuple(np.zeros(0, dtype=np.int64) for _ in range(5))

    def _block_angles(self, block) -> np.ndarray:
        """The indices of the constraint rows' angle measures among all of the system's
        (found again only when an event changes the coordinate block)."""
        if self._block is None or self._block[0] is not block:
            position = {id(m): j for j, m in enumerate(self.stepper.system.angle_measures)}
            found = np.array([position[id(m)] for m in block.angles], dtype=np.int64)
            self._block = (block, found)
        return self._block[1]

    def _record(self, trajectory, times, states, refs, element_states=None) -> None:
        """The rows (found finite by the kernel), each with the system's snapshot, its own
        angle references and element states (made into a dict when read:
        mechlib.model.analysis.Snapshots)."""
        if not len(times):
            return
        system = self.stepper.system
        trajectory.extend(
            times, states, system.nq, system.snapshot(), self.angle_keys, refs, element_states
        )
