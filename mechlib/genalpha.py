"""Generalized-alpha for the index-3 equations of motion (Arnold & Bruls 2007).

    M(q) qdd + phi_q^T lam = Q(q, qd, t),  phi(q, t) = 0
    (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) qdd_{n+1} + alpha_f qdd_n
    q_{n+1}  = q_n + h qd_n + h^2 ((1/2 - beta) a_n + beta a_{n+1})
    qd_{n+1} = qd_n + h ((1 - gamma) a_n + gamma a_{n+1})

Newton on (q, lam) with the scaled iteration matrix [[M + (C gamma' + K)/beta', phi_q^T],
[phi_q, 0]] (beta' = (1-alpha_m)/(h^2 beta (1-alpha_f)), gamma' = gamma/(h beta)), kept
across iterations and steps while it converges (modified Newton). K = -dQ/dq and
C = -dQ/dqd are kept apart, so that a new step size only refactors; elements that give their
own tangent (compiled contacts) have it re-evaluated at every step, the rest of K and C
(forward differences, 2 nq force evaluations) only after slow or failed convergence.
Local error estimate e = h^2 (beta - gamma/2 + 1/12)(a_{n+1} - a_n) (leading term of the
position update, h^3/12 q''' for the trapezoidal case), steps controlled on it and landing
on output times.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from numba import njit

from mechlib.analysis import Dynamic, Trajectory, check_step_limit, output_times
from mechlib.events import EventMonitor, fire, first_events
from mechlib.linalg import factor_saddle, singular_failure, solve_factored
from mechlib.reaction_loads import accelerations_and_reactions, reaction_coupling
from mechlib.runaway import StepCollapse, element_loads
from mechlib.solution import SolverFailure, SolverStats
from mechlib.stick import slip_stop, switch_sticking
from mechlib.system import System

__all__ = ["Coefficients", "run_generalized_alpha", "consistent_accelerations",
           "consistent_state"]

_MAX_ITER = 8
_SAFETY = 0.9
_GROW, _SHRINK = 4.0, 0.2
_REGROW = 1.5
_NEWTON_KAPPA = 0.05
_ETA_MIN = 1e-3
_ROUNDOFF = 1e3 * np.finfo(float).eps
_SLOW_ITERATIONS = 3
# first step, as a fraction of the analysis span: small, because the start acceleration may
# be one the motion leaves at once (joint friction at rest carries nothing until the joint
# slips); the step grows x4 per accepted step, so this costs about five steps
_FIRST_STEP = 1e-6


@dataclass(frozen=True)
class Coefficients:
    """alpha_m, alpha_f, beta, gamma of generalized-alpha for a spectral radius rho_inf."""

    alpha_m: float
    alpha_f: float
    beta: float
    gamma: float

    @classmethod
    def from_rho(cls, rho: float) -> "Coefficients":
        am = (2.0 * rho - 1.0) / (rho + 1.0)
        af = rho / (rho + 1.0)
        g = 0.5 + af - am
        return cls(am, af, 0.25 * (g + 0.5) ** 2, g)

    @property
    def error_constant(self) -> float:
        return abs(self.beta - 0.5 * self.gamma + 1.0 / 12.0)


def consistent_state(system: System, q, qd, t: float, *, project: bool = True):
    """(qd, qdd, lam): with `project`, qd projected onto phi_q qd = nu (mass-weighted);
    then qdd and lam from [[M, phi_q^T], [phi_q, 0]] [qdd; lam] = [Q(lam); gamma]: the
    reactions of the equations of motion at that state, free of integrator transients,
    with the joint friction they load (`mechlib.reaction_loads`)."""
    k = system.kin(q, qd, t)
    jac = system.phi_q(k)
    lu = factor_saddle(system.mass(k), jac, system.saddle_pattern())
    if lu is None:
        raise singular_failure(system, jac, t, "dynamic analysis failed")
    drift = system.nu(k) - jac @ qd
    if project and np.abs(drift).max(initial=0.0) > 0.0:
        qd = qd + solve_factored(lu, np.concatenate([np.zeros(system.nq), drift]))[:system.nq]
        k = system.kin(q, qd, t)
    sol = accelerations_and_reactions(system, k, jac, lu)
    if sol is None:
        raise singular_failure(system, jac, t, "dynamic analysis failed")
    return qd, sol[:system.nq], sol[system.nq:]


def consistent_accelerations(system: System, q, qd, t: float):
    """(qdd, lam) at the state (q, qd) without touching qd (see `consistent_state`)."""
    _, qdd, lam = consistent_state(system, q, qd, t, project=False)
    return qdd, lam


class _Scales:
    """Error weights: absolute parts from the mechanism's size, relative part = tolerance."""

    def __init__(self, system: System, q0: np.ndarray, tol: float):
        length = system.length
        self.tol = tol
        self.q_abs = np.tile(np.r_[np.full(3, length), np.ones(4)], system.nb) * tol
        g = max(float(np.linalg.norm(system.gravity)), 1.0)
        self.a_ref = np.tile(np.r_[np.full(3, g), np.full(4, g / length)], system.nb)

    def update(self, qdd: np.ndarray) -> None:
        """Raise the acceleration reference to the largest accelerations seen."""
        np.maximum(self.a_ref, np.abs(qdd), out=self.a_ref)

    def newton_size(self, dq: np.ndarray, q: np.ndarray, qdd: np.ndarray, bp: float) -> float:
        """Size of a Newton increment: the larger of its RMS against the position weights
        and of bp dq against tol (a_ref + |qdd|), the latter floored at what round-off in q
        allows (bp eps |q|): below it Newton cannot go, whatever tol asks."""
        return _newton_size(dq, q, qdd, bp, self.q_abs, self.a_ref, self.tol, _ROUNDOFF)

    def norm_q(self, e: np.ndarray, q: np.ndarray) -> float:
        """RMS of e weighted by atol + tol |q|."""
        w = e / (self.q_abs + self.tol * np.abs(q))
        return math.sqrt(w @ w / w.size)


