"""Pseudo-transient continuation: bodies brought to rest on supports that have no stiffness yet.

A contact at zero penetration (k x^e, e > 1) or open has no stiffness, so Newton's matrix
for the static balance is singular there. Continuation adds the mass matrix over a pseudo
time step squared, delta (s^2): each step solves

    (K_T + M / delta) dq + phi_q^T dlam = -(phi_q^T lam - Q),    phi_q dq = -phi

(a damped fall along the unbalanced load: a free body moves delta * F / m). delta follows
the switched evolution relaxation rule, delta *= |R_old| / |R_new| (Mulder & van Leer 1985;
Kelley & Keyes 1998, SIAM J. Numer. Anal. 35), and at least doubles while the residual does
not grow, so that a body far from its support reaches it in a number of steps logarithmic in
the gap; as the residual falls M / delta vanishes and the steps become Newton's. The
continuation hands over to Newton once the weighted residual is below HANDOVER.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.outcome import SolverFailure, SolverStats, Status
from mechlib.linalg.factor import augmented, factor, singular_failure, solve_factored
from mechlib.solvers.static.balance import Balance

__all__ = ["HANDOVER", "MAX_STEPS", "RUNAWAY", "settle"]

HANDOVER = 1e-3
"""Weighted residual (forces over the balance's force scale) below which Newton takes over."""
MAX_STEPS = 120
"""Continuation steps before the bodies are declared not held."""
RUNAWAY = 1e3
"""Travel, in mechanism sizes, beyond which a body is taken to fall without end."""
_FIRST_TRAVEL = 1e-6
"""The first step's largest coordinate change, as a fraction of the mechanism's size (-)."""
_MIN_GROWTH = 2.0
_MAX_RETRIES = 8  # a singular matrix (a load path softening, K_T < 0): delta / 4, retried


def settle(
    balance: Balance, q: np.ndarray, lam: np.ndarray, stats: SolverStats
) -> tuple[np.ndarray, np.ndarray]:
    """(q, lam) near rest, from where Newton converges; SolverFailure naming the body that is
    not held (and the contacts on it) when a body runs away or MAX_STEPS pass."""
    system = balance.system
    length = system.length
    start = system.cm_positions(q)
    res, jac = balance.residual(q, lam)
    delta = _first_delta(balance, q, res, length)
    for _ in range(MAX_STEPS):
        size = balance.size(res)
        if size < HANDOVER:
            return q, lam
        stats.newton_iterations += 1
        step, delta = _step(balance, q, lam, res, jac, delta)
        q, lam = q + step[: system.nq], lam + step[system.nq :]
        res, jac = balance.residual(q, lam)
        travel = np.abs(system.cm_positions(q) - start).max()
        if not np.isfinite(res).all() or travel > RUNAWAY * length:
            break
        ratio = size / balance.size(res)
        delta *= max(ratio, _MIN_GROWTH) if ratio >= 1.0 else ratio
    raise _not_held(balance, q, lam, res, start)


def _first_delta(balance: Balance, q: np.ndarray, res: np.ndarray, length: float) -> float:
    """delta (s^2) moving a free coordinate by _FIRST_TRAVEL of the mechanism's size
    `length` (m) under the unbalanced load (M^-1 R: its acceleration)."""
    system = balance.system
    # least squares: massless bodies (the nodes of flexible bodies) make M singular
    mass = system.mass(system.kin(q, None, balance.t))
    accel = np.linalg.lstsq(mass, res[: system.nq], rcond=None)[0]
    return _FIRST_TRAVEL * length / max(float(np.abs(accel).max(initial=0.0)), 1e-300)


def _step(balance: Balance, q, lam, res, jac, delta: float) -> tuple[np.ndarray, float]:
    """The continuation step (dq, dlam) and the delta it was taken with."""
    system = balance.system
    stiffness = balance.stiffness(q, lam)
    mass = system.mass(system.kin(q, None, balance.t))
    for _ in range(_MAX_RETRIES):
        lu = factor(augmented(stiffness + mass / delta, jac))
        if lu is not None:
            return solve_factored(lu, -res), delta
        delta *= 0.25
    raise singular_failure(system, jac, balance.t, "static equilibrium failed")


def _not_held(balance: Balance, q, lam, res, start: np.ndarray) -> SolverFailure:
    """The failure of a body that continuation could not bring to rest: which body, along
    which direction, how far it went and what the contacts on it do there."""
    system, t = balance.system, balance.t
    unbalanced = -system.cm_forces(res)
    body = int(np.argmax(np.linalg.norm(unbalanced, axis=1)))
    force = unbalanced[body]
    direction = force / max(float(np.linalg.norm(force)), 1e-300) + 0.0  # no "-0"
    moved = float(np.linalg.norm(system.cm_positions(q)[body] - start[body]))
    view = system.view(system.kin(q, None, t), lam)
    contacts = [
        e for e in system.elements if e.active and hasattr(e, "geometry") and body in e.body_pair()
    ]
    notes = "; ".join(_contact_note(c, view, body, direction) for c in contacts)
    hint = (
        (
            f"{notes}: check that each contact lies where the load pushes the body and "
            "that its normal points from body 2 (plane, socket) towards body 1 (sphere, "
            "ball)"
        )
        if contacts
        else "no contact acts on it: add its support"
    )
    name = system.body_names[body]
    return SolverFailure(
        f"static equilibrium not found at t = {t:.6g} s: body '{name}' is not held along "
        f"({direction[0]:.3g}, {direction[1]:.3g}, {direction[2]:.3g}) (global): under an "
        f"unbalanced force of {np.linalg.norm(force):.4g} N it moved {moved:.4g} m without "
        f"coming to rest; {hint}",
        time=t,
        where=(name, *(c.name for c in contacts)),
        status=Status.NOT_HELD,
    )


def _contact_note(contact, view, body: int, direction: np.ndarray) -> str:
    """What contact `contact` does to `body` (index) moving along `direction`."""
    f = contact.forces(view)
    on_body = f.force if body == contact.body_pair()[0] else -f.force
    if f.normal <= 0.0:
        return f"contact '{contact.name}' is open there (gap {-f.gap.penetration:.4g} m)"
    way = "pushes it that way" if on_body @ direction > 0.0 else "holds part of it"
    return (
        f"contact '{contact.name}' {way} ({f.normal:.4g} N at penetration "
        f"{f.gap.penetration:.4g} m)"
    )
