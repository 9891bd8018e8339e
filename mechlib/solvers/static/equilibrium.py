"""Static equilibrium: Newton on (q, lam), with inertia ignored.

Unknowns (q, lam); the balance R = [phi_q^T lam - Q(q, t); phi(q, t)] and its
forward-difference stiffness are in mechlib.solvers.static.balance. Newton with backtracking on the
residual norm; where Newton's matrix is singular, pseudo-transient continuation
(mechlib.solvers.static.continuation)
first. Used by the static and quasi-static analyses (mechlib.solvers.static.analyses) and by modes.

The differenced stiffness (nq force evaluations, most of an equilibrium's cost) is reused by
the next iterations, and through a `Tangent` by the next equilibria of a quasi-static run,
with phi_q always current (modified Newton), as long as each such iteration at least halves
the residual; otherwise it is differenced afresh at the iterate and Newton goes on from
there. The convergence test is the same either way. Where this Newton fails, or needs more
than _MAX_FRESH fresh stiffnesses, Newton with a fresh stiffness at every iteration takes
over as if started from the same guess: its iterates are the reusing Newton's as long as
every step of that one was on a fresh stiffness (each reused step rejected), so it goes on
from the last of those (the guess itself once a reused step was accepted) instead of
differencing them again; the same iterates, iteration limit and result as a restart.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.outcome import SolverFailure, SolverStats, Status
from mechlib.core.work import count
from mechlib.linalg.factor import augmented, factor, singular_failure, solve_factored
from mechlib.solvers.assembly import solve_positions
from mechlib.solvers.static.balance import Balance
from mechlib.solvers.static.continuation import settle
from mechlib.system.system import System

__all__ = ["Tangent", "equilibrium"]

_MAX_NEWTON = 40
_CONTRACTION = 0.5  # residual ratio an iteration on a reused stiffness must reach
_MAX_FRESH = 4  # fresh stiffnesses in a Newton that reuses them: beyond, plain Newton


class Tangent:
    """The stiffness K_T (nq, nq) last differenced, for reuse (None: none yet). Newton
    replaces the array, never writes into it: tangents may share one."""

    def __init__(self, stiffness: np.ndarray | None = None) -> None:
        self.stiffness = stiffness


def equilibrium(
    system: System,
    q: np.ndarray,
    lam: np.ndarray | None,
    t: float,
    stats: SolverStats,
    tol: float = 1e-10,
    *,
    states_step: float = 0.0,
    tangent: Tangent | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(q, lam) in static equilibrium at t from a guess; SolverFailure if none is found.

    Newton first; where its matrix is singular (a contact at zero penetration or open has
    no stiffness: a body not yet resting on its support), pseudo-transient continuation
    (mechlib.solvers.static.continuation) brings the bodies to rest, and Newton finishes from there.
    Element states advance over `states_step` (s) with every iterate
    (mechlib.solvers.static.balance);
    `tangent`: the stiffness to start from (a quasi-static run's last), kept up to date."""
    q, its = solve_positions(system, q, t)
    stats.newton_iterations += its
    if lam is None or len(lam) != len(system.labels):
        # multipliers balancing the loads at the guess (least squares): the constraint
        # forces then carry their geometric stiffness (a hanging pendulum) from the start
        k = system.kin(q, None, t)
        count(factorizations=1)
        lam, *_ = np.linalg.lstsq(system.phi_q(k).T, system.forces(k, inertia=False), rcond=None)
    balance = Balance(system, t, q, states_step)
    tangent = tangent or Tangent()
    try:
        return _solve(balance, q, lam, stats, tol, tangent)
    except _Singular:
        tangent.stiffness = None
        q, lam = settle(balance, q, lam, stats)
    try:
        return _solve(balance, q, lam, stats, tol, tangent)
    except _Singular as singular:
        raise singular_failure(system, singular.jac, t, "static equilibrium failed") from None


def _solve(
    balance: Balance,
    q: np.ndarray,
    lam: np.ndarray,
    stats: SolverStats,
    tol: float,
    tangent: Tangent,
) -> tuple[np.ndarray, np.ndarray]:
    """Newton reusing `tangent`'s stiffness; where it fails, Newton differencing it at every
    iteration from the same start, resumed where the two part (_Abandoned)."""
    try:
        return _newton(balance, q, lam, stats, tol, tangent)
    except _Abandoned as abandoned:
        tangent.stiffness = None
        return _newton(balance, abandoned.q, abandoned.lam, stats, tol, None, abandoned.taken)


Moved = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def _fresh_step(balance: Balance, tangent: Tangent, q, lam, res, jac) -> Moved:
    """(q, lam, res, jac, step) after a Newton step on a stiffness differenced at q (kept
    in `tangent`), halved until the residual decreases; _Singular if the matrix is."""
    nq = balance.system.nq
    tangent.stiffness = balance.stiffness(q, lam)
    lu = factor(augmented(tangent.stiffness, jac))
    if lu is None:
        tangent.stiffness = None
        raise _Singular(jac)
    step = solve_factored(lu, -res)
    norm0, alpha = balance.size(res), 1.0
    while True:
        q_new, lam_new = q + alpha * step[:nq], lam + alpha * step[nq:]
        res_new, jac_new = balance.residual(q_new, lam_new)
        if balance.size(res_new) < norm0 or alpha < 1e-3:
            return q_new, lam_new, res_new, jac_new, step
        alpha *= 0.5


