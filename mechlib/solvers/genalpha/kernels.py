"""Generalized-alpha's error weights and its compiled vector updates
(mechlib.solvers.genalpha.integrator)."""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.solvers.error_weights import coordinate_scales, element_state_scales
from mechlib.solvers.genalpha.rules import ROUNDOFF
from mechlib.system.system import System

__all__ = ["Scales", "correct", "error_norm", "position_size", "predict"]


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
    a1 = (qdd - alpha_m * a) / (1.0 - alpha_m)
    q1 = q + h * qd + h * h * ((0.5 - beta) * a + beta * a1)
    qd1 = qd + h * ((1.0 - gamma) * a + gamma * a1)
    return q1, qd1, qdd.copy()


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