class _Integrator:
    def __init__(self, system: System, spec: Dynamic, stats: SolverStats):
        self.system, self.spec, self.stats = system, spec, stats
        self.c = Coefficients.from_rho(spec.rho_inf)
        self.lu = None
        self.lu_h = 0.0
        self.tangent: tuple[np.ndarray, np.ndarray] | None = None
        self.stale = False
        self.stiff = bool(system.elements)
        self.eta = 1.0
        self.singular: SolverFailure | None = None  # the last singular iteration matrix

    def _iteration_matrix(self, k, h: float, fresh: bool, lam: np.ndarray):
        """Factor the iteration matrix at step h, state k and multipliers lam: the
        elements' own tangents (compiled contacts, cheap) always at k; the finite-difference
        part re-evaluated when `fresh`, else the last one reused; -dQ/dlam of the loads that
        depend on the reactions (joint friction) beside phi_q^T."""
        c, sys = self.c, self.system
        bp = (1.0 - c.alpha_m) / (h * h * c.beta * (1.0 - c.alpha_f))
        jac = sys.phi_q(k)
        top = sys.mass(k)
        if self.stiff:
            own = self.own
            if fresh or self.tangent is None:
                self.tangent = self._differenced_tangent(k, own, lam, jac)
            stiffness, damping = (m.copy() for m in self.tangent) if own else self.tangent
            if own:
                view = sys.view(k)
                for element in own:
                    element.tangent(view, stiffness, damping)
            top = top + (stiffness + (c.gamma / (h * c.beta)) * damping) / bp
        lu = factor_saddle(top, jac, None if self.stiff else sys.saddle_pattern(),
                           coupling=reaction_coupling(sys, k, lam, jac))
        if lu is None:
            raise singular_failure(sys, jac, k.t, "dynamic analysis failed")
        self.lu, self.lu_h = lu, h

    @property
    def own(self) -> list:
        """The active elements that give their own tangent (`has_tangent`)."""
        return [e for e in self.system.elements
                if e.active and getattr(e, "has_tangent", False)]

    def _differenced_tangent(self, k, own: list, lam: np.ndarray, jac: np.ndarray
                             ) -> tuple[np.ndarray, np.ndarray]:
        """(K, C) = (-dQ/dq, -dQ/dqd) of the applied forces but the elements with their
        own tangent (`own`), by forward differences at multipliers `lam` (joint friction
        is loaded by them)."""
        sys = self.system
        skip = {id(e) for e in own}
        q, qd = k.x[:-1].ravel(), k.xd[:-1].ravel()
        base = sys.forces(k, skip=skip, lam=lam, jac=jac)
        stiffness, damping = np.empty((sys.nq, sys.nq)), np.empty((sys.nq, sys.nq))
        for j in range(sys.nq):
            dq = np.zeros(sys.nq)
            dq[j] = eps = 1e-7 * max(1.0, abs(q[j]))
            stiffness[:, j] = -(sys.forces(sys.kin(q + dq, qd, k.t), skip=skip, lam=lam)
                                - base) / eps
            dq[j] = eps = 1e-7 * max(1.0, abs(qd[j]))
            damping[:, j] = -(sys.forces(sys.kin(q, qd + dq, k.t), skip=skip, lam=lam,
                                         jac=jac) - base) / eps
        return stiffness, damping

    def step(self, t, h, q, qd, qdd, a, lam):
        """One step; returns the new state or None when Newton does not converge."""
        c, sys = self.c, self.system
        bp = (1.0 - c.alpha_m) / (h * h * c.beta * (1.0 - c.alpha_f))
        gp = c.gamma / (h * c.beta)
        q1, qd1, qdd1 = _predict(q, qd, qdd, a, h, c.alpha_m, c.beta, c.gamma)
        lam1 = lam.copy()
        t1 = t + h
        # a new differenced tangent after a failure or slow convergence; a step-size change
        # refactors; elements with their own tangent (contacts: stiffness and friction slope
        # change from step to step) have it re-evaluated at every step
        fresh = self.lu is None or self.stale
        rebuild = fresh or abs(h / self.lu_h - 1.0) > 0.25 or bool(self.own)
        self.stale = False
        refreshed, prev, it = False, math.inf, 0
        eta = self.eta
        while it < _MAX_ITER:
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
            res = np.concatenate([(sys.mass_times(k, qdd1) + jac.T @ lam1
                                   - sys.forces(k, lam=lam1, jac=jac)) / bp,
                                  phi])
            dx = solve_factored(self.lu, -res)
            dq = dx[:sys.nq]
            _correct(q1, qd1, qdd1, lam1, dx, gp, bp)
            self.stats.newton_iterations += 1
            it += 1
            # acceleration level: a position increment small against the position tolerance
            # is still large for qdd (x 1/(beta h^2)), i.e. for the forces and the energy
            size = self.scales.newton_size(dq, q1, qdd1, bp)
            if prev < math.inf:
                theta = size / prev
                eta = theta / (1.0 - theta) if theta < 1.0 else math.inf
            # Newton error estimate eta*|dq| against a fraction of the local error tolerance
            # (Hairer & Wanner, Solving ODEs II, IV.8); positions only, as the error test
            if (eta * size <= _NEWTON_KAPPA and size < 1.0) or size < 1e-10:
                self.eta = max(eta, _ETA_MIN) ** 0.8
                if it > _SLOW_ITERATIONS:
                    self.stale = True  # converging slowly: a fresh matrix for the next step
                a1 = ((1.0 - c.alpha_f) * qdd1 + c.alpha_f * qdd - c.alpha_m * a) / (1.0 - c.alpha_m)
                return q1, qd1, qdd1, a1, lam1, self._true_acceleration(q1, qd1, t1, qdd1, lam1,
                                                                       jac)
            if (prev < math.inf and size > 0.9 * prev) or it == _MAX_ITER:
                if refreshed:
                    break
                rebuild = fresh = True  # an old iteration matrix: refresh it once, go on
                it = 0
            prev = size
        self.lu = None
        self.eta = 1.0
        sys.states.reject()
        return None

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
        res = np.concatenate([sys.mass_times(k, qdd1) + jac.T @ lam1
                              - sys.forces(k, lam=lam1, jac=jac),
                              jac @ qdd1 - sys.gamma(k)])
        fix = solve_factored(self.lu, res)
        return qd, qdd1 - fix[:nq], lam1 - fix[nq:]

    def error(self, h, q1, acc0, acc1) -> float:
        """Scaled norm of the local position error c h^2 (qdd_{n+1} - qdd_n), about
        c h^3 d3q/dt3, from the true accelerations at both ends (accept when <= 1)."""
        e = self.c.error_constant * h * h * (acc1 - acc0)
        return float(np.abs(e / (self.scales.q_abs + self.scales.tol * np.abs(q1))).max())


