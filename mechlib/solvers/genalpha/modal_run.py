"""Runs of generalized-alpha steps in one compiled call for systems with modal bodies and no
force elements (mechlib.flexible.packed.modal_arrays), with steps landing on the output
times: what mechlib.solvers.genalpha.run does for rigid systems.

`run_modal` takes the steps `GeneralizedAlphaStepper.step`, `settle` and
mechlib.solvers.genalpha.modal_step take, one after another without returning to Python: the
step size from the error estimate (the run's helpers, rules.step_size), the predictor, the
iteration matrix [[M + (K + gamma' C) / beta', phi_q^T], [phi_q, 0]] factored at the
predicted state when the last step was slow or the step size moved (rules.refactors) and
at the iterate after a stall on an older matrix (rules.restalled: KEPT), with the
differenced tangent (K, C) kept, the Newton iterations (modal_newton), the error
estimate, the acceleration scales, the angles' unwrapping and the rows at the output
times. The motions' functions of time are read at each attempt's end through
mechlib.kinematics.time_functions. It stops, the state where it was (but for the
velocity and pseudo-acceleration carried to a new step size, as `run_steps` does), before
a step that needs what only the Python step does: a new differenced tangent (after a failed step, a
slow step on a matrix already refactored for slowness: rules.retangents, or a stall on a
matrix factored in the step: rules.restalled FRESH), a matrix the kernel finds singular,
a step below the floor, the step limit or a collapsing step size, a non-finite row.
`march` then takes that step in Python and calls it again: the same steps, iterations and
results as the Python-stepped path to round-off (tests/mechlib/test_modal_run.py).
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.core.work import count
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics.time_functions import NO_CALL, calling, functions_at
from mechlib.solvers.genalpha import kernels as gk
from mechlib.solvers.genalpha import rules
from mechlib.solvers.genalpha import run as rr
from mechlib.solvers.genalpha.modal_matrix import factored
from mechlib.solvers.genalpha.modal_newton import CONVERGED, modal_newton, row_arrays

__all__ = ["ModalRun", "run_modal"]

RETANGENT = rr.RETANGENT  # ctrl slot (in/out): a slow step asks for a new tangent
CTRL_SIZE = rr.CTRL_SIZE


@njit(**KERNEL)
def _solved(
    q1, qd1, qdd1, lam1, h, ctrl, counts, system, tangent, factors, scales, start, true, lent
):  # fmt: skip
    """Newton on the step h (s) from its predicted (q1, qd1, qdd1, lam1), in place, as
    modal_step iterates it: the matrix refactored at the start when stale or off the step
    size, at the iterate after a stall on a matrix not factored in the step (with the
    tangent kept). `factors`: the committed (fi, ff) and a working pair; `scales`: (q_abs,
    a_ref); `start`: the step's start (qdd, a); `lent`: modal_newton.row_arrays' (the
    factorisation's rows for Newton's first residual). Returns (converged, the last factors used
    are the working pair, iterations of the last matrix, eta, iterations done, tried: the
    matrix was refactored for slowness with the tangent kept); not converged: a new
    tangent or a singular matrix is Python's to make (nothing changed)."""
    fi, ff, wi, wf = factors
    stale = ctrl[rr.STALE] != 0.0
    rebuild = stale or rules.refactors(h, ctrl[rr.LU_H])
    rebuilt, tried, working = rebuild, stale, False
    ints, floats, functions, refs, body, bodies, welds, active = system
    params = np.empty(5)
    am, af, beta = ctrl[rr.ALPHA_M], ctrl[rr.ALPHA_F], ctrl[rr.BETA]
    params[0] = (1.0 - am) / (h * h * beta * (1.0 - af))
    params[1] = ctrl[rr.GAMMA] / (h * beta)
    params[2], params[3], params[4] = ctrl[rr.TOL], am, af
    prev, it, eta, done = math.inf, 0, ctrl[rr.ETA], 0
    while True:
        if rebuild:
            if not factored(q1, params[0], params[1], system, tangent, wi, wf, lent):
                return False, working, it, eta, done, tried
            working, rebuild, prev = True, False, math.inf
            counts[rr.ROW_JACOBIANS] += 1
            counts[rr.ROW_FACTORS] += 1
        gi, gf = (wi, wf) if working else (fi, ff)
        status, it, prev, eta, more = modal_newton(
            q1, qd1, qdd1, lam1, ints, floats, functions, refs, body, bodies, welds, active,
            gi, gf, scales[0], scales[1], params, it, prev, eta, start[0], start[1], true, lent,
        )  # fmt: skip
        done += more
        if status == CONVERGED:
            return True, working, it, eta, done, tried
        if rules.restalled(False, rebuilt, True) != rules.KEPT:
            return False, working, it, eta, done, tried
        rebuild = rebuilt = tried = True
        it = 0


