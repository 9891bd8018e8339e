"""Integrator.step for a system with modal bodies whose Newton iterations run compiled
(mechlib.solvers.genalpha.modal_newton, the system packed by mechlib.flexible.packed): the
same predictor, iteration matrices (the differenced tangent included), rules and results
(to round-off) as the Python step, as Integrator._compiled_step is for rigid systems."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from mechlib.core.outcome import SolverFailure
from mechlib.core.work import count
from mechlib.flexible.packed import ModalArrays
from mechlib.solvers.genalpha import rules
from mechlib.solvers.genalpha.modal_matrix import factored
from mechlib.solvers.genalpha.modal_newton import (
    CONVERGED,
    modal_matrices,
    modal_newton,
    row_arrays,
)

if TYPE_CHECKING:
    from mechlib.solvers.genalpha.integrator import Integrator

__all__ = ["modal_step"]


def modal_step(integ: Integrator, arrays: ModalArrays, t, h, q, qd, qdd, a, lam, cons=None):
    """One step of Integrator `integ` from t over h (s) (`cons`: the consistent
    acceleration at t, for the predictor); the new state as Integrator.step returns it, or
    None when Newton does not converge."""
    c, sys, scales = integ.c, integ.system, integ.scales
    assert scales is not None, "set by the stepper before its first step"
    bp, gp, q1, qd1, qdd1, lam1, t1, fresh = integ._predicted(t, h, q, qd, qdd, a, lam, cons)
    rebuild = fresh or integ.refactor or rules.refactors(h, integ.lu_h)
    tried = integ.refactor and not fresh  # refactored for slowness, the tangent kept
    refreshed, rebuilt, prev, it, eta = False, rebuild, math.inf, 0, integ.eta
    ints, floats = arrays.packed()
    functions, refs = arrays.functions(t1), arrays.references()
    bodies, welds, active = arrays.modal(), arrays.welds(), arrays.active()
    params = np.array([bp, gp, scales.tol, c.alpha_m, c.alpha_f])
    nq, m = sys.nq, lam1.shape[0]
    true = np.empty(3 * nq + m)  # qd, qdd, lam on three levels; a
    lent = row_arrays(nq, ints, floats, welds)  # the factorisation's rows for Newton
    while True:
        if rebuild:
            system = (ints, floats, functions, refs, arrays.bodies(), bodies, welds, active)
            try:
                _factor(integ, system, q1, qd1, t1, h, fresh, lam1, lent)
            except SolverFailure as failure:  # singular here: reject, try a smaller step
                integ.singular = failure
                break
            refreshed = refreshed or fresh or not integ.stiff
            rebuild, prev = False, math.inf
        fi, ff = integ._factor_data()
        status, it, prev, eta, done = modal_newton(
            q1, qd1, qdd1, lam1, ints, floats, functions, refs, arrays.bodies(), bodies, welds,
            active, fi, ff, scales.q_abs, scales.a_ref, params, it, prev, eta, qdd, a, true, lent,
        )  # fmt: skip
        integ.stats.newton_iterations += done
        if status == CONVERGED:
            integ.eta = rules.carried_rate(eta)
            integ.converged_in(it, tried)
            consistent = (true[:nq], true[nq : 2 * nq], true[2 * nq : 2 * nq + m])
            return q1, qd1, qdd1, true[2 * nq + m :], lam1, consistent
        again = integ.restalled(refreshed, rebuilt)  # stalled
        if again is None:
            break
        fresh, tried = again
        rebuild = rebuilt = True
        it = 0
    integ.drop()
    return None


def _factor(integ: Integrator, system: tuple, q1, qd1, t1, h, fresh: bool, lam1, lent) -> None:
    """The iteration matrix of the step h (s) at (q1, qd1) factored: with the tangent kept
    in one compiled call (modal_matrix.factored, which modal_run uses too), with a new
    differenced tangent (`fresh`, or none yet) or where the kernel finds it singular by
    Integrator._iteration_matrix (the failure naming the joints). `lent`:
    modal_newton.row_arrays', flagged where the compiled call made the rows at q1."""
    sys, c = integ.system, integ.c
    nq, m = sys.nq, lam1.shape[0]
    if not fresh and integ.tangent is not None:
        n = nq + m
        fi, ff = np.zeros(2 + n, dtype=np.int64), np.empty(n * n + n)
        fi[1] = n
        bp = (1.0 - c.alpha_m) / (h * h * c.beta * (1.0 - c.alpha_f))
        if factored(q1, bp, c.gamma / (h * c.beta), system, integ.tangent, fi, ff, lent):
            count(jacobian_evaluations=1, factorizations=1)
            integ.adopt(fi, ff, h)
            return
    ints, floats, functions, refs, body, bodies, welds, active = system
    matrices = (np.empty((nq, nq)), np.empty((m, nq)))
    modal_matrices(q1, ints, floats, functions, refs, body, bodies, welds, active, *matrices)
    integ._iteration_matrix(sys.kin(q1, qd1, t1), h, fresh, lam1, matrices)
