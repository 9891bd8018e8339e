"""Kinematic analysis: motions fix every degree of freedom.

Positions by Newton on phi(q, t) = 0, velocities from phi_q qd = nu, accelerations from
phi_q qdd = gamma, and reactions from the equations of motion with inertia:
phi_q^T lam = Q(lam) - M qdd (Newton when joint friction makes Q depend on lam). Element
states advance between the solved states (trapezoidal rule, mechlib.elements.states) before the
reactions, which their forces load.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.outcome import SolverFailure, SolverStats, Status
from mechlib.core.rotation import omega_global
from mechlib.linalg.factor import factor, singular_failure, solve_factored
from mechlib.solvers.assembly import solve_positions
from mechlib.solvers.contract import State, Stepper, StepResult
from mechlib.system.reaction_loads import solve_reaction_loaded
from mechlib.system.system import System

__all__ = ["KinematicStepper", "kinematic_state", "predicted_positions"]

_MAX_SUBDIVISIONS = 10


def predicted_positions(system: System, state: State, h: float) -> np.ndarray:
    """Position guess (nq,) at state.t + h: q + h qd + h^2/2 qdd, but each body's Euler
    parameters (3-D systems) turned by the rotation vector h omega + h^2/2 alpha (rad,
    global): added to linearly, they leave unit length and aim at a half turn when a body
    turns a radian or more per step, and Newton then fails or crawls."""
    guess = state.q + h * state.qd + 0.5 * h * h * state.qdd
    nb = system.nb
    if system.nq != 7 * nb + system.nz or not nb:  # planar: the angle is a coordinate
        return guess
    body = slice(0, 7 * nb)
    p = state.q[body].reshape(nb, 7)[:, 3:]
    turn = h * omega_global(p, state.qd[body].reshape(nb, 7)[:, 3:])
    turn += 0.5 * h * h * omega_global(p, state.qdd[body].reshape(nb, 7)[:, 3:])
    angle = np.linalg.norm(turn, axis=1)
    half = 0.5 * angle
    # sin(half) / angle, its limit 1/2 at rest
    scale = np.where(angle > 1e-8, np.sin(half) / np.where(angle > 0.0, angle, 1.0), 0.5)
    r0, r = np.cos(half), scale[:, None] * turn
    e0, e = p[:, 0], p[:, 1:]
    turned = np.empty_like(p)  # the product (r0, r) (e0, e)
    turned[:, 0] = r0 * e0 - np.einsum("ij,ij->i", r, e)
    turned[:, 1:] = r0[:, None] * e + e0[:, None] * r + np.cross(r, e)
    guess[body].reshape(nb, 7)[:, 3:] = turned
    return guess


def kinematic_state(
    system: System,
    q_guess: np.ndarray,
    t: float,
    stats: SolverStats,
    *,
    inertia: bool = True,
    states_step: float = 0.0,
):
    """(q, qd, qdd, lam) at time t from a position guess; raises SolverFailure by name.
    Element states (if any) advance by `states_step` (s) from their accepted values."""
    q, its = solve_positions(system, q_guess, t)
    stats.newton_iterations += its
    k = system.kin(q, None, t)
    system.commit(k)
    jac = system.phi_q(k)
    lu = factor(jac) if jac.shape[0] == jac.shape[1] else None
    if lu is None:
        raise singular_failure(system, jac, t, "kinematic analysis failed")
    qd = solve_factored(lu, system.nu(k))
    k = system.kin(q, qd, t)
    if system.states and states_step > 0.0:
        system.states.advance(system.view(k), states_step)
    qdd = solve_factored(lu, system.gamma(k))
    inertial = system.mass(k) @ qdd if inertia else 0.0

    def loads(lam):
        return system.forces(k, inertia=inertia, lam=lam, jac=jac) - inertial

    if not system.reaction_dependent:
        return q, qd, qdd, solve_factored(lu, loads(None), transpose=True)
    lam = solve_reaction_loaded(system, k, jac.T, loads, slice(0, jac.shape[0]), jac=jac)
    if lam is None:
        raise singular_failure(system, jac, t, "kinematic analysis failed")
    return q, qd, qdd, lam


class KinematicStepper(Stepper):
    """Each output time solved on its own from the state before (no integration: the
    output interval sets where results are sampled, not their accuracy); an interval that
    Newton cannot take is halved, recursively, 2^10 times at most (rejected steps)."""

    def init(self, t: float, q0: np.ndarray, qd0: np.ndarray) -> State:
        if self.system.states:
            self.system.states.start(self.system.view(self.system.kin(q0, qd0, t)))
        start = State(t, q0, qd0, np.zeros_like(q0), np.zeros(0))
        start.elements = self._mark(start)
        return self.settle(self._advance(start, t))

    def step(self, state: State, t_out: float) -> StepResult:
        return StepResult(self._advance(state, t_out), None, Status.SUCCESSFUL)

    def resolve(self, state: State, t: float) -> State:
        return self._advance(state, t)

    def settle(self, state: State) -> State:
        self.stats.steps += 1
        if self.system.states:
            assert state.elements is not None, "marked by _mark when there are states"
            self.system.states.resume(state.elements)
        return state

    def restart(self, state: State) -> State:
        """Positions, velocities and reactions afresh on the changed model."""
        return self._advance(state, state.t)

    def _advance(self, state: State, t1: float, depth: int = 0) -> State:
        """State at t1 from `state`; a step Newton cannot take is halved (10 times at most):
        the position guess (predicted_positions) extrapolates from `state`."""
        h = t1 - state.t
        if self.system.states:
            assert state.elements is not None, "marked by _mark when there are states"
            self.system.states.resume(state.elements)
        guess = predicted_positions(self.system, state, h)
        try:
            new = State(t1, *kinematic_state(self.system, guess, t1, self.stats, states_step=h))
            new.elements = self._mark(new)
            return new
        except SolverFailure:
            if depth >= _MAX_SUBDIVISIONS or h <= 0.0:
                raise
        self.stats.rejected_steps += 1
        mid = 0.5 * (state.t + t1)
        half = self._advance(state, mid, depth + 1)
        return self._advance(half, t1, depth + 1)

    def _mark(self, state: State):
        if not self.system.states:
            return None
        return self.system.states.mark(
            self.system.view(self.system.kin(state.q, state.qd, state.t))
        )
