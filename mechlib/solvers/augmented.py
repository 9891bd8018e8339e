"""Accelerations and reactions that stay bounded at singular positions: the augmented
Lagrangian iteration (Bayo and Ledesma 1996) on the index-1 equations of motion.

    (M + alpha J^T J) qdd_{i+1} = Q(lam_i) - J^T lam_i + alpha J^T g
    lam_{i+1} = lam_i + alpha (J qdd_{i+1} - g)

with J = phi_q scaled to unit rows (a row's scale does not change what it allows) and g
the right-hand side of the acceleration constraints scaled alike. Where J has full rank
the iteration converges to the solution of the saddle system [[M, J^T], [J, 0]] at a rate
of about |M| / (alpha sigma_min^2) per iteration; where J
loses rank (the horizontal position of a chain of parallelogram four-bars, a toggle) the
saddle matrix is singular, yet M + alpha J^T J stays positive definite (the body
normalisation rows fill the null space of the Euler-parameter mass) and qdd stays bounded:
the part of g no acceleration can meet (the constraint drift there) is left unmet instead
of being divided by a vanishing singular value. qdd is then a smooth function of the
state, which an error-controlled integrator can step through. The penalty trades digits:
a larger alpha converges in fewer iterations but loses about log10(alpha/|M|) digits in
the factor (at 1e8, Radau at tolerance 1e-6 stalled on Andrews' squeezer and the A01
pendulum at 1e-8 lost an order); 1e4 with 12 iterations keeps Andrews at 1.1e-7 and the
N-four-bar crossings within their bounds.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from mechlib.core.work import count
from mechlib.kinematics.kin import Kin

__all__ = ["PENALTY", "augmented_accelerations"]

PENALTY = 1e4  # alpha over the largest mass-matrix entry: larger loses digits in the factor
_ITERATIONS = 12  # at full rank the error shrinks ~1e-4 per iteration


def augmented_accelerations(
    system, k: Kin, jac: np.ndarray, gamma: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """(qdd, lam) of the equations of motion at state `k` with acceleration constraints
    phi_q qdd = gamma (SI; lam the multipliers of the rows of `jac`), by the augmented
    Lagrangian iteration; None when M + alpha J^T J is not positive definite (a body
    without mass in some direction)."""
    norms = np.linalg.norm(jac, axis=1)
    rows = 1.0 / np.where(norms > 0.0, norms, 1.0)
    unit, g = jac * rows[:, None], gamma * rows
    mass = system.mass(k)
    alpha = PENALTY * float(np.abs(mass).max())
    count(factorizations=1)
    try:
        factors = cho_factor(mass + alpha * (unit.T @ unit))
    except np.linalg.LinAlgError:
        return None
    lam_unit = np.zeros(len(g))
    pull = alpha * (unit.T @ g)
    qdd = np.zeros(system.nq)
    applied = None if system.reaction_dependent else system.forces(k, jac=jac)
    for _ in range(_ITERATIONS):  # a fixed count: qdd a smooth function of the state
        if applied is None:  # loads of the reactions (joint friction): at the last lam
            load = system.forces(k, lam=lam_unit * rows, jac=jac)
        else:
            load = applied
        load = load - unit.T @ lam_unit + pull
        new = cho_solve(factors, load)
        qdd = new
        lam_unit = lam_unit + alpha * (unit @ qdd - g)
    return qdd, lam_unit * rows
