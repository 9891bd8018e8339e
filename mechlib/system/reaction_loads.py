"""Loads that depend on the joint reactions (joint friction): Q(q, qd, t, lam).

The equations of motion M qdd + phi_q^T lam = Q(lam) are then nonlinear in the multipliers.
Every analysis solves them with the same Newton iteration, whose matrix carries the
coupling dQ/dlam next to phi_q^T, so that the friction an integrator applies is the friction
of the reactions it reports (not the friction of the reactions of a frictionless solve).
dQ/dlam is analytic where the element gives it (joint friction: a rank-one term per
element), else a forward difference over the multipliers of the rows the element reads.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from mechlib.core.work import count
from mechlib.kinematics.kin import Kin
from mechlib.linalg.factor import augmented, factor, solve_factored

__all__ = [
    "MAX_REACTION_NEWTON",
    "accelerations_and_reactions",
    "differenced_coupling",
    "reaction_coupling",
    "solve_reaction_loaded",
]

MAX_REACTION_NEWTON = 30
_FD = 1e-7
_CONVERGED = 1e-12


def reaction_coupling(
    system, k: Kin, lam: np.ndarray, jac: np.ndarray | None = None
) -> np.ndarray | None:
    """dQ/dlam (nq, m) at state `k` and multipliers `lam` (`jac`: phi_q at k, if known),
    or None when no active element depends on the reactions. Elements give it through
    `reaction_jacobian(view, out)`; forward differences over the rows they read are the
    fallback (and the test oracle)."""
    stiffening = system.stiffening_coupling(k, lam) if system.nz else None
    users = [e for e in system.elements if e.active and getattr(e, "uses_reactions", False)]
    if not users:
        return stiffening
    view = system.view(k, lam, jac)
    space = view.system  # the elements' own (3-D for a planar system: mechlib.system.planar)
    out = np.zeros((space.nq, len(lam)))
    differenced = []
    for element in users:
        if hasattr(element, "reaction_jacobian"):
            element.reaction_jacobian(view, out)
        else:
            differenced.append(element)
    out = system.reaction_coupling(out, k)
    if differenced:
        out += differenced_coupling(system, k, lam, differenced, jac)
    return out if stiffening is None else out + stiffening


def differenced_coupling(
    system, k: Kin, lam: np.ndarray, users: list, jac: np.ndarray | None = None
) -> np.ndarray:
    """dQ/dlam (nq, m) of the elements `users` by forward differences over the
    multipliers of their joints' rows."""
    others = {id(e) for e in system.elements if e not in users}
    base = system.forces(k, lam=lam, skip=others, jac=jac)
    out = np.zeros((system.nq, len(lam)))
    rows = np.concatenate([system.joint_force_rows(e.joint)[0] for e in users])
    for j in np.unique(rows):
        bumped = lam.copy()
        bumped[j] += (eps := _FD * max(1.0, abs(lam[j])))
        out[:, j] = (system.forces(k, lam=bumped, skip=others, jac=jac) - base) / eps
    return out


def solve_reaction_loaded(
    system,
    k: Kin,
    matrix: np.ndarray | None,
    rhs: Callable[[np.ndarray | None], np.ndarray],
    lam_at: slice,
    *,
    lu=None,
    lam_guess: np.ndarray | None = None,
    jac: np.ndarray | None = None,
) -> np.ndarray | None:
    """x with `matrix @ x = rhs(x[lam_at])`, where rows :nq of rhs hold Q(lam) (N) and the
    rest does not depend on lam. Without reaction-dependent loads one linear solve (with
    `lu`, the factors of `matrix`, when given); else Newton from the solution for
    `lam_guess` (default: the reactions of the loads without their lam-dependent part),
    with -dQ/dlam beside the multipliers' columns (`jac`: phi_q at k, if known). None
    when a matrix is singular. `matrix` may be None when `lu` is given and no load
    depends on the reactions."""
    if lu is None:
        assert matrix is not None, "a matrix to factor"
        lu = factor(matrix)
    if lu is None:
        return None
    x = solve_factored(lu, rhs(lam_guess))
    if not system.reaction_dependent:
        return x
    assert matrix is not None, "the reactions' Newton iteration needs the matrix"
    nq = system.nq
    # without elements that read the reactions, only geometric stiffening does: its loads
    # are affine in lam (the coupling does not depend on lam) and one Newton step is exact
    affine = not any(e.active and getattr(e, "uses_reactions", False) for e in system.elements)
    for _ in range(MAX_REACTION_NEWTON):
        lam = x[lam_at]
        coupling = reaction_coupling(system, k, lam, jac)
        if coupling is None:
            return x
        count(jacobian_evaluations=1)
        newton = matrix.copy()
        newton[:nq, lam_at] -= coupling
        lu_n = factor(newton)
        if lu_n is None:
            return None
        dx = solve_factored(lu_n, rhs(lam) - matrix @ x)
        x = x + dx
        if affine or np.abs(dx[lam_at]).max(initial=0.0) <= _CONVERGED * (
            1.0 + np.abs(x[lam_at]).max()
        ):
            break
    return x


def accelerations_and_reactions(
    system,
    k: Kin,
    jac: np.ndarray,
    lu=None,
    *,
    gamma: np.ndarray | None = None,
    lam_guess: np.ndarray | None = None,
) -> np.ndarray | None:
    """[qdd; lam] of [[M, phi_q^T], [phi_q, 0]] [qdd; lam] = [Q(lam); gamma] at state `k`
    (`lu`: factors of that matrix, if known; `gamma`: default the constraints' own), with
    the loads that depend on the reactions solved together with them; None when
    singular."""
    gamma = system.gamma(k) if gamma is None else gamma
    # the matrix is needed to factor it, or for the reactions' Newton iteration
    needed = lu is None or system.reaction_dependent
    matrix = augmented(system.mass(k), jac) if needed else None
    return solve_reaction_loaded(
        system,
        k,
        matrix,
        lambda lam: np.concatenate([system.forces(k, lam=lam, jac=jac), gamma]),
        slice(system.nq, None),
        lu=lu,
        lam_guess=lam_guess,
        jac=jac,
    )
