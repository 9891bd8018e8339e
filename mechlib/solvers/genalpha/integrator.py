"""Generalized-alpha for the index-3 equations of motion (Arnold & Bruls 2007).

    M(q) qdd + phi_q^T lam = Q(q, qd, t),  phi(q, t) = 0
    (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) qdd_{n+1} + alpha_f qdd_n
    q_{n+1}  = q_n + h qd_n + h^2 ((1/2 - beta) a_n + beta a_{n+1})
    qd_{n+1} = qd_n + h ((1 - gamma) a_n + gamma a_{n+1})

Newton on (q, lam) with the scaled iteration matrix [[M + (C gamma' + K)/beta', phi_q^T],
[phi_q, 0]] (beta' = (1-alpha_m)/(h^2 beta (1-alpha_f)), gamma' = gamma/(h beta)), kept
across iterations and steps while it converges (modified Newton). K = -dQ/dq and
C = -dQ/dqd are kept apart, so that a new step size only refactors; elements that give their
own tangent (compiled contacts) have it re-evaluated at each factorisation, the rest of K and C
(forward differences, 2 nq force evaluations, a column leaving out the elements whose
forces depend on other bodies only, and none for the exactly zero columns of massless node
bodies: mechlib.system.fd_columns) only after slow or failed convergence (a slow step is
first answered by a refactorisation with the tangent kept but for modal bodies with force
elements: rules.keeps_tangent, rules.retangents).
Local error estimate e = h^2 (beta - gamma/2 + 1/12)(a_{n+1} - a_n) (leading term of the
position update, h^3/12 q''' for the trapezoidal case), steps controlled on it and landing
on output times (the stepper around it: mechlib.solvers.genalpha.stepper).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechlib.core.outcome import SolverFailure, SolverStats
from mechlib.core.work import count
from mechlib.elements.compiled_forces import CompiledForces
from mechlib.flexible.packed import modal_arrays
from mechlib.linalg.factor import factor_saddle, singular_failure, solve_factored
from mechlib.linalg.flat_lu import factor_data, factors
from mechlib.model.analysis import Dynamic
from mechlib.solvers.genalpha import rules
from mechlib.solvers.genalpha.applied_tangent import packed_tangent
from mechlib.solvers.genalpha.compiled import CONVERGED, loaded_newton
from mechlib.solvers.genalpha.kernels import Scales, correct, error_norm, predict, predict_swing
from mechlib.solvers.genalpha.modal_step import modal_step
from mechlib.solvers.genalpha.tangent import differenced_tangent
from mechlib.system.fd_columns import ColumnSkips
from mechlib.system.reaction_loads import reaction_coupling
from mechlib.system.saddle import rigid_saddle_factors
from mechlib.system.system import System

__all__ = ["Coefficients", "Integrator"]


@dataclass(frozen=True)
class Coefficients:
    """alpha_m, alpha_f, beta, gamma of generalized-alpha for a spectral radius rho_inf."""

    alpha_m: float
    alpha_f: float
    beta: float
    gamma: float

    @classmethod
    def from_rho(cls, rho: float) -> Coefficients:
        am = (2.0 * rho - 1.0) / (rho + 1.0)
        af = rho / (rho + 1.0)
        g = 0.5 + af - am
        return cls(am, af, 0.25 * (g + 0.5) ** 2, g)

    @property
    def error_constant(self) -> float:
        return abs(self.beta - 0.5 * self.gamma + 1.0 / 12.0)


class Integrator:
    """One generalized-alpha step: Newton on (q, lam) with the scaled iteration matrix,
    then the state corrected on all three constraint levels; its error estimate."""

    def __init__(self, system: System, spec: Dynamic, stats: SolverStats):
        self.system, self.spec, self.stats = system, spec, stats
        self.c = Coefficients.from_rho(spec.rho_inf)
        self.lu = None
        self.lu_h = 0.0
        self.tangent: tuple[np.ndarray, np.ndarray] | None = None
        self.stale = False
        self.retangent = False  # the next factorisation takes a new tangent (rules.retangents)
        # modal bodies and no force elements: a tangent that changes with the spin alone
        self.spun = bool(system.nz) and not system.elements
        # a slow step refactors with the tangent kept before a new one (rules.keeps_tangent)
        self.kept_first = bool(rules.keeps_tangent(bool(system.nz), bool(system.elements)))
        self.refactor = False  # the next step factors the matrix again (set by _predicted)
        self.stiff = bool(system.elements) or system.nz > 0  # modal stiffness, damping
        self.eta = 1.0
        self.singular: SolverFailure | None = None  # the last singular iteration matrix
        self.scales: Scales | None = None  # set by the stepper from its first state
        # the compiled Newton loop (mechlib.solvers.genalpha.compiled) serves steps whose
        # active elements are all packed (mechlib.elements.compiled_forces, with the valve
        # actuators' states): nothing of theirs to evaluate in Python between two
        # iterations (the kernels are compiled by now: the model checks called them)
        python = spec.compiled == "python"
        self.arrays = None if python else system.packed_constraints()
        # modal bodies: their own compiled loop (mechlib.solvers.genalpha.modal_step)
        self.modal = None if python or self.arrays is not None else modal_arrays(system)
        # the predictor of modal bodies without force elements (kernels.predict_swing); not
        # along a grid: A01's companion over 2000 s gained energy from it (analyses.md)
        self.swings = self.spun
        # its memory: the last two step starts' times and consistent accelerations
        self.past_t = np.full(2, np.nan)
        self.past = np.zeros((2, system.nq if self.swings else 0))
        self._factors: tuple = (None, None)  # (self.lu, its factor_data)

    def elements(self, t: float | None = None) -> CompiledForces | None:
        """The active force elements packed (System.compiled_forces), their moving values
        refreshed (the actuators' demands at t, s, when given); None: one is not packable."""
        packed = self.system.compiled_forces()
        if packed is not None:
            packed.refresh(self.system, t)
        return packed

    def _iteration_matrix(self, k, h: float, fresh: bool, lam: np.ndarray, matrices=None):
        """Factor the iteration matrix at step h, state k and multipliers lam: the
        elements' own tangents (compiled contacts, cheap) always at k; the finite-difference
        part re-evaluated when `fresh`, else the last one reused; -dQ/dlam of the loads that
        depend on the reactions (joint friction) beside phi_q^T. `matrices`: (M, phi_q) at
        k when known (mechlib.solvers.genalpha.modal_step computes them compiled)."""
        c, sys = self.c, self.system
        count(jacobian_evaluations=1)
        if not self.stiff:  # [[M, phi_q^T], [phi_q, 0]], gathered on its pattern
            lu = rigid_saddle_factors(sys, k)
            if lu is None:
                raise singular_failure(sys, sys.phi_q(k), k.t, "dynamic analysis failed")
            self.lu, self.lu_h = lu, h
            return
        bp = (1.0 - c.alpha_m) / (h * h * c.beta * (1.0 - c.alpha_f))
        mass, jac = (sys.mass(k), sys.phi_q(k)) if matrices is None else matrices
        own = self.own
        if fresh or self.tangent is None:
            self.tangent = self._differenced_tangent(k, own, lam, jac, h)
        stiffness, damping = (m.copy() for m in self.tangent) if own else self.tangent
        if own:
            view = sys.view(k)
            for element in own:
                element.tangent(view, stiffness, damping)
        top = mass + (stiffness + (c.gamma / (h * c.beta)) * damping) / bp
        lu = factor_saddle(top, jac, None, coupling=reaction_coupling(sys, k, lam, jac))
        if lu is None:
            raise singular_failure(sys, jac, k.t, "dynamic analysis failed")
        self.lu, self.lu_h = lu, h

    def _rebuilds(self, h: float, fresh: bool) -> bool:
        """A step factors its matrix anew (`own` tangents too: kept with the rest, cheaper)."""
        return fresh or self.refactor or rules.refactors(h, self.lu_h)

    @property
    def own(self) -> list:
        """The active elements that give their own tangent (`has_tangent`)."""
        return [e for e in self.system.elements if e.active and getattr(e, "has_tangent", False)]

    def _differenced_tangent(
        self, k, own: list, lam: np.ndarray, jac: np.ndarray, h: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """(K, C) of the applied forces but the elements with their own tangent (`own`),
        by forward differences at multipliers `lam` (mechlib.solvers.genalpha.tangent), in
        one compiled call where the kernel covers the system (applied_tangent)."""
        skips = ColumnSkips(self.system, {id(e) for e in own})  # a column: its body's elements
        packed = packed_tangent(self.system, self.arrays, k, skips, own, lam)  # compiled
        return differenced_tangent(self.system, k, skips, lam, jac, h) if packed is None else packed

    def step(self, t, h, q, qd, qdd, a, lam, cons=None):
        """One step; returns the new state or None when Newton does not converge. `cons`:
        the consistent acceleration at t, which the predictor of systems with modal bodies
        and no force elements reads (kernels.predict_swing)."""
        if self.modal is not None:
            return modal_step(self, self.modal, t, h, q, qd, qdd, a, lam, cons)
        elements = None if self.arrays is None else self.elements(t + h)
        if elements is not None:
            return self._compiled_step(t, h, q, qd, qdd, a, lam, elements, cons)
        c, sys = self.c, self.system
        bp, gp, q1, qd1, qdd1, lam1, t1, fresh = self._predicted(t, h, q, qd, qdd, a, lam, cons)
        rebuild = self._rebuilds(h, fresh)
        tried = self.refactor and not fresh  # refactored for slowness, the tangent kept
        refreshed, rebuilt, prev, it = False, rebuild, math.inf, 0
        eta = self.eta
        while it < rules.MAX_ITER:
            k = sys.kin(q1, qd1, t1)
            if sys.states:
                sys.states.advance(sys.view(k), h)
            if rebuild:
                try:
                    self._iteration_matrix(k, h, fresh, lam1)
                except SolverFailure as failure:  # singular here: reject, try a smaller step
                    self.singular = failure
                    break
                refreshed = refreshed or fresh or not self.stiff
                rebuild, prev = False, math.inf
            phi, jac = sys.phi_and_jacobian(k)
            res = np.concatenate(
                [
                    (sys.mass_times(k, qdd1) + jac.T @ lam1 - sys.forces(k, lam=lam1, jac=jac))
                    / bp,
                    phi,
                ]
            )
            dx = solve_factored(self.lu, -res)
            dq = dx[: sys.nq]
            correct(q1, qd1, qdd1, lam1, dx, gp, bp)
            self.stats.newton_iterations += 1
            it += 1
            # acceleration level: a position increment small against the position tolerance
            # is still large for qdd (x 1/(beta h^2)), i.e. for the forces and the energy
            assert self.scales is not None, "set by the stepper before its first step"
            size = self.scales.newton_size(dq, q1, qdd1, bp)
            eta = rules.newton_rate(size, prev, eta)
            if rules.converged(eta, size, _noise(self.scales, size, prev, dq, q1)):
                self.eta = rules.carried_rate(eta)
                self.converged_in(it, tried)
                a1 = ((1.0 - c.alpha_f) * qdd1 + c.alpha_f * qdd - c.alpha_m * a) / (
                    1.0 - c.alpha_m
                )
                return (
                    q1,
                    qd1,
                    qdd1,
                    a1,
                    lam1,
                    self._true_acceleration(q1, qd1, t1, qdd1, lam1, jac),
                )
            if rules.stalled(size, prev, it):
                again = self.restalled(refreshed, rebuilt)
                if again is None:
                    break
                fresh, tried = again
                rebuild = rebuilt = True
                it = 0
            prev = size
        self.drop()
        return None

    def _predicted(self, t, h, q, qd, qdd, a, lam, cons=None) -> tuple:
        """(beta', gamma', q1, qd1, qdd1, lam1, t + h, fresh): the predictor of a step h
        from t (of systems with modal bodies and no force elements, given the consistent
        acceleration `cons`: kernels.predict_swing) and whether
        the differenced tangent is made afresh (no matrix, or the last step failed or
        converged slowly)."""
        c = self.c
        bp = (1.0 - c.alpha_m) / (h * h * c.beta * (1.0 - c.alpha_f))
        gp = c.gamma / (h * c.beta)
        if cons is not None and self.swings:
            q1, qd1, qdd1 = predict_swing(
                q, qd, qdd, a, cons, t, h, self.past_t, self.past, c.alpha_m, c.alpha_f,
                c.beta, c.gamma,
            )  # fmt: skip
        else:
            q1, qd1, qdd1 = predict(q, qd, qdd, a, h, c.alpha_m, c.beta, c.gamma)
        fresh = self.lu is None or (self.stale and self.retangent)
        self.refactor, self.stale = self.stale, False
        return bp, gp, q1, qd1, qdd1, lam.copy(), t + h, fresh

    def converged_in(self, iterations: int, tried: bool) -> None:
        """A step converged in `iterations`, its matrix refactored for the last step's
        slowness with the tangent kept (`tried`) or not: slow convergence asks for a new
        matrix for the next step (rules.slow), with a new differenced tangent as
        rules.retangents says where the system keeps its tangent first (rules.keeps_tangent:
        all but modal bodies with force elements, which take one at once; the compiled
        whole runs, mechlib.solvers.genalpha.run and .modal_run, decide alike)."""
        slow = rules.slow(iterations)
        self.stale = slow
        self.retangent = slow and (not self.kept_first or rules.retangents(tried))

    def restalled(self, refreshed: bool, rebuilt: bool) -> tuple[bool, bool] | None:
        """Newton stalled in a step (`refreshed`: on a matrix of a fresh tangent; `rebuilt`:
        one factored in this step): None, give the step up; else (fresh, tried) of the
        matrix to factor at the iterate (rules.restalled)."""
        again = rules.restalled(refreshed, rebuilt, self.spun)
        return None if again == rules.GIVE_UP else (again == rules.FRESH, again == rules.KEPT)

    def _compiled_step(self, t, h, q, qd, qdd, a, lam, elements: CompiledForces, cons=None):
        """`step` with the Newton iterations and three-level correction compiled
        (genalpha.compiled): the same steps and results (to round-off) for `elements`."""
        c, sys, arrays, states = self.c, self.system, self.arrays, self.system.states
        assert arrays is not None and self.scales is not None, "checked by step; set by init"
        bp, gp, q1, qd1, qdd1, lam1, t1, fresh = self._predicted(t, h, q, qd, qdd, a, lam, cons)
        rebuild = self._rebuilds(h, fresh)
        tried = self.refactor and not fresh
        refreshed, prev, it, eta = False, math.inf, 0, self.eta
        ints, floats = arrays.packed()
        functions, refs = arrays.functions(t1), arrays.references()
        scales = self.scales
        params = np.array([bp, gp, scales.tol, c.alpha_m, c.alpha_f])
        nq = sys.nq
        true = np.empty(3 * nq + lam1.shape[0])  # qd, qdd, lam on three levels; a
        states.compiled_step(h)
        rates = states.z if states.rates_accepted is None else states.rates_accepted
        while True:
            if rebuild:
                k = sys.kin(q1, qd1, t1)
                if states:  # the tangent's base at the iterate's states, as in `step`
                    states.advance(sys.view(k), h)
                try:
                    self._iteration_matrix(k, h, fresh, lam1)
                except SolverFailure as failure:  # singular here: reject, try a smaller step
                    self.singular = failure
                    break
                refreshed = refreshed or fresh or not self.stiff
                rebuild, prev = False, math.inf
            status, it, prev, eta, done = loaded_newton(
                q1, qd1, qdd1, lam1, ints, floats, functions, refs, arrays.bodies(),
                *self._factor_data(), scales.q_abs, scales.a_ref, params, it, prev, eta, qdd, a,
                true, h, states.z, rates, states.trial, elements.args,
            )  # fmt: skip
            self.stats.newton_iterations += done
            if status == CONVERGED:
                self.eta = rules.carried_rate(eta)
                self.converged_in(it, tried)
                m = lam.size
                consistent = (true[:nq], true[nq : 2 * nq], true[2 * nq : 2 * nq + m])
                return q1, qd1, qdd1, true[2 * nq + m :], lam1, consistent
            if refreshed:
                break
            rebuild = fresh = True  # an old iteration matrix: refresh it once, go on
            tried, it = False, 0
        self.drop()
        return None

    def drop(self) -> None:
        """A step failed: the iteration matrix is dropped (the next step factors afresh),
        the Newton rate estimate reset and the element states' trial values undone."""
        self.lu = None
        self.eta = 1.0
        self.system.states.reject()

    def adopt(self, ints: np.ndarray, floats: np.ndarray, h: float) -> None:
        """Take flat factors (mechlib.linalg.flat_lu) made by a compiled run for the step size h
        (s) as the iteration matrix's."""
        self.lu, self.lu_h = factors(ints, floats), h
        self._factors = (self.lu, (ints, floats))

    def _factor_data(self) -> tuple[np.ndarray, np.ndarray]:
        """The current factors as the compiled kernels take them (converted once)."""
        lu, data = self._factors
        if lu is not self.lu:
            data = factor_data(self.lu)
            self._factors = (self.lu, data)
        return data

    def _true_acceleration(self, q1, qd1, t1, qdd1, lam1, jac):
        """The state on all three constraint levels, by corrections with the iteration
        matrix: qd projected onto phi_q qd = nu (mass-weighted), then (qdd, lam) meeting
        phi_q qdd = gamma too. Index-3 generalized-alpha leaves O(h) transients in its qdd
        and lam and O(h^2) velocity-constraint errors; the error estimate and the outputs
        (reactions) use these corrected values. `jac` is phi_q of the last Newton iterate
        (one small increment away: good enough for corrections). Returns (qd, qdd, lam)."""
        sys = self.system
        k = sys.kin(q1, qd1, t1)
        nq = sys.nq
        drift = sys.nu(k) - jac @ qd1
        qd = qd1 + solve_factored(self.lu, np.concatenate([np.zeros(nq), drift]))[:nq]
        k = sys.kin(q1, qd, t1)
        res = np.concatenate(
            [
                sys.mass_times(k, qdd1) + jac.T @ lam1 - sys.forces(k, lam=lam1, jac=jac),
                jac @ qdd1 - sys.gamma(k),
            ]
        )
        fix = solve_factored(self.lu, res)
        return qd, qdd1 - fix[:nq], lam1 - fix[nq:]

    def error(self, h, q1, acc0, acc1) -> float:
        """Scaled norm of the local position error c h^2 (qdd_{n+1} - qdd_n), about
        c h^3 d3q/dt3, from the true accelerations at both ends (accept when <= 1)."""
        assert self.scales is not None, "set by the stepper before its first step"
        scales = self.scales
        return error_norm(self.c.error_constant * h * h, acc0, acc1, scales.q_abs, scales.tol, q1)


def _noise(scales: Scales, size: float, prev: float, dq: np.ndarray, q1: np.ndarray) -> bool:
    """Newton has reached its round-off floor (rules.is_noise)."""
    return bool(rules.is_noise(size, prev, scales.position_size(dq, q1), scales.tol))