@njit(**KERNEL)
def _settled(ctrl, factors, working, h):
    """A step h (s) that converged: the working factors committed (made for h; the next
    step's matrix stale after slow convergence and its tangent new as rules.retangents
    says: run._converged_in, called by run._rejected and run._accept_control)."""
    if working:
        fi, ff, wi, wf = factors
        fi[:] = wi
        ff[:] = wf
        ctrl[rr.LU_H] = h
        ctrl[rr.REFACTORED] += 1.0


@njit(**KERNEL)
def run_modal(
    own, own_lam, cons, cons_lam, ctrl, counts, outs, first, system, handle, tangent, factors,
    scales, angles, refs_all, block_angles, rows_t, rows_state, rows_refs, most_steps, past,
):  # fmt: skip
    """Accepted steps from the state (`own` (4, nq): q, qd, qdd, a of the integrator,
    `own_lam` its multipliers; `cons` (2, nq): the consistent qd, qdd, `cons_lam` the
    consistent multipliers), in place, recording the rows at the output times outs[first:]
    (rows_t, rows_state: q, qd, qdd, lam stacked, rows_refs: the angles' references), at
    most len(rows_t) rows and `most_steps` steps. `system`: (ints, floats, functions,
    refs, body, bodies, welds, active) as modal_step passes them, `functions` filled at
    each attempt's end by `handle` (mechlib.kinematics.time_functions), `refs` the
    constraint rows' angles' references (`block_angles`: their indices among all,
    `refs_all`, in place, `angles` their args). `tangent`: the kept (K, C); `factors`:
    the committed flat LU (fi, ff, in place) and a working pair of their size; `scales`:
    (q_abs, a_ref (in place)). ctrl: mechlib.solvers.genalpha.run's slots and RETANGENT.
    `past`: the predictor's memory (the Integrator's past_t, past: kernels.predict_swing),
    in place. Returns (0, STOPPED; next output index, rows written)."""
    nq = own.shape[1]
    nb = system[0][0]
    refs = system[3]
    new_refs, new_block = refs_all.copy(), refs.copy()
    true = np.empty(3 * nq + own_lam.shape[0])
    lent = row_arrays(nq, system[0], system[1], system[6])  # the factorisation's rows
    i, written, taken = first, 0, 0
    while True:
        t = ctrl[rr.T]
        row = rr._output_row(
            i, written, t, outs, own, cons, cons_lam, refs_all, rows_t, rows_state, rows_refs
        )  # fmt: skip
        if row == rr._WRITTEN:
            written += 1
            i += 1
            continue
        if row != rr._STEP:  # done (0), or a row Python must look at
            return rr.STOPPED * (row != rr._FULL), i, written
        limit = rr._limits(counts, ctrl, taken, most_steps)
        if limit >= 0:
            return limit, i, written
        if ctrl[rr.STALE] != 0.0 and ctrl[RETANGENT] != 0.0:
            return rr.STOPPED, i, written  # a new differenced tangent: Python's step
        h = rr._trial_step(t, outs[i] - t, ctrl, False, rr._NO_GRID)  # no grid: ctrl[GRID] 0
        rr._carried(h, ctrl, own, cons)  # GeneralizedAlphaStepper._attempt
        if rr._watched(counts, ctrl, t, h):
            return rr.STOPPED, i, written  # the step-collapse watch
        functions_at(handle, t + h, system[2])
        if not np.isfinite(system[2]).all():
            return rr.STOPPED, i, written  # a function failed there: Python's step says why
        am, af, beta, gamma = ctrl[rr.ALPHA_M], ctrl[rr.ALPHA_F], ctrl[rr.BETA], ctrl[rr.GAMMA]
        q1, qd1, qdd1 = gk.predict_swing(
            own[0], own[1], own[2], own[3], cons[1], t, h, past[0], past[1], am, af, beta, gamma
        )  # fmt: skip
        lam1 = own_lam.copy()
        ok, working, it, eta, done, tried = _solved(
            q1, qd1, qdd1, lam1, h, ctrl, counts, system, tangent, factors, scales,
            (own[2], own[3]), true, lent,
        )  # fmt: skip
        if not ok:
            return rr.STOPPED, i, written  # Python takes the step from its start
        err = gk.error_norm(
            ctrl[rr.ERROR_CONSTANT] * h * h, cons[1], true[nq : 2 * nq], scales[0], ctrl[rr.TOL], q1
        )  # fmt: skip
        if err > 1.0:  # rejected: the step shrunk as the Python stepper shrinks it
            if not rr._rejected(ctrl, counts, h, err, eta, it, tried, done):
                return rr.STOPPED, i, written  # below the step floor: Python's stall
            _settled(ctrl, factors, working, h)
            continue
        rr._unwrapped(q1, nb, angles, refs_all, block_angles, new_refs, new_block)
        counts[rr.ITERATIONS] += done
        rr._accept_control(ctrl, h, err, eta, it, tried)
        _settled(ctrl, factors, working, h)
        rr._take(own, own_lam, cons, cons_lam, q1, qd1, qdd1, lam1, true, scales[1])
        counts[rr.STEPS] += 1
        taken += 1
        refs_all[:] = new_refs
        refs[:] = new_block


