"""Generalized-alpha's error weights and its compiled vector updates
(mechlib.solvers.genalpha.integrator)."""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.solvers.error_weights import coordinate_scales, element_state_scales
from mechlib.solvers.genalpha.rules import ROUNDOFF
from mechlib.system.system import System

__all__ = ["Scales", "correct", "error_norm", "position_size", "predict", "predict_swing"]


class Scales:
    """Error weights tol (scale + |q|) of each coordinate, the scales by one rule
    (mechlib.solvers.error_weights); acceleration references scale g / size, raised to
    the largest accelerations seen."""

    def __init__(self, system: System, q0: np.ndarray, tol: float):
        self.tol = tol
        g = max(float(np.linalg.norm(system.gravity)), 1.0)
        scales = coordinate_scales(system)
        self.q_abs = tol * scales
        # bodies: g for translations, g / size for rotations; a modal coordinate likewise
        self.a_ref = scales * (g / system.length)
        # element states (mechlib.elements.states): weighed by their element's scales
        self.z_abs = tol * element_state_scales(system.elements, system.states.z.size)

    def state_error(self, error: np.ndarray, z: np.ndarray) -> float:
        """max_i |error_i| / (z_abs_i + tol |z_i|): the scaled local error of the element
        states z after a step (0 for states of infinite scale)."""
        return float(np.max(np.abs(error) / (self.z_abs + self.tol * np.abs(z)), initial=0.0))

    def update(self, qdd: np.ndarray) -> None:
        """Raise the acceleration reference to the largest accelerations seen."""
        np.maximum(self.a_ref, np.abs(qdd), out=self.a_ref)

    def newton_size(self, dq: np.ndarray, q: np.ndarray, qdd: np.ndarray, bp: float) -> float:
        """Size of a Newton increment: the larger of its RMS against the position weights
        and of bp dq against tol (a_ref + |qdd|), the latter floored at what round-off in q
        allows (bp eps |q|): below it Newton cannot go, whatever tol asks."""
        return _newton_size(dq, q, qdd, bp, self.q_abs, self.a_ref, self.tol, ROUNDOFF)

    def position_size(self, dq: np.ndarray, q: np.ndarray) -> float:
        """RMS of a Newton increment against the position weights alone."""
        return position_size(dq, q, self.q_abs, self.tol)


@njit(**KERNEL)
def predict(q, qd, qdd, a, h, alpha_m, beta, gamma):
    """Predictor with qdd_{n+1} = qdd_n: (q, qd, qdd) at t + h."""
    nq = q.shape[0]
    q1, qd1 = np.empty(nq), np.empty(nq)
    hh = h * h
    for i in range(nq):  # one loop: no temporary arrays
        a1 = (qdd[i] - alpha_m * a[i]) / (1.0 - alpha_m)
        q1[i] = q[i] + h * qd[i] + hh * ((0.5 - beta) * a[i] + beta * a1)
        qd1[i] = qd[i] + h * ((1.0 - gamma) * a[i] + gamma * a1)
    return q1, qd1, qdd.copy()


@njit(**KERNEL)
def predict_swing(q, qd, qdd, a, cons, t, h, past_t, past, alpha_m, alpha_f, beta, gamma):
    """Predictor of a system whose integrator acceleration qdd swings step to step about
    the consistent one `cons` (modal bodies: the index-3 scheme leaves its modal
    accelerations alternating about the consistent ones, +-3.6 m/s^2 on Kane's beam, each
    step -0.98 times the last): qdd_{n+1} = cons + h (cons - cons_past) / (t - t_past) -
    (qdd - cons), the consistent acceleration's trend with the swing reversed, and
    (q, qd) at t + h by the Newmark relations of that qdd_{n+1}: (q1, qd1, qdd1). The
    Newton iterations that follow reach the same solution as from `predict`'s (to their
    tolerance) in fewer iterations (Kane's beam at 1e-6: 7203 against 7998, the same
    steps). `past_t` (2,) and `past` (2, nq): the times and consistent accelerations of
    the last two step starts (NaN: none), in place: a start at a new t (the last one
    accepted) shifts them."""
    if past_t[1] != t:
        past_t[0] = past_t[1]
        past[0, :] = past[1]
        past_t[1] = t
    past[1, :] = cons
    slope = h / (t - past_t[0]) if past_t[0] < t else 0.0  # NaN: no trend
    nq = q.shape[0]
    qdd1, q1, qd1 = np.empty(nq), np.empty(nq), np.empty(nq)
    for i in range(nq):
        guess = 2.0 * cons[i] - qdd[i]
        if slope != 0.0:
            guess += slope * (cons[i] - past[0, i])
        a1 = ((1.0 - alpha_f) * guess + alpha_f * qdd[i] - alpha_m * a[i]) / (1.0 - alpha_m)
        qdd1[i] = guess
        q1[i] = q[i] + h * qd[i] + h * h * ((0.5 - beta) * a[i] + beta * a1)
        qd1[i] = qd[i] + h * ((1.0 - gamma) * a[i] + gamma * a1)
    return q1, qd1, qdd1


@njit(**KERNEL)
def correct(q1, qd1, qdd1, lam1, dx, gp, bp):
    """Newton correction in place: dq into q, gamma' dq into qd, beta' dq into qdd."""
    nq = q1.shape[0]
    for i in range(nq):
        q1[i] += dx[i]
        qd1[i] += gp * dx[i]
        qdd1[i] += bp * dx[i]
    for i in range(lam1.shape[0]):
        lam1[i] += bp * dx[nq + i]


@njit(**KERNEL)
def _newton_size(dq, q, qdd, bp, q_abs, a_ref, tol, roundoff):  # see Scales.newton_size
    sq = sa = 0.0
    for i in range(dq.shape[0]):
        wq = dq[i] / (q_abs[i] + tol * abs(q[i]))
        wa = (
            bp
            * dq[i]
            / (tol * (a_ref[i] + abs(qdd[i])) + roundoff * bp * (q_abs[i] / tol + abs(q[i])))
        )
        sq += wq * wq
        sa += wa * wa
    return math.sqrt(max(sq, sa) / dq.shape[0])


@njit(**KERNEL)
def error_norm(scale, acc0, acc1, q_abs, tol, q1):
    """max_i |scale (acc1_i - acc0_i)| / (q_abs_i + tol |q1_i|): the scaled local error of
    a step (mechlib.solvers.genalpha.integrator.Integrator.error)."""
    worst = 0.0
    for i in range(q1.shape[0]):
        e = abs(scale * (acc1[i] - acc0[i]) / (q_abs[i] + tol * abs(q1[i])))
        if e > worst or e != e:  # a NaN stays: the step is then rejected
            worst = e
    return worst


@njit(**KERNEL)
def position_size(dq, q, q_abs, tol):
    """RMS of a Newton increment dq against the position weights q_abs + tol |q| alone."""
    acc = 0.0
    for j in range(dq.shape[0]):
        w = dq[j] / (q_abs[j] + tol * abs(q[j]))
        acc += w * w
    return math.sqrt(acc / dq.shape[0])
