"""Flexible bodies started in their quasi-static deflection (`InitialModes(static=True)`).

At the start of a dynamic run the named bodies' modal coordinates are moved until no modal
acceleration is needed: the equations of motion are solved for the accelerations and
reactions with the modal accelerations held at zero ([[M, phi_q^T, E^T], [phi_q, 0, 0],
[E, 0, 0]] [qdd; lam; mu] = [Q; gamma; 0], E the unit rows of the modal coordinates), and
mu, the modal force still unbalanced (N m per kg^0.5 m of the mass-normalised modes), moves
each coordinate by mu / omega^2 (the modal stiffness, the derivative that dominates for a
body stiffer than its attachments). The rigid coordinates follow through the assembly
(the constraints and the given values). The elastic forces then balance the loads, the
reactions and the inertia of the motion at the start: no ringing from a wrong start.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from mechlib.model.analysis import InitialModes
from mechlib.solvers.assembly import Assembled, reassemble
from mechlib.solvers.initial_modes import modal_columns
from mechlib.system.system import System

__all__ = ["settle_modes"]

_MAX_ITERATIONS = 50
_CONVERGED = 1e-7  # largest step, of the largest modal coordinate (2 to 3 steps; then round-off)


def _imbalance(system: System, q: np.ndarray, qd: np.ndarray, t: float, cols: np.ndarray):
    """mu (len(cols),): the modal forces that hold the modal accelerations at zero."""
    k = system.kin(q, qd, t)
    jac = system.phi_q(k)
    n, m, c = system.nq, jac.shape[0], len(cols)
    hold = np.zeros((c, n))
    hold[np.arange(c), cols] = 1.0
    saddle = np.zeros((n + m + c, n + m + c))
    saddle[:n, :n] = system.mass(k)
    saddle[:n, n : n + m] = jac.T
    saddle[:n, n + m :] = hold.T
    saddle[n : n + m, :n] = jac
    saddle[n + m :, :n] = hold
    rhs = np.concatenate([system.forces(k), system.gamma(k), np.zeros(c)])
    solution, *_ = np.linalg.lstsq(saddle, rhs, rcond=None)  # redundant rows: least norm
    return solution[n + m :]


def settle_modes(system: System, assembled: Assembled, t: float, initial: Sequence) -> Assembled:
    """`assembled` with the modal coordinates of the bodies marked `static` in `initial` at
    their quasi-static deflection (a warning in its notes when the iterations do not
    converge)."""
    bodies = [i.body for i in initial if isinstance(i, InitialModes) and i.static]
    if not bodies:
        return assembled
    parts = [modal_columns(system, body) for body in bodies]
    cols = np.concatenate([c for c, _ in parts])
    stiffness = np.concatenate([s for _, s in parts])
    others = [i for i in initial if not (isinstance(i, InitialModes) and i.body in bodies)]
    rates = [InitialModes(i.body, rates=i.rates) for i in initial if _rated(i, bodies)]
    q, qd, notes = assembled.q, assembled.qd, list[str]()
    for _ in range(_MAX_ITERATIONS):
        step = _imbalance(system, q, qd, t, cols) / stiffness
        targets = q.copy()
        targets[cols] += step
        given = [InitialModes(body, modes=list(targets[c])) for body, (c, _) in zip(bodies, parts)]
        q, qd, notes = reassemble(system, targets, t, others + given + rates)
        if np.abs(step).max() <= _CONVERGED * np.abs(q[cols]).max(initial=1e-300):
            return replace(assembled, q=q, qd=qd, notes=assembled.notes + notes)
    return replace(
        assembled,
        q=q,
        qd=qd,
        notes=assembled.notes
        + notes
        + [
            f"the quasi-static start of flexible bodies {', '.join(bodies)} did not converge "
            f"in {_MAX_ITERATIONS} iterations (last modal step {np.abs(step).max():.3g} "
            "kg^0.5 m): the run starts near it and may ring"
        ],
    )


def _rated(item, bodies: list[str]) -> bool:
    return isinstance(item, InitialModes) and item.body in bodies and item.rates is not None