class ModalRun(rr.StepRun):
    """`run_modal` for a generalized-alpha stepper of a system with modal bodies in `march`
    (the rows, angles and counters as `StepRun` keeps them)."""

    @staticmethod
    def eligible(stepper) -> bool:
        """A stepper whose runs may be compiled: steps landing on the output times, the
        system served by modal_step (modal bodies, no force elements)."""
        return not stepper.spec.fixed_step and not stepper.dense and stepper.integ.modal is not None

    def _ready(self, t: float) -> bool:
        """A matrix and a differenced tangent to go on with (else Python's step makes them)."""
        integ = self.stepper.integ
        return integ.lu is not None and integ.tangent is not None

    def run(self, s, outputs: np.ndarray, i: int, trajectory, progress) -> tuple:
        """From state s, the steps and rows towards outputs[i:] that `run_modal` takes;
        returns (the state reached, the index of the next output time)."""
        if not self._ready(s.t):
            return s, i
        arrays = self.stepper.integ.modal
        functions = arrays.functions(s.t)
        varying = any(not getattr(f, "constant", False) for f in self._functions())

        def fill(t: float, out: np.ndarray) -> None:
            try:
                out[:] = arrays.functions(t)
            except Exception:  # noqa: BLE001 -- not swallowed: the kernel stops before the
                # step, and the Python step evaluates the function again and raises it there,
                # with the rows before it recorded (a failure keeps its results)
                out[:] = math.nan

        with calling(fill) as handle:
            for _ in range(self.MOST_CALLS):
                s, i, status = self._chunk(s, outputs, i, trajectory, progress,
                                           functions, handle if varying else NO_CALL)  # fmt: skip
                if status or i == len(outputs):
                    break
        return s, i

    def _functions(self) -> list:
        """The coordinate equations' functions of time (None: no function)."""
        block = self.stepper.system.coordinate_rows()
        return [f for f in (block.equations[j].function for j in block.linear) if f is not None]

    def _chunk(self, s, outputs, i, trajectory, progress, functions, handle) -> tuple:
        """One `run_modal` call from s: (the state reached, the next output index, the
        status)."""
        stepper, system = self.stepper, self.stepper.system
        integ, stats = stepper.integ, stepper.stats
        arrays, scales = integ.modal, integ.scales
        assert arrays is not None and scales is not None and integ.tangent is not None
        own = np.stack([s.q, s.raw_qd, s.raw_qdd, s.a])
        own_lam = np.array(s.raw_lam, dtype=float)
        cons = np.stack([s.qd, s.qdd])
        cons_lam = np.array(s.lam, dtype=float)
        ctrl = self._control(s)
        counts = np.array([stats.steps, stats.rejected_steps, 0, 0, 0], dtype=np.int64)
        fi, ff = (a.copy() for a in integ._factor_data())
        factors = (fi, ff, fi.copy(), ff.copy())
        if self._angle_args is None:
            self._angle_args = ca.measure_args([m.sine_cosine for m in system.angle_measures], 4)
        refs_all = np.array([m.reference for m in system.angle_measures], dtype=float)
        block_angles = self._block_angles(system.coordinate_rows())
        ints, floats = arrays.packed()
        packed = (ints, floats, functions, refs_all[block_angles], arrays.bodies(),
                  arrays.modal(), arrays.welds(), arrays.active())  # fmt: skip
        rows = min(self.calls.rows(3 * system.nq + own_lam.size), len(outputs) - i)
        rows_t, rows_refs = np.empty(rows), np.empty((rows, len(refs_all)))
        rows_state = np.empty((rows, 3 * system.nq + own_lam.size))
        status, i_next, written = run_modal(
            own, own_lam, cons, cons_lam, ctrl, counts, outputs, i, packed, handle,
            integ.tangent, factors, (scales.q_abs, scales.a_ref), self._angle_args, refs_all,
            block_angles, rows_t, rows_state, rows_refs, 10 * rows, (integ.past_t, integ.past),
        )  # fmt: skip
        self.calls.done(written)
        count(
            factorizations=int(counts[rr.ROW_FACTORS]),
            jacobian_evaluations=int(counts[rr.ROW_JACOBIANS]),
        )
        if ctrl[rr.REFACTORED]:
            integ.adopt(fi, ff, float(ctrl[rr.LU_H]))
        taken = int(counts[rr.STEPS]) - stats.steps
        rejected = int(counts[rr.REJECTED]) - stats.rejected_steps
        stats.steps, stats.rejected_steps = int(counts[rr.STEPS]), int(counts[rr.REJECTED])
        stats.newton_iterations += int(counts[rr.ITERATIONS])
        for m, value in zip(system.angle_measures, refs_all):
            m.reference = float(value)
        if taken or rejected or ctrl[rr.RESTARTED]:
            s = self._moved(s, ctrl, own, own_lam, cons, cons_lam)
        self._record(trajectory, rows_t[:written], rows_state[:written], rows_refs[:written])
        if written and progress:
            progress(float(rows_t[written - 1]), stepper.spec.end)
        return s, i_next, status

    def _control(self, s) -> np.ndarray:
        """The control array of a call from s (run.py's slots and RETANGENT)."""
        stepper = self.stepper
        integ, spec, c = stepper.integ, stepper.spec, stepper.integ.c
        assert integ.scales is not None, "set by init"
        ctrl = np.zeros(CTRL_SIZE)
        ctrl[[rr.T, rr.H, rr.H_USED, rr.LU_H, rr.ETA, rr.STALE, RETANGENT]] = (
            s.t, stepper.h, stepper.h_used, integ.lu_h, integ.eta, integ.stale, integ.retangent
        )  # fmt: skip
        ctrl[[rr.MAX_STEP, rr.END, rr.MAX_STEPS, rr.TOL, rr.ERROR_CONSTANT]] = (
            stepper.max_step, spec.end, spec.max_steps, integ.scales.tol, c.error_constant
        )  # fmt: skip
        ctrl[[rr.ALPHA_M, rr.ALPHA_F, rr.BETA, rr.GAMMA]] = c.alpha_m, c.alpha_f, c.beta, c.gamma
        ctrl[rr.H_MIN] = stepper.h_min
        ctrl[rr.CEILING] = stepper.ceiling
        window = stepper.collapse.since
        ctrl[rr.WATCH] = -1.0 if window is None else float(window.taken)
        return ctrl

    def _moved(self, s, ctrl, own, own_lam, cons, cons_lam):
        """The stepper's state after a call that moved, shrunk or carried a to a new h."""
        stepper, integ = self.stepper, self.stepper.integ
        stepper.h, stepper.h_used = float(ctrl[rr.H]), float(ctrl[rr.H_USED])
        stepper.ceiling = float(ctrl[rr.CEILING])
        integ.eta, integ.stale = float(ctrl[rr.ETA]), bool(ctrl[rr.STALE])
        integ.retangent = bool(ctrl[RETANGENT])
        return type(s)(
            float(ctrl[rr.T]), own[0], cons[0], cons[1], cons_lam,
            raw_qd=own[1], raw_qdd=own[2], a=own[3], raw_lam=own_lam,
        )  # fmt: skip