def _reused_step(balance: Balance, tangent: Tangent, q, lam, res, jac) -> Moved | None:
    """The full step on the reused stiffness with the current phi_q, or None when it
    does not at least halve the weighted residual (or the matrix is singular)."""
    nq = balance.system.nq
    assert tangent.stiffness is not None, "called with a stiffness to reuse"
    lu = factor(augmented(tangent.stiffness, jac))
    if lu is None:
        return None
    step = solve_factored(lu, -res)
    q_new, lam_new = q + step[:nq], lam + step[nq:]
    res_new, jac_new = balance.residual(q_new, lam_new)
    if not balance.size(res_new) <= _CONTRACTION * balance.size(res):
        return None
    return q_new, lam_new, res_new, jac_new, step


def _polished(balance: Balance, tangent: Tangent, q, lam, res, jac):
    """One more step on the reused stiffness where it contracts: a modified Newton ends just
    below the tolerance where a fresh one would have ended far below it (the kinematics of
    a driven quasi-static run at 3e-12 rad instead of 3e-15); one residual, no differencing."""
    moved = (
        _reused_step(balance, tangent, q, lam, res, jac) if tangent.stiffness is not None else None
    )
    return (q, lam) if moved is None else (moved[0], moved[1])


class _Abandoned(Exception):
    """A Newton reusing its stiffness failed. Its first `taken` iterations were on fresh
    stiffnesses (every reused step rejected), so they are those of a Newton with a fresh
    stiffness at every iteration from the same start: (q, lam) is where that one goes on."""

    def __init__(self, q: np.ndarray, lam: np.ndarray, taken: int):
        super().__init__("modified Newton abandoned")
        self.q, self.lam, self.taken = q, lam, taken


class _Singular(Exception):
    """Newton's matrix is singular at an iterate with constraint Jacobian `jac`."""

    def __init__(self, jac: np.ndarray):
        super().__init__("singular static matrix")
        self.jac = jac


def _newton(
    balance: Balance,
    q: np.ndarray,
    lam: np.ndarray,
    stats: SolverStats,
    tol: float,
    reused: Tangent | None,
    taken: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Newton on (q, lam), each step on a fresh stiffness halved (down to 1/1000) until the
    weighted residual decreases; given a `reused` tangent, on its stiffness while an
    undamped step at least halves it (module docstring); _Singular when a fresh matrix is.
    Reusing, _Abandoned after _MAX_NEWTON iterations or _MAX_FRESH stiffnesses; else
    SolverFailure after _MAX_NEWTON iterations in all (`taken`: those already taken)."""
    res, jac = balance.residual(q, lam)
    tangent, fresh = reused or Tangent(), 0
    resume = _Abandoned(q, lam, taken)
    unsettled = None  # the last step taken from a balanced iterate without settling
    for iteration in range(taken + 1, _MAX_NEWTON + 1):
        stats.newton_iterations += 1
        moved = None
        if reused is not None and tangent.stiffness is not None:
            moved = _reused_step(balance, tangent, q, lam, res, jac)
        on_fresh = moved is None
        if on_fresh:
            fresh += 1
            if reused is not None and fresh > _MAX_FRESH:
                break
            moved = _fresh_step(balance, tangent, q, lam, res, jac)
        assert moved is not None, "a fresh step always moves"
        if balance.balanced(res, tol):
            unsettled = moved[4]
        q, lam, res, jac, step = moved
        if balance.converged(res, step, tol):
            return _polished(balance, tangent, q, lam, res, jac) if reused else (q, lam)
        if on_fresh and resume.taken == iteration - 1:  # no reused step yet
            resume = _Abandoned(q, lam, iteration)
    if reused is not None:
        raise resume
    if unsettled is not None:
        raise _unsettled(balance, unsettled)
    raise _no_equilibrium(balance, res)


def _no_equilibrium(balance: Balance, res: np.ndarray) -> SolverFailure:
    """The failure of a Newton that ended at the residual `res`, naming the worst equation."""
    system, t, nq = balance.system, balance.t, balance.system.nq
    m = len(system.labels)
    worst = int(np.argmax(np.abs(res[nq:]))) if m else 0
    where = (system.labels[worst],) if m else ()
    return SolverFailure(
        f"static equilibrium did not converge at t = {t:.6g} s: no equilibrium "
        "near the previous position (a load beyond what the mechanism can "
        "hold, or an unloaded free degree of freedom)",
        time=t,
        where=where,
        status=Status.NEWTON_FAILED,
    )


def _unsettled(balance: Balance, step: np.ndarray) -> SolverFailure:
    """The failure of a Newton that reached an iterate whose forces balance but whose
    position step from it, `step`, stayed above the 1e-8 test: a direction held by a
    stiffness too small for the forward-difference tangent to resolve (about 1e-9 of its
    largest entry), along which each step is noise."""
    system, t = balance.system, balance.t
    frames = np.abs(step[: system.per_body * system.nb])  # the bodies' frames, not modes
    worst = int(np.argmax(frames))
    name = system.body_names[worst // system.per_body]
    return SolverFailure(
        f"static equilibrium did not settle at t = {t:.6g} s: the forces and constraints "
        f"came to balance within the tolerance, but the position steps stayed at "
        f"{float(frames[worst]):.3g} (above 1e-8) on body '{name}': a direction held "
        "by a stiffness too small for the tangent (forward differences) to resolve against "
        "the model's stiffest ones (a soft hold of a free motion): stiffen that hold, or "
        "hold the motion with a joint",
        time=t,
        where=(name,),
        status=Status.NEWTON_FAILED,
    )