@njit(cache=True)
def _predict(q, qd, qdd, a, h, alpha_m, beta, gamma):
    """Predictor with qdd_{n+1} = qdd_n: (q, qd, qdd) at t + h."""
    a1 = (qdd - alpha_m * a) / (1.0 - alpha_m)
    q1 = q + h * qd + h * h * ((0.5 - beta) * a + beta * a1)
    qd1 = qd + h * ((1.0 - gamma) * a + gamma * a1)
    return q1, qd1, qdd.copy()


@njit(cache=True)
def _correct(q1, qd1, qdd1, lam1, dx, gp, bp):
    """Newton correction in place: dq into q, gamma' dq into qd, beta' dq into qdd."""
    nq = q1.shape[0]
    for i in range(nq):
        q1[i] += dx[i]
        qd1[i] += gp * dx[i]
        qdd1[i] += bp * dx[i]
    for i in range(lam1.shape[0]):
        lam1[i] += bp * dx[nq + i]


@njit(cache=True)
def _newton_size(dq, q, qdd, bp, q_abs, a_ref, tol, roundoff):  # see _Scales.newton_size
    sq = sa = 0.0
    for i in range(dq.shape[0]):
        wq = dq[i] / (q_abs[i] + tol * abs(q[i]))
        wa = bp * dq[i] / (tol * (a_ref[i] + abs(qdd[i])) + roundoff * bp * (q_abs[i] / tol
                                                                            + abs(q[i])))
        sq += wq * wq
        sa += wa * wa
    return math.sqrt(max(sq, sa) / dq.shape[0])


def _substeps(interval: float, h: float) -> tuple[int, float]:
    """Equal sub-steps landing on the output time: (count, size)."""
    n = max(1, math.ceil(interval / h * (1.0 - 1e-9)))
    return n, interval / n


@dataclass
class _State:
    """An accepted state: time (s), q, qd, qdd, gen-alpha's a, lam, and the consistent
    (qd, qdd, lam) that outputs and the error estimate use."""

    t: float
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    a: np.ndarray
    lam: np.ndarray
    consistent: tuple


def _view(system: System, s: "_State"):
    """The state view of an accepted state, with its consistent velocities and multipliers
    (so that event conditions can read motion efforts and reactions)."""
    qd, _, lam = s.consistent
    return system.view(system.kin(s.q, qd, s.t), lam)


class _Run:
    """Step-size control, event handling and restarts around `_Integrator.step`."""

    def __init__(self, system: System, spec: Dynamic, stats: SolverStats, events):
        self.system, self.spec, self.stats = system, spec, stats
        self.integ = _Integrator(system, spec, stats)
        self.monitor = EventMonitor(events)
        self.log: list = []
        self.stopped = False
        self.max_step = min(spec.max_step or spec.step, spec.step)
        span = spec.end - spec.start
        self.h = self.max_step if spec.fixed_step else min(self.max_step,
                                                            _FIRST_STEP * span or 1e-3)
        self.h_min = 1e-12 * max(1.0, abs(spec.end))
        self.h_used = 0.0
        self.collapse = StepCollapse(spec.name, spec.end, spec.max_steps)

    def restart(self, t: float, q: np.ndarray, qd: np.ndarray) -> _State:
        """Consistent accelerations (and velocities: a latch engaging is a plastic impact,
        the mass-weighted projection) at t; the pseudo-acceleration starts from them."""
        if self.system.states:
            self.system.states.start(self.system.view(self.system.kin(q, qd, t)))
        qd, qdd, lam = consistent_state(self.system, q, qd, t)
        self.integ.lu, self.integ.eta = None, 1.0
        state = _State(t, q, qd, qdd, qdd.copy(), lam, (qd, qdd, lam))
        self.monitor.arm(t, _view(self.system, state))
        return state

    def attempt(self, s: _State, t_out: float) -> _State | None:
        """One step towards t_out; None when rejected (the step size is then reduced)."""
        spec, stats = self.spec, self.stats
        check_step_limit(spec, stats, s.t)
        _, h_try = _substeps(t_out - s.t, self.h)
        if self.h_used and abs(h_try / self.h_used - 1.0) > 1e-9:
            qdd, lam = consistent_accelerations(self.system, s.q, s.qd, s.t)
            s.qdd, s.a, s.lam, s.consistent = qdd, qdd.copy(), lam, (s.qd, qdd, lam)
        self.h_used = h_try
        new = self.integ.step(s.t, h_try, s.q, s.qd, s.qdd, s.a, s.lam)
        err = 0.0 if new is None or spec.fixed_step else self.integ.error(
            h_try, new[0], s.consistent[1], new[5][1])
        if new is None or err > 1.0:
            self.system.states.reject()
            if spec.fixed_step:
                raise _newton_failure(self.system, s.t, h_try)
            self._shrink(s.t, h_try * (0.25 if new is None else
                                       max(_SHRINK, _SAFETY * err ** (-1 / 3))))
            return None
        if not spec.fixed_step:
            grow = _GROW if err == 0.0 else min(_GROW, _SAFETY * err ** (-1 / 3))
            if grow > _REGROW:
                self.h = min(self.max_step, h_try * grow)
        return _State(s.t + h_try, *new)

    def _shrink(self, t: float, h: float) -> None:
        """A rejected step at t (s): retry with step h (s), failing below h_min."""
        self.stats.rejected_steps += 1
        self.h = h
        if self.h < self.h_min:  # a singular matrix says more than "no convergence"
            raise self.integ.singular or _newton_failure(self.system, t, self.h)

    def accept(self, s: _State) -> None:
        self.stats.steps += 1
        self.integ.scales.update(s.consistent[1])
        k = self.system.kin(s.q, s.qd, s.t)
        if self.system.states:
            self.system.states.accept(self.system.view(k))
        self.system.commit(k)
        self.collapse.watch(self.stats.steps + self.stats.rejected_steps, s.t, self.h_used,
                            lambda: element_loads(self.system, _view(self.system, s)))

    def _to(self, s: _State, t: float) -> _State:
        """The step from s re-solved to end at t (s); _Unresolved when Newton fails."""
        new = self.integ.step(s.t, t - s.t, s.q, s.qd, s.qdd, s.a, s.lam)
        if new is None:
            raise _Unresolved(t)
        return _State(t, *new)

    def stop_slips(self, s: _State, new: _State) -> _State:
        """`new`, or the state at the first instant within the step where a sliding joint
        friction stops (its slip rate passes through zero: it may stick there)."""
        sys = self.system
        try:
            t = slip_stop(sys, s.t, new.t, _view(sys, s), _view(sys, new),
                          lambda tt: _view(sys, self._to(s, tt)))
            if t is None:
                return new
            if t < new.t:
                return self._to(s, t)
        except (_Unresolved, SolverFailure):  # a shorter step Newton cannot take: keep new
            pass
        # the re-solved steps moved the element states' trial values: back to new's
        return self._to(s, new.t) if sys.states else new

    def events(self, s: _State, new: _State, trajectory: Trajectory) -> _State | None:
        """If events fire during the step s -> new: the state at the first one, recorded,
        with the actions done and the integration restarted; else None. When a re-solved
        step of the location fails, the step is rejected instead: `s` is returned and the
        next attempt is a quarter as long."""
        sys = self.system
        try:
            hit = first_events(self.monitor, s.t, new.t, _view(sys, new),
                               lambda t: _view(sys, self._to(s, t)))
            if hit is None:
                return None
            t_e, now = hit
            at = self._to(s, t_e)
        except _Unresolved as failed:
            # a load that jumps where the condition's zero lies (a preloaded wire going
            # taut) defeats Newton on steps ending just past it; shorter steps resolve it,
            # as for any step Newton cannot take
            self.system.states.reject()
            if self.spec.fixed_step:
                names = ", ".join(f"'{e.name}'" for e in
                                  self.monitor.crossed(new.t, _view(sys, new)))
                raise _newton_failure(sys, s.t, failed.t - s.t, f"locating event {names}")
            self._shrink(s.t, 0.25 * (new.t - s.t))
            return s
        self.accept(at)
        trajectory.record(t_e, at.q, *at.consistent)
        if fire(sys, self.monitor, now, sys.kin(at.q, at.qd, t_e), self.log):
            self.stopped = True
        return self.restart(t_e, at.q, at.qd)


def run_generalized_alpha(system: System, spec: Dynamic, q0, qd0, trajectory: Trajectory,
                          stats: SolverStats, progress: Callable | None = None,
                          events=(), event_log: list | None = None) -> None:
    """Integrate from spec.start to spec.end, recording at the output times (and at the
    events, whose records go to `event_log`).

    The step size changes only when the error estimate asks for it (shrink, or growth by
    more than _REGROW); at each change the pseudo-acceleration restarts from the consistent
    acceleration, because generalized-alpha's `a` is tied to the step it was made with.
    Outputs carry consistent velocities, accelerations and reactions.
    """
    run = _Run(system, spec, stats, events)
    run.integ.scales = _Scales(system, q0, spec.tolerance)
    s = run.restart(spec.start, q0.copy(), qd0.copy())
    if switch_sticking(system, s.q, s.qd, s.t, _view(system, s), consistent_state):
        s = run.restart(s.t, s.q, s.qd)
    trajectory.record(s.t, s.q, *s.consistent)
    try:
        for t_out in output_times(spec.start, spec.end, spec.step)[1:]:
            while t_out - s.t > 1e-12 * max(1.0, abs(t_out)) and not run.stopped:
                new = run.attempt(s, t_out)
                if new is None:
                    continue
                new = run.stop_slips(s, new)
                after = run.events(s, new, trajectory) if run.monitor.armed else None
                if after is None:
                    run.accept(new)
                    if switch_sticking(system, new.q, new.qd, new.t, _view(system, new),
                                       consistent_state):
                        after = run.restart(new.t, new.q, new.qd)
                    elif run.monitor.armed:
                        run.monitor.arm(new.t, _view(system, new))
                s = new if after is None else after
            if run.stopped:
                break
            trajectory.record(s.t, s.q, *s.consistent)
            if progress:
                progress(s.t, spec.end)
    finally:
        if event_log is not None:
            event_log.extend(run.log)


class _Unresolved(Exception):
    """A step re-solved to end at `t` (s) that Newton could not take."""

    def __init__(self, t: float):
        super().__init__(t)
        self.t = t


def _newton_failure(system: System, t: float, h: float, doing: str = "") -> SolverFailure:
    while_ = f" {doing}" if doing else ""
    return SolverFailure(f"dynamic analysis failed at t = {t:.6g} s{while_}: Newton iterations "
                         f"did not converge even with a step of {h:.3g} s (an impact or a "
                         "stiffness too large for the step, a toggle position, or a load "
                         "discontinuity)", time=t)
